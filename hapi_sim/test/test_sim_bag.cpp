// make_sim_bag end to end on short, low-resolution runs: determinism of the
// whole file, the topic list with types, counts, stamps (camera stamps 3 ms
// late) and latching, the true extrinsic on /tf_static, the scene and
// calibration YAML, ground-truth odometry twist against its own poses, the
// IMU against the IMU ground truth, the --asl folder written alongside, and
// --realism real: the filter's topics carry the believed calibration, the
// ground truth the true one, CameraInfo the real lens; --imaging-rate: the
// imaging camera's topics, its frame on /tf_static and the surface-motion
// truth, the same numbers as the ASL folder's.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <hapi_msgs/SurfaceMotion.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>

#include "bag_contents.hpp"
#include "hapi_sim/scenario.hpp"

#ifndef MAKE_SIM_BAG
#error "MAKE_SIM_BAG (path of the generator) must be defined by the build"
#endif

using namespace hapi_sim;

namespace {

std::string tmp(const std::string& name) { return "/tmp/hapi_sim_sim_bag_test_" + std::to_string(::getpid()) + "_" + name; }

void generate(const std::string& args) {
  const std::string cmd = std::string(MAKE_SIM_BAG) + " --duration 1 --image-scale 0.25 --blur-samples 4 " + args + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

std::string fileBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

struct BagData : hapi_sim_test::BagTopics {
  std::vector<sensor_msgs::Image> left, right;
  std::vector<geometry_msgs::PoseStamped> gt;
  std::vector<nav_msgs::Odometry> odom, imu_odom;
  std::vector<sensor_msgs::Imu> imu;
  std::vector<tf2_msgs::TFMessage> tf_static;
  std::map<std::string, std::string> text;  // the last std_msgs/String of each such topic
};

BagData readBag(const std::string& path) {
  using hapi_sim_test::readMessages;
  BagData d;
  static_cast<hapi_sim_test::BagTopics&>(d) = hapi_sim_test::readBagTopics(path);
  d.left = readMessages<sensor_msgs::Image>(path, "/stereo/left/image_raw");
  d.right = readMessages<sensor_msgs::Image>(path, "/stereo/right/image_raw");
  d.gt = readMessages<geometry_msgs::PoseStamped>(path, "/ground_truth/pose");
  d.odom = readMessages<nav_msgs::Odometry>(path, "/ground_truth/odometry");
  d.imu_odom = readMessages<nav_msgs::Odometry>(path, "/ground_truth/imu_odometry");
  d.imu = readMessages<sensor_msgs::Imu>(path, "/imu/data");
  d.tf_static = readMessages<tf2_msgs::TFMessage>(path, "/tf_static");
  for (const auto& [topic, type] : d.types)
    if (type == "std_msgs/String") d.text[topic] = readMessages<std_msgs::String>(path, topic).back().data;
  return d;
}

Eigen::Quaterniond quat(const geometry_msgs::Quaternion& q) { return Eigen::Quaterniond(q.w, q.x, q.y, q.z); }
Eigen::Vector3d vec(const geometry_msgs::Point& p) { return {p.x, p.y, p.z}; }
Eigen::Vector3d vec(const geometry_msgs::Vector3& p) { return {p.x, p.y, p.z}; }

class SimBagTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    generate("--scene skin --trajectory handheld --seed 1 --output " + tmp("a.bag") + " --asl " + tmp("asl"));
    generate("--scene skin --trajectory handheld --seed 1 --output " + tmp("a2.bag"));
    generate("--scene skin --trajectory handheld --seed 2 --output " + tmp("b.bag"));
    generate("--scene globe --trajectory subject --seed 1 --output " + tmp("g.bag"));
    generate("--scene skin --trajectory rest --seed 4 --realism real --output " + tmp("r.bag"));
    generate("--scene skin --trajectory measurement --seed 3 --imaging-rate 40 --output " + tmp("m.bag") + " --asl " +
             tmp("masl"));
    skin_ = new BagData(readBag(tmp("a.bag")));
    globe_ = new BagData(readBag(tmp("g.bag")));
  }
  static void TearDownTestSuite() {
    for (const char* f : {"a.bag", "a2.bag", "b.bag", "g.bag", "r.bag", "m.bag"}) std::remove(tmp(f).c_str());
    std::filesystem::remove_all(tmp("asl"));
    std::filesystem::remove_all(tmp("masl"));
    delete skin_;
    delete globe_;
  }
  static BagData *skin_, *globe_;
};
BagData* SimBagTest::skin_ = nullptr;
BagData* SimBagTest::globe_ = nullptr;

}  // namespace

TEST_F(SimBagTest, SameSeedSameBytesOtherSeedDiffers) {
  const std::string a = fileBytes(tmp("a.bag")), a2 = fileBytes(tmp("a2.bag")), b = fileBytes(tmp("b.bag"));
  EXPECT_GT(a.size(), 100000u);
  EXPECT_EQ(a, a2);
  EXPECT_NE(a, b);
}

TEST_F(SimBagTest, TopicsTypesCountsStampsAndLatching) {
  for (const BagData* d : {skin_, globe_}) {
    std::map<std::string, std::string> want = {
        {"/stereo/left/image_raw", "sensor_msgs/Image"},        {"/stereo/right/image_raw", "sensor_msgs/Image"},
        {"/stereo/left/camera_info", "sensor_msgs/CameraInfo"},  {"/stereo/right/camera_info", "sensor_msgs/CameraInfo"},
        {"/tf", "tf2_msgs/TFMessage"},                           {"/tf_static", "tf2_msgs/TFMessage"},
        {"/ground_truth/pose", "geometry_msgs/PoseStamped"},     {"/imu/data", "sensor_msgs/Imu"},
        {"/ground_truth/odometry", "nav_msgs/Odometry"},         {"/ground_truth/imu_odometry", "nav_msgs/Odometry"},
        {"/ground_truth/scene", "std_msgs/String"},              {"/ground_truth/calibration", "std_msgs/String"}};
    if (d == globe_) want["/globe/info"] = "std_msgs/String";
    EXPECT_EQ(d->types, want);
    for (const char* t : {"/stereo/left/image_raw", "/stereo/right/image_raw", "/stereo/left/camera_info",
                          "/stereo/right/camera_info", "/tf", "/ground_truth/pose"})
      EXPECT_EQ(d->counts.at(t), 10) << t;
    for (const char* t : {"/imu/data", "/ground_truth/odometry", "/ground_truth/imu_odometry"})
      EXPECT_EQ(d->counts.at(t), 200) << t;
    for (const char* t : {"/tf_static", "/ground_truth/scene", "/ground_truth/calibration"}) {
      EXPECT_EQ(d->counts.at(t), 1) << t;
      EXPECT_TRUE(d->latched.at(t)) << t;
    }
    const ros::Time t0(1000000000, 0);
    for (int k = 0; k < 10; ++k) {
      EXPECT_EQ(d->left[k].header.stamp, t0 + ros::Duration(0, 100000000 * k + 3000000));  // 3 ms late
      EXPECT_EQ(d->right[k].header.stamp, d->left[k].header.stamp);
      EXPECT_EQ(d->gt[k].header.stamp, t0 + ros::Duration(0, 100000000 * k));             // true time
      EXPECT_EQ(d->left[k].width, 160u);
      EXPECT_EQ(d->left[k].header.frame_id, "stereo_left_optical_frame");
    }
    for (int i = 0; i < 200; ++i) {
      EXPECT_EQ(d->imu[i].header.stamp, t0 + ros::Duration(0, 5000000 * i));
      EXPECT_EQ(d->imu[i].header.frame_id, "imu_link");
      EXPECT_GT(d->imu[i].angular_velocity_covariance[0], 0.0);
      EXPECT_EQ(d->odom[i].header.frame_id, "world");
      EXPECT_EQ(d->odom[i].child_frame_id, "ground_truth/stereo_left_optical_frame");
      EXPECT_EQ(d->imu_odom[i].header.frame_id, "inertial");
    }
  }
  EXPECT_EQ(globe_->counts.at("/globe/info"), 1);
  EXPECT_EQ(globe_->text.at("/globe/info").rfind("radius: 0.2\ncentre: [0, 0, 0]\nframe_id: world\nseed: 1\ntexture: \"", 0), 0u);
  EXPECT_TRUE(globe_->latched.at("/globe/info"));
}

TEST_F(SimBagTest, ExtrinsicSceneAndCalibrationYaml) {
  const CameraImuCalibration cal = CameraImuCalibration::makeDefault();
  ASSERT_EQ(skin_->tf_static.size(), 1u);
  bool found = false;
  for (const auto& t : skin_->tf_static[0].transforms)
    if (t.child_frame_id == "imu_link") {
      found = true;
      EXPECT_EQ(t.header.frame_id, "stereo_left_optical_frame");
      EXPECT_LT((vec(t.transform.translation) - cal.T_cam_imu.p).norm(), 1e-15);
      EXPECT_LT(quat(t.transform.rotation).angularDistance(cal.T_cam_imu.q), 1e-12);
      EXPECT_GT(cal.T_cam_imu.p.norm(), 0.02);  // a real lever arm and rotation
      EXPECT_GT(cal.T_cam_imu.q.angularDistance(Eigen::Quaterniond::Identity()), 1.0);
    }
  EXPECT_TRUE(found);
  EXPECT_EQ(skin_->text.at("/ground_truth/scene"), makeSkinScene()->yaml());
  EXPECT_EQ(globe_->text.at("/ground_truth/scene").rfind("name: globe\nsurfaces:\n  - {type: sphere, centre: [0, 0, 0], radius: 0.2}", 0), 0u);
  const std::string& c = skin_->text.at("/ground_truth/calibration");
  EXPECT_NE(c.find("time_offset_s: -0.003\n"), std::string::npos);
  EXPECT_NE(c.find("T_cam_imu: ["), std::string::npos);
}

TEST_F(SimBagTest, RealismRealTellsTheFilterTheBelievedCalibration) {
  ScenarioConfig cfg;
  cfg.scene = SceneKind::Skin;
  cfg.trajectory = TrajectoryKind::Rest;
  cfg.seed = 4;
  cfg.duration = 1;
  cfg.image_scale = 0.25;
  cfg.realism = Realism::Real;
  const Scenario sc(cfg);
  const BagData real = readBag(tmp("r.bag"));
  ASSERT_EQ(real.tf_static.size(), 1u);
  const CameraImuCalibration &told = sc.believedCalibration(), &truth = sc.calibration();
  bool found = false;
  for (const auto& t : real.tf_static[0].transforms)
    if (t.child_frame_id == "imu_link") {
      found = true;
      EXPECT_LT((vec(t.transform.translation) - told.T_cam_imu.p).norm(), 1e-15);
      EXPECT_LT(quat(t.transform.rotation).angularDistance(told.T_cam_imu.q), 1e-12);
      EXPECT_NEAR(quat(t.transform.rotation).angularDistance(truth.T_cam_imu.q), sc.realism().calibration.rotation_rad,
                  1e-9);
    }
  EXPECT_TRUE(found);
  EXPECT_EQ(real.text.at("/calibration"), sc.believedCalibrationYaml());
  EXPECT_EQ(real.text.at("/ground_truth/calibration"), sc.calibrationYaml());
  EXPECT_NE(real.text.at("/calibration"), real.text.at("/ground_truth/calibration"));
  EXPECT_TRUE(real.latched.at("/calibration"));
  EXPECT_EQ(skin_->types.count("/calibration"), 0u);  // the ideal bag keeps its historic topics
  const auto info = hapi_sim_test::readMessages<sensor_msgs::CameraInfo>(tmp("r.bag"), "/stereo/left/camera_info");
  ASSERT_FALSE(info.empty());
  EXPECT_EQ(info[0].distortion_model, "plumb_bob");
  ASSERT_EQ(info[0].D.size(), 5u);
  EXPECT_EQ(info[0].D[0], sc.realism().left_lens.k1);
  // Camera stamps follow the true offset.
  ASSERT_FALSE(real.left.empty());
  EXPECT_EQ(real.left[1].header.stamp.toNSec() - real.left[0].header.stamp.toNSec(), 100000000u);
  EXPECT_EQ(static_cast<int64_t>(real.left[0].header.stamp.toNSec()), kSimEpochNs - truth.time_offset_ns);
}

// REP-105 twist in the child frame, checked against central differences of
// the odometry's own poses (both the camera in world and the IMU in inertial).
TEST_F(SimBagTest, OdometryTwistMatchesItsPoses) {
  for (const BagData* d : {skin_, globe_})
    for (const auto* odom : {&d->odom, &d->imu_odom})
      for (size_t i = 1; i + 1 < odom->size(); ++i) {
        const auto &a = (*odom)[i - 1].pose.pose, &m = (*odom)[i].pose.pose, &b = (*odom)[i + 1].pose.pose;
        const double dt = 0.01;
        const Eigen::Quaterniond q = quat(m.orientation);
        const Eigen::Vector3d v = q.conjugate() * (vec(b.position) - vec(a.position)) / dt;
        const Eigen::AngleAxisd aa(quat(a.orientation).conjugate() * quat(b.orientation));
        const Eigen::Vector3d w = aa.axis() * aa.angle() / dt;
        EXPECT_LT((v - vec((*odom)[i].twist.twist.linear)).norm(), 5e-3) << i;
        EXPECT_LT((w - vec((*odom)[i].twist.twist.angular)).norm(), 2e-2) << i;
      }
}

// Gyro = IMU angular rate; accelerometer = R^T (a - g) of the IMU ground truth.
TEST_F(SimBagTest, ImuAgreesWithTheImuGroundTruth) {
  const BagData& d = *globe_;  // subject motion: the IMU truth differs from the camera-in-scene truth
  for (size_t i = 1; i + 1 < d.imu.size(); ++i) {
    const Eigen::Quaterniond q = quat(d.imu_odom[i].pose.pose.orientation);
    const Eigen::Vector3d w = vec(d.imu_odom[i].twist.twist.angular);
    EXPECT_LT((vec(d.imu[i].angular_velocity) - w).norm(), 0.03) << i;  // turn-on bias + noise
    auto v_world = [&](size_t j) {
      return Eigen::Vector3d(quat(d.imu_odom[j].pose.pose.orientation) * vec(d.imu_odom[j].twist.twist.linear));
    };
    const Eigen::Vector3d a = (v_world(i + 1) - v_world(i - 1)) / 0.01;
    const Eigen::Vector3d f = q.conjugate() * (a + Eigen::Vector3d(0, 0, kGravity));
    EXPECT_LT((vec(d.imu[i].linear_acceleration) - f).norm(), 0.3) << i;
  }
}

TEST_F(SimBagTest, AslFolderWrittenAlongside) {
  const std::string m = tmp("asl") + "/mav0/";
  int pngs = 0;
  for (const auto& e : std::filesystem::directory_iterator(m + "cam0/data")) pngs += e.path().extension() == ".png";
  EXPECT_EQ(pngs, 10);
  std::ifstream f(m + "imu0/data.csv");
  int rows = 0;
  for (std::string l; std::getline(f, l);) ++rows;
  EXPECT_EQ(rows, 201);
}

// The imaging camera (the left camera at 40 Hz) and the truth at its pixel:
// topics, counts, frames and stamps (camera clock for the images, true clock
// for the truth), the identity extrinsic, CameraInfo = the left camera's,
// and the truth's numbers = the scenario's = the ASL folder's.
TEST_F(SimBagTest, ImagingCameraAndSurfaceMotionTruth) {
  const std::string bag = tmp("m.bag");
  const BagData d = readBag(bag);
  for (const auto& [topic, type] : skin_->types) EXPECT_EQ(d.types.at(topic), type) << topic;
  EXPECT_EQ(d.types.at("/imaging/image_raw"), "sensor_msgs/Image");
  EXPECT_EQ(d.types.at("/imaging/camera_info"), "sensor_msgs/CameraInfo");
  EXPECT_EQ(d.types.at("/ground_truth/surface_motion"), "hapi_msgs/SurfaceMotion");
  EXPECT_EQ(d.types.size(), skin_->types.size() + 3);
  EXPECT_EQ(d.counts.at("/imaging/image_raw"), 40);
  EXPECT_EQ(d.counts.at("/imaging/camera_info"), 40);
  EXPECT_EQ(d.counts.at("/ground_truth/surface_motion"), 200);
  const auto images = hapi_sim_test::readMessages<sensor_msgs::Image>(bag, "/imaging/image_raw");
  const auto infos = hapi_sim_test::readMessages<sensor_msgs::CameraInfo>(bag, "/imaging/camera_info");
  const auto left_info = hapi_sim_test::readMessages<sensor_msgs::CameraInfo>(bag, "/stereo/left/camera_info");
  const ros::Time t0(1000000000, 0);
  for (int j = 0; j < 40; ++j) {
    EXPECT_EQ(images[j].header.stamp, t0 + ros::Duration(0, 25000000 * j + 3000000));  // camera clock
    EXPECT_EQ(images[j].header.frame_id, "imaging_optical_frame");
    EXPECT_EQ(images[j].header.seq, static_cast<uint32_t>(j));
    EXPECT_EQ(images[j].encoding, "mono8");
    EXPECT_EQ(images[j].width, 160u);
    EXPECT_EQ(infos[j].header, images[j].header);
    EXPECT_EQ(infos[j].K, left_info[0].K);
    EXPECT_EQ(infos[j].D, left_info[0].D);
  }
  // Every 4th imaging frame is exposed with a stereo frame (other noise).
  EXPECT_EQ(images[4].header.stamp, d.left[1].header.stamp);
  bool found = false;
  for (const auto& t : d.tf_static.at(0).transforms)
    if (t.child_frame_id == "imaging_optical_frame") {
      found = true;
      EXPECT_EQ(t.header.frame_id, "stereo_left_optical_frame");
      EXPECT_EQ(vec(t.transform.translation).norm(), 0.0);
      EXPECT_EQ(quat(t.transform.rotation).angularDistance(Eigen::Quaterniond::Identity()), 0.0);
    }
  EXPECT_TRUE(found);
  // The truth, against the scenario and the ASL folder written by the same run.
  ScenarioConfig cfg;
  cfg.trajectory = TrajectoryKind::Measurement;
  cfg.seed = 3;
  cfg.duration = 1;
  cfg.image_scale = 0.25;
  cfg.blur_samples = 4;
  cfg.imaging_rate = 40;
  const Scenario sc(cfg);
  const auto truth = hapi_sim_test::readMessages<hapi_msgs::SurfaceMotion>(bag, "/ground_truth/surface_motion");
  std::ifstream csv(tmp("masl") + "/mav0/surface_motion_groundtruth0/data.csv");
  std::string line;
  std::getline(csv, line);  // the header
  for (int i = 0; i < 200; ++i) {
    const hapi_msgs::SurfaceMotion& m = truth[i];
    EXPECT_EQ(m.header.stamp, t0 + ros::Duration(0, 5000000 * i));  // true clock
    EXPECT_EQ(m.header.frame_id, "imaging_optical_frame");
    EXPECT_EQ(m.status, hapi_msgs::SurfaceMotion::STATUS_OK);
    EXPECT_EQ(m.u, 79.5);
    EXPECT_EQ(m.v, 59.5);
    EXPECT_EQ(m.frame_rate, 40.0);
    const SurfaceMotionTruth want = sc.surfaceMotion(sc.imuTimeNs(i) * 1e-9);
    EXPECT_EQ(vec(m.point), want.point);
    EXPECT_EQ(vec(m.normal), want.normal);
    EXPECT_EQ(vec(m.surface_velocity), want.surface_velocity);
    EXPECT_EQ(m.speed, want.speed);
    EXPECT_EQ(m.normal_velocity, want.normal_velocity);
    EXPECT_EQ(m.image_velocity[0], want.image_velocity.x());
    EXPECT_EQ(m.image_velocity[1], want.image_velocity.y());
    for (double c : m.surface_velocity_covariance) EXPECT_EQ(c, 0.0);
    ASSERT_TRUE(std::getline(csv, line));
    std::stringstream row(line);
    std::vector<double> v;
    for (std::string cell; std::getline(row, cell, ',');) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 15u);
    const double bag_numbers[] = {m.point.x, m.point.y, m.point.z, m.normal.x, m.normal.y, m.normal.z,
                                  m.surface_velocity.x, m.surface_velocity.y, m.surface_velocity.z, m.speed,
                                  m.normal_velocity, m.image_velocity[0], m.image_velocity[1],
                                  static_cast<double>(m.status)};
    for (int k = 0; k < 14; ++k) EXPECT_EQ(v[1 + k], bag_numbers[k]) << "row " << i << " column " << k + 1;
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
