// asl_to_bag on the tiny ASL recording: the topics, frames and messages of
// the simulator's bags, the calibration and ground-truth conversions, the
// window and rate options, and byte-identical output for the same input.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "asl_fixture.hpp"
#include "hapi_dataset/rig_frames.hpp"

namespace {

using hapi_dataset_test::TinyAsl;

int run(const std::string& args) {
  return std::system((std::string(ASL_TO_BAG) + " " + args + " 2>/dev/null").c_str());
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

std::map<std::string, int> topicCounts(rosbag::Bag& bag) {
  std::map<std::string, int> n;
  rosbag::View view(bag);
  for (const rosbag::MessageInstance& m : view) ++n[m.getTopic()];
  return n;
}

Eigen::Isometry3d toIsometry(const geometry_msgs::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z)
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

class AslToBag : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = hapi_dataset_test::makeTempDir("bag");
    hapi_dataset_test::writeTinyAsl(dir_ + "/rec", true, scene_);
  }
  std::string dir_;
  const std::string scene_ = "name: box\nsurfaces:\n  - {type: plane, point: [0, 0, 0], normal: [0, 0, 1], "
                             "half_extent: 5}\n";
};

}  // namespace

TEST_F(AslToBag, TopicsFramesAndMessages) {
  const std::string out = dir_ + "/a.bag";
  ASSERT_EQ(run("--asl " + dir_ + "/rec --output " + out), 0);
  rosbag::Bag bag(out, rosbag::bagmode::Read);
  const auto n = topicCounts(bag);
  const int frames = TinyAsl::kFrames;
  // Without --duration every IMU and truth row from the first frame on (the
  // one 5 ms before it is outside).
  const int in_window = TinyAsl::kImuRows - 1;
  const std::map<std::string, int> expected = {
      {"/stereo/left/image_raw", frames}, {"/stereo/right/image_raw", frames},
      {"/stereo/left/camera_info", frames}, {"/stereo/right/camera_info", frames},
      {"/imu/data", in_window}, {"/ground_truth/pose", in_window}, {"/ground_truth/odometry", in_window},
      {"/tf", in_window}, {"/tf_static", 1}, {"/ground_truth/scene", 1}};
  EXPECT_EQ(n, expected);

  rosbag::View view(bag);
  int k = 0;
  int64_t previous = 0;
  for (const rosbag::MessageInstance& m : view) {
    EXPECT_GE(m.getTime().toNSec(), previous) << "bag not in time order";
    previous = m.getTime().toNSec();
    if (m.getTopic() == "/tf_static") {
      const auto st = m.instantiate<tf2_msgs::TFMessage>();
      ASSERT_EQ(st->transforms.size(), 2u);
      EXPECT_EQ(st->transforms[0].header.frame_id, "stereo_left_optical_frame");
      EXPECT_EQ(st->transforms[0].child_frame_id, "stereo_right_optical_frame");
      EXPECT_NEAR(st->transforms[0].transform.translation.x, 0.11, 1e-9);
      EXPECT_EQ(st->transforms[1].child_frame_id, "imu_link");
      // imu_link in the left camera = T_BS(cam0)^-1 (EuRoC: IMU = body).
      const Eigen::Isometry3d T_ci = TinyAsl::T_BS_cam0().inverse();
      EXPECT_NEAR(st->transforms[1].transform.translation.y, T_ci.translation().y(), 1e-9);
      EXPECT_NEAR(st->transforms[1].transform.translation.z, T_ci.translation().z(), 1e-9);
      const auto& q = st->transforms[1].transform.rotation;
      EXPECT_TRUE(Eigen::Quaterniond(q.w, q.x, q.y, q.z).toRotationMatrix().isApprox(T_ci.linear(), 1e-9));
      const auto header = m.getConnectionHeader();
      EXPECT_EQ(header->at("latching"), "1");
    } else if (m.getTopic() == "/ground_truth/scene") {
      EXPECT_EQ(m.instantiate<std_msgs::String>()->data, scene_);
      EXPECT_EQ(m.getConnectionHeader()->at("latching"), "1");
    } else if (m.getTopic() == "/stereo/right/camera_info") {
      const auto ci = m.instantiate<sensor_msgs::CameraInfo>();
      EXPECT_EQ(ci->header.frame_id, "stereo_right_optical_frame");
      EXPECT_EQ(ci->distortion_model, "plumb_bob");
      EXPECT_EQ(ci->D.size(), 5u);
      EXPECT_DOUBLE_EQ(ci->K[0], 41.0);
      EXPECT_NEAR(ci->P[3], -ci->P[0] * 0.11, 1e-9);
      EXPECT_EQ(ci->width, static_cast<uint32_t>(TinyAsl::kWidth));
    } else if (m.getTopic() == "/stereo/left/image_raw") {
      const auto img = m.instantiate<sensor_msgs::Image>();
      EXPECT_EQ(img->encoding, "mono8");
      EXPECT_EQ(img->header.frame_id, "stereo_left_optical_frame");
      EXPECT_EQ(img->header.stamp.toNSec(), static_cast<uint64_t>(TinyAsl::kT0 + k * TinyAsl::kFramePeriod));
      EXPECT_EQ(img->header.seq, static_cast<uint32_t>(k));
      ASSERT_EQ(img->data.size(), static_cast<size_t>(TinyAsl::kWidth * TinyAsl::kHeight));
      EXPECT_EQ(img->data[9 * img->step + 4], TinyAsl::pixel(k, 0, 4, 9));
      ++k;
    } else if (m.getTopic() == "/imu/data") {
      const auto imu = m.instantiate<sensor_msgs::Imu>();
      EXPECT_EQ(imu->header.frame_id, "imu_link");
      EXPECT_DOUBLE_EQ(imu->angular_velocity.z, TinyAsl::kYawRate);
      EXPECT_EQ(imu->orientation_covariance[0], -1.0);
      EXPECT_NEAR(imu->angular_velocity_covariance[0], 1.6968e-04 * 1.6968e-04 * 200.0, 1e-15);
    } else if (m.getTopic() == "/ground_truth/pose") {
      const auto gt = m.instantiate<geometry_msgs::PoseStamped>();
      EXPECT_EQ(gt->header.frame_id, "world");
      const Eigen::Isometry3d expected_pose =
          TinyAsl::bodyPose(static_cast<int64_t>(gt->header.stamp.toNSec())) * TinyAsl::T_BS_cam0();
      EXPECT_TRUE(toIsometry(gt->pose).isApprox(expected_pose, 1e-9));
    } else if (m.getTopic() == "/ground_truth/odometry") {
      const auto od = m.instantiate<nav_msgs::Odometry>();
      EXPECT_EQ(od->child_frame_id, "ground_truth/stereo_left_optical_frame");
      const Eigen::Vector3d w(od->twist.twist.angular.x, od->twist.twist.angular.y, od->twist.twist.angular.z);
      EXPECT_NEAR(w.norm(), TinyAsl::kYawRate, 1e-6);
    } else if (m.getTopic() == "/tf") {
      const auto tf = m.instantiate<tf2_msgs::TFMessage>();
      ASSERT_EQ(tf->transforms.size(), 1u);
      EXPECT_EQ(tf->transforms[0].header.frame_id, "world");
      EXPECT_EQ(tf->transforms[0].child_frame_id, "ground_truth/stereo_left_optical_frame");
    }
  }
  EXPECT_EQ(k, frames);
}

TEST_F(AslToBag, WindowRateDivisorAndDeterminism) {
  const std::string a = dir_ + "/a.bag", b = dir_ + "/b.bag";
  const std::string args = "--asl " + dir_ + "/rec/mav0 --start 0.05 --duration 0.2 --rate-divisor 2 --output ";
  ASSERT_EQ(run(args + a), 0);
  ASSERT_EQ(run(args + b), 0);
  EXPECT_EQ(slurp(a), slurp(b)) << "same input and options must give the same bytes";
  rosbag::Bag bag(a, rosbag::bagmode::Read);
  const auto n = topicCounts(bag);
  // Frames 1..5 are inside [0.05, 0.25] s; every second one: 1, 3, 5.
  EXPECT_EQ(n.at("/stereo/left/image_raw"), 3);
  EXPECT_EQ(n.at("/imu/data"), 41);  // 0.2 s at 200 Hz, both ends included
  rosbag::View view(bag, rosbag::TopicQuery("/stereo/left/image_raw"));
  EXPECT_EQ(view.begin()->instantiate<sensor_msgs::Image>()->header.stamp.toNSec(),
            static_cast<uint64_t>(TinyAsl::kT0 + TinyAsl::kFramePeriod));
}

TEST_F(AslToBag, WithoutTruthAndBadArguments) {
  const std::string plain = dir_ + "/plain";
  hapi_dataset_test::writeTinyAsl(plain, false);
  ASSERT_EQ(run("--asl " + plain + " --output " + dir_ + "/p.bag"), 0);
  rosbag::Bag bag(dir_ + "/p.bag", rosbag::bagmode::Read);
  const auto n = topicCounts(bag);
  EXPECT_EQ(n.count("/ground_truth/pose"), 0u);
  EXPECT_EQ(n.count("/ground_truth/scene"), 0u);
  EXPECT_EQ(n.at("/stereo/right/image_raw"), TinyAsl::kFrames);

  EXPECT_NE(run("--asl " + dir_ + "/nothing --output " + dir_ + "/x.bag"), 0);
  EXPECT_NE(run("--asl " + plain), 0);
  EXPECT_NE(run("--asl " + plain + " --output " + dir_ + "/x.bag --rate-divisor 0"), 0);
  EXPECT_NE(run("--asl " + plain + " --output " + dir_ + "/x.bag --start 100"), 0);
}
