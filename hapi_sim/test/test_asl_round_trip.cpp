// Round trip through the standard ASL layout: hapi_sim's writer puts a short
// simulated scenario on disk, hapi_dataset's reader reads it back, and every
// number the system uses must survive: frame and IMU stamps (images on the
// camera clock), the IMU readings, the body ground truth, the camera-IMU
// extrinsic, the noise densities, the stereo baseline after rectification and
// the scene description.
#include "hapi_dataset/asl_recording.hpp"
#include "hapi_dataset/stereo_calibration.hpp"
#include "hapi_sim/asl_writer.hpp"
#include "hapi_sim/scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

TEST(SimulatorAslRoundTrip, TheReaderGetsBackWhatTheSimulatorWrote) {
  hapi_sim::ScenarioConfig cfg;
  cfg.scene = hapi_sim::SceneKind::Skin;
  cfg.trajectory = hapi_sim::TrajectoryKind::Handheld;
  cfg.seed = 3;
  cfg.duration = 0.5;
  cfg.image_scale = 0.25;  // 160 x 120: the images only need to exist
  cfg.blur_samples = 1;
  ASSERT_EQ(cfg.validate(), "");
  const hapi_sim::Scenario scenario(cfg);
  const std::string root =
      (std::filesystem::temp_directory_path() / ("hapi_dataset_sim_round_trip_" + std::to_string(::getpid())))
          .string();
  std::filesystem::remove_all(root);
  hapi_sim::writeAslDataset(scenario, root);

  const hapi_dataset::AslRecording rec = hapi_dataset::readAslRecording(root);
  // Frames: every one, stamped on the camera clock.
  ASSERT_EQ(static_cast<int64_t>(rec.frames.size()), scenario.frameCount());
  for (int64_t k = 0; k < scenario.frameCount(); ++k)
    EXPECT_EQ(rec.frames[k].stamp_ns, hapi_sim::kSimEpochNs + scenario.frameStampNs(k)) << k;
  // IMU: the readings the simulator produced, in order, on the IMU clock.
  std::vector<hapi_sim::ImuReading> written;
  scenario.play([&](int64_t, const hapi_sim::ImuReading& r) { written.push_back(r); },
                [](int64_t, const cv::Mat&, const cv::Mat&) {});
  ASSERT_EQ(rec.imu.size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    EXPECT_EQ(rec.imu[i].stamp_ns, hapi_sim::kSimEpochNs + scenario.imuTimeNs(static_cast<int64_t>(i)));
    EXPECT_LT((rec.imu[i].angular_velocity - written[i].gyro).norm(), 1e-9) << i;
    EXPECT_LT((rec.imu[i].linear_acceleration - written[i].accel).norm(), 1e-9) << i;
  }
  // Ground truth: the IMU (body) in the inertial frame.
  ASSERT_FALSE(rec.ground_truth.empty());
  for (std::size_t i = 0; i < rec.ground_truth.size(); i += 17) {
    const double t = (rec.ground_truth[i].stamp_ns - hapi_sim::kSimEpochNs) * 1e-9;
    const hapi_sim::MotionSample b = scenario.imuInInertial(t);
    EXPECT_LT((rec.ground_truth[i].T_W_B.translation() - b.p).norm(), 1e-9) << i;
    EXPECT_LT(Eigen::Quaterniond(rec.ground_truth[i].T_W_B.linear()).angularDistance(b.q), 1e-9) << i;
    EXPECT_LT((rec.ground_truth[i].v_W - b.v).norm(), 1e-9) << i;
  }
  // Extrinsic: cam0's T_BS is the camera in the IMU (body) frame, the inverse of Kalibr's T_cam_imu.
  const hapi_sim::Pose& T_ci = scenario.calibration().T_cam_imu;
  const Eigen::Isometry3d T_cam_imu = Eigen::Translation3d(T_ci.p) * T_ci.q;
  EXPECT_LT((rec.cam0.T_BS.matrix() - T_cam_imu.inverse().matrix()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(rec.imu0.gyroscope_noise_density, scenario.imuSpec().gyro_noise_density, 1e-12);
  EXPECT_NEAR(rec.imu0.accelerometer_noise_density, scenario.imuSpec().accel_noise_density, 1e-12);
  // Stereo: the rectified pair keeps the rig's baseline (Tx = -f b).
  const hapi_dataset::StereoCalibration cal = hapi_dataset::rectifyStereo(rec.cam0, rec.cam1);
  EXPECT_NEAR(cal.baseline, scenario.rig().baseline, 1e-9);
  EXPECT_NEAR(cal.right.P[3], -cal.right.P[0] * scenario.rig().baseline, 1e-6);
  EXPECT_NE(rec.scene_yaml.find("surfaces"), std::string::npos);
  std::filesystem::remove_all(root);
}

}  // namespace
