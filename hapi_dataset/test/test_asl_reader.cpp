// ASL reader round trip (asl_recording.hpp) on the tiny recording the test
// writes, and the frame changes of rig_frames.hpp.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <fstream>

#include "asl_fixture.hpp"
#include "hapi_dataset/asl_recording.hpp"
#include "hapi_dataset/rig_frames.hpp"

namespace {

using hapi_dataset_test::TinyAsl;

}  // namespace

TEST(AslRecording, TinyFolderRoundTrip) {
  const std::string root = hapi_dataset_test::makeTempDir("reader");
  const std::string scene = "name: test\nsurfaces:\n  - {type: sphere, centre: [0, 0, 0], radius: 1.0}\n";
  hapi_dataset_test::writeTinyAsl(root, true, scene);

  // The parent folder and mav0 itself are both accepted.
  const hapi_dataset::AslRecording rec = hapi_dataset::readAslRecording(root);
  EXPECT_EQ(rec.mav0, root + "/mav0");
  EXPECT_EQ(hapi_dataset::readAslRecording(root + "/mav0").frames.size(), rec.frames.size());

  EXPECT_TRUE(rec.cam0.T_BS.isApprox(TinyAsl::T_BS_cam0(), 1e-12));
  EXPECT_TRUE(rec.cam1.T_BS.isApprox(TinyAsl::T_BS_cam1(), 1e-12));
  EXPECT_EQ(rec.cam0.width, TinyAsl::kWidth);
  EXPECT_DOUBLE_EQ(rec.cam1.fu, 41.0);

  // The unpaired right image is dropped; the pairs keep their order.
  ASSERT_EQ(rec.frames.size(), static_cast<size_t>(TinyAsl::kFrames));
  for (int k = 0; k < TinyAsl::kFrames; ++k) {
    const int64_t t = TinyAsl::kT0 + k * TinyAsl::kFramePeriod;
    EXPECT_EQ(rec.frames[k].stamp_ns, t);
    EXPECT_EQ(rec.frames[k].left_png, root + "/mav0/cam0/data/" + std::to_string(t) + ".png");
    const cv::Mat img = cv::imread(rec.frames[k].right_png, cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty());
    EXPECT_EQ(img.at<uint8_t>(7, 5), TinyAsl::pixel(k, 1, 5, 7));
  }

  ASSERT_EQ(rec.imu.size(), static_cast<size_t>(TinyAsl::kImuRows));
  EXPECT_EQ(rec.imu[1].stamp_ns, TinyAsl::kT0);
  EXPECT_DOUBLE_EQ(rec.imu[3].angular_velocity.z(), TinyAsl::kYawRate);
  EXPECT_DOUBLE_EQ(rec.imu[3].linear_acceleration.x(), 0.03);
  EXPECT_DOUBLE_EQ(rec.imu0.rate_hz, 200.0);

  ASSERT_EQ(rec.ground_truth.size(), static_cast<size_t>(TinyAsl::kImuRows));
  for (const auto& g : rec.ground_truth) {
    EXPECT_TRUE(g.T_W_B.isApprox(TinyAsl::bodyPose(g.stamp_ns), 1e-12));
    EXPECT_DOUBLE_EQ(g.v_W.x(), TinyAsl::kSpeed);
  }
  EXPECT_EQ(rec.scene_yaml, scene);
}

TEST(AslRecording, OptionalPartsAndErrors) {
  const std::string root = hapi_dataset_test::makeTempDir("reader_bad");
  hapi_dataset_test::writeTinyAsl(root, false);
  const hapi_dataset::AslRecording rec = hapi_dataset::readAslRecording(root);
  EXPECT_TRUE(rec.ground_truth.empty());
  EXPECT_TRUE(rec.scene_yaml.empty());

  EXPECT_THROW(hapi_dataset::readAslRecording(root + "/mav0/cam0"), std::runtime_error);
  // A timestamp that goes backwards is an error, named with its line.
  std::ofstream(root + "/mav0/imu0/data.csv", std::ios::app) << "1,0,0,0,0,0,0\n";
  try {
    hapi_dataset::readAslRecording(root);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("imu0/data.csv:64"), std::string::npos) << e.what();
  }
}

TEST(RigFrames, GroundTruthImuExtrinsicAndTwist) {
  const std::string root = hapi_dataset_test::makeTempDir("frames");
  hapi_dataset_test::writeTinyAsl(root, true);
  const hapi_dataset::AslRecording rec = hapi_dataset::readAslRecording(root);

  // T_W_cam = T_W_B T_BS: the camera's origin is the body origin plus the
  // rotated lever arm.
  const auto& g = rec.ground_truth[10];
  const Eigen::Isometry3d T_W_cam = hapi_dataset::cameraInWorld(g.T_W_B, rec.cam0);
  EXPECT_TRUE(T_W_cam.translation().isApprox(
      g.T_W_B.translation() + g.T_W_B.linear() * TinyAsl::T_BS_cam0().translation(), 1e-12));
  EXPECT_TRUE(T_W_cam.linear().isApprox(g.T_W_B.linear() * TinyAsl::T_BS_cam0().linear(), 1e-12));

  // IMU (= body here) in the camera: the inverse of T_BS, rotation and translation.
  const Eigen::Isometry3d T_cam_imu = hapi_dataset::imuInCamera(rec.cam0, rec.imu0);
  EXPECT_TRUE((T_cam_imu * TinyAsl::T_BS_cam0()).isApprox(Eigen::Isometry3d::Identity(), 1e-12));
  EXPECT_GT(T_cam_imu.translation().norm(), 0.05);

  // Body turning at 0.5 rad/s about world z (= body z) while moving at
  // 1 m/s along world x: in the camera frame w = R_BS^T (0, 0, 0.5) and
  // v = R_W_cam^T (v_B + w_W x R_WB t_BS).
  const hapi_dataset::CameraTwist tw = hapi_dataset::cameraTwistAt(rec.ground_truth, 10, rec.cam0);
  const Eigen::Vector3d w_B(0, 0, TinyAsl::kYawRate);
  EXPECT_LT((tw.angular - TinyAsl::T_BS_cam0().linear().transpose() * w_B).norm(), 1e-6);
  const Eigen::Vector3d v_W = Eigen::Vector3d(TinyAsl::kSpeed, 0, 0) +
                              (g.T_W_B.linear() * w_B).cross(g.T_W_B.linear() * TinyAsl::T_BS_cam0().translation());
  EXPECT_LT((tw.linear - T_W_cam.linear().transpose() * v_W).norm(), 1e-6);
  // One-sided at the ends, same constant rate.
  EXPECT_LT((hapi_dataset::cameraTwistAt(rec.ground_truth, 0, rec.cam0).angular - tw.angular).norm(), 1e-6);

  const hapi_dataset::SecNsec s = hapi_dataset::toSecNsec(1403636579763555584LL);
  EXPECT_EQ(s.sec, 1403636579u);
  EXPECT_EQ(s.nsec, 763555584u);
  EXPECT_THROW(hapi_dataset::toSecNsec(-1), std::out_of_range);
}
