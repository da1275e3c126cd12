// The calibration conversion: sensor.yaml parsing and the rectified
// CameraInfo pair (stereo_calibration.hpp), on a synthetic rig with a known
// rotation between the cameras and on EuRoC MH_01's published calibration.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "asl_fixture.hpp"
#include "hapi_dataset/asl_sensor.hpp"
#include "hapi_dataset/stereo_calibration.hpp"

namespace {

using hapi_dataset::CameraInfoData;
using hapi_dataset::CameraSensor;
using hapi_dataset::StereoCalibration;

Eigen::Matrix3d mat3(const std::array<double, 9>& a) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = a[i];
  return m;
}

Eigen::Matrix<double, 3, 4> mat34(const std::array<double, 12>& a) {
  Eigen::Matrix<double, 3, 4> m;
  for (int i = 0; i < 12; ++i) m(i / 4, i % 4) = a[i];
  return m;
}

// What the front end relies on (docs/DESIGN.md "Keypoint undistortion"):
// one rectified focal length, Tx = -f * baseline on the right, zero on the
// left, rotations that make both optical axes parallel with the baseline
// along the rectified x axis, and a 3-D point projecting to the same row.
void expectRectifiedPair(const StereoCalibration& c, double tol_px) {
  const Eigen::Matrix<double, 3, 4> P1 = mat34(c.left.P), P2 = mat34(c.right.P);
  const Eigen::Matrix3d R1 = mat3(c.left.R), R2 = mat3(c.right.R);
  const double f = P1(0, 0);
  EXPECT_GT(f, 0);
  EXPECT_NEAR(P1(1, 1), f, 1e-9);
  EXPECT_NEAR(P2(0, 0), f, 1e-9);
  EXPECT_NEAR(P2(1, 1), f, 1e-9);
  EXPECT_NEAR(P1(0, 3), 0.0, 1e-12);
  EXPECT_NEAR(P2(0, 3), -f * c.baseline, 1e-6 * f);
  EXPECT_NEAR(P2(1, 3), 0.0, 1e-9);
  EXPECT_NEAR(P1(1, 2), P2(1, 2), 1e-9);  // same principal row
  EXPECT_NEAR(P1(0, 2), P2(0, 2), 1e-9);  // zero disparity at infinity
  EXPECT_LT((R1 * R1.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  EXPECT_LT((R2 * R2.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  // Rectified right frame in the rectified left frame: R1 R_lr R2^T = I,
  // and the right camera's centre lies on the rectified +x axis at baseline.
  const Eigen::Matrix3d R_lr = c.T_left_right.linear();
  EXPECT_LT((R1 * R_lr * R2.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  const Eigen::Vector3d b = R1 * c.T_left_right.translation();
  EXPECT_NEAR(b.x(), c.baseline, 1e-12);
  EXPECT_NEAR(b.y(), 0.0, 1e-12);
  EXPECT_NEAR(b.z(), 0.0, 1e-12);
  // A point 3 m ahead of the left camera: same row in both rectified images,
  // disparity f * b / z. P2 projects points of the rectified left frame;
  // the right camera's own rectified frame with its K' gives the same pixel.
  const Eigen::Vector3d X_l(0.3, -0.2, 3.0);
  const Eigen::Vector3d X_r = c.T_left_right.inverse() * X_l;
  const Eigen::Vector3d u_l = P1.leftCols<3>() * (R1 * X_l);
  const Eigen::Vector3d u_r = P2.leftCols<3>() * (R1 * X_l) + P2.col(3);
  const Eigen::Vector3d u_r_own = P2.leftCols<3>() * (R2 * X_r);
  EXPECT_NEAR(u_r.x() / u_r.z(), u_r_own.x() / u_r_own.z(), tol_px);
  EXPECT_NEAR(u_r.y() / u_r.z(), u_r_own.y() / u_r_own.z(), tol_px);
  EXPECT_NEAR(u_l.y() / u_l.z(), u_r.y() / u_r.z(), tol_px);
  EXPECT_NEAR(u_l.x() / u_l.z() - u_r.x() / u_r.z(), f * c.baseline / (R1 * X_l).z(), tol_px);
}

void expectUnchangedIntrinsics(const CameraInfoData& d, const CameraSensor& s) {
  EXPECT_EQ(d.width, s.width);
  EXPECT_EQ(d.height, s.height);
  EXPECT_EQ(d.distortion_model, "plumb_bob");
  ASSERT_EQ(d.D.size(), 5u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(d.D[i], s.distortion[i]);
  EXPECT_EQ(d.D[4], 0.0);
  const std::array<double, 9> K{s.fu, 0, s.cu, 0, s.fv, s.cv, 0, 0, 1};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(d.K[i], K[i]) << i;
}

CameraSensor syntheticCamera(const Eigen::Isometry3d& T_BS, double fu, double cu) {
  CameraSensor c;
  c.T_BS = T_BS;
  c.width = 752;
  c.height = 480;
  c.fu = fu;
  c.fv = fu - 1.0;
  c.cu = cu;
  c.cv = 250.0;
  c.distortion = {-0.28, 0.07, 2e-4, 1.8e-5};
  return c;
}

}  // namespace

TEST(StereoCalibration, SyntheticRigWithKnownRotation) {
  using hapi_dataset_test::TinyAsl;
  const CameraSensor l = syntheticCamera(TinyAsl::T_BS_cam0(), 458.0, 367.0);
  const CameraSensor r = syntheticCamera(TinyAsl::T_BS_cam1(), 457.0, 380.0);
  const StereoCalibration c = hapi_dataset::rectifyStereo(l, r);
  EXPECT_NEAR(c.baseline, 0.11, 1e-12);
  // The relative pose is the one built into the fixture: 1 degree about y.
  const Eigen::AngleAxisd rel(c.T_left_right.linear());
  EXPECT_NEAR(rel.angle(), M_PI / 180.0, 1e-9);
  EXPECT_NEAR(std::abs(rel.axis().y()), 1.0, 1e-9);
  // R1 and R2 differ by that rotation (they make the axes parallel).
  const Eigen::AngleAxisd diff(mat3(c.left.R).transpose() * mat3(c.right.R));
  EXPECT_NEAR(diff.angle(), M_PI / 180.0, 1e-9);
  expectRectifiedPair(c, 1e-6);
  expectUnchangedIntrinsics(c.left, l);
  expectUnchangedIntrinsics(c.right, r);
}

TEST(StereoCalibration, RejectsCoincidentCamerasAndSizeMismatch) {
  const CameraSensor l = syntheticCamera(Eigen::Isometry3d::Identity(), 458.0, 367.0);
  EXPECT_THROW(hapi_dataset::rectifyStereo(l, l), std::invalid_argument);
  CameraSensor r = syntheticCamera(Eigen::Isometry3d(Eigen::Translation3d(0.1, 0, 0)), 458.0, 367.0);
  r.width = 640;
  EXPECT_THROW(hapi_dataset::rectifyStereo(l, r), std::invalid_argument);
}

// EuRoC MH_01 (fixtures/euroc_mh01: the dataset's sensor.yaml files
// verbatim). Reference: the rectification of this pair that ORB-SLAM2 ships
// for EuRoC (cv::stereoRectify of an older OpenCV): f = 435.2046959714599,
// bf = 47.90639384423901 (baseline 0.110078 m) and the two rotations below.
// The rotations and the baseline are pure geometry and must agree closely;
// the rectified focal length comes from OpenCV's search of the valid image
// region for alpha 0, which differs between versions (436.23 px with
// OpenCV 4.6), hence the looser bound on f and no check of the rectified
// principal point.
TEST(StereoCalibration, EurocMh01MatchesThePublishedRectification) {
  const std::string dir = std::string(HAPI_DATASET_FIXTURES) + "/euroc_mh01";
  const CameraSensor l = hapi_dataset::readCameraSensor(dir + "/cam0/sensor.yaml");
  const CameraSensor r = hapi_dataset::readCameraSensor(dir + "/cam1/sensor.yaml");
  EXPECT_EQ(l.width, 752);
  EXPECT_EQ(l.height, 480);
  EXPECT_DOUBLE_EQ(l.fu, 458.654);
  EXPECT_DOUBLE_EQ(l.fv, 457.296);
  EXPECT_DOUBLE_EQ(l.cu, 367.215);
  EXPECT_DOUBLE_EQ(l.cv, 248.375);
  EXPECT_DOUBLE_EQ(l.distortion[0], -0.28340811);
  EXPECT_DOUBLE_EQ(r.distortion[3], -3.55590700e-05);
  EXPECT_DOUBLE_EQ(l.rate_hz, 20.0);
  EXPECT_NEAR(l.T_BS.translation().y(), -0.064676986768, 1e-12);
  EXPECT_NEAR(r.T_BS(0, 1), -0.999755099723, 1e-8);

  const StereoCalibration c = hapi_dataset::rectifyStereo(l, r);
  EXPECT_NEAR(c.baseline, 47.90639384423901 / 435.2046959714599, 1e-6);
  expectRectifiedPair(c, 1e-6);
  expectUnchangedIntrinsics(c.left, l);
  expectUnchangedIntrinsics(c.right, r);
  const Eigen::Matrix3d R1_ref = (Eigen::Matrix3d() << 0.999966347530033, -0.001422739138722922,
                                  0.008079580483432283, 0.001365741834644127, 0.9999741760894847,
                                  0.007055629199258132, -0.008089410156878961, -0.007044357138835809,
                                  0.9999424675829176).finished();
  const Eigen::Matrix3d R2_ref = (Eigen::Matrix3d() << 0.9999633526194376, -0.003625811871560086,
                                  0.007755443660172947, 0.003680398547259526, 0.9999684752771629,
                                  -0.007035845251224894, -0.007729688520722713, 0.007064130529506649,
                                  0.999945173484644).finished();
  EXPECT_LT((mat3(c.left.R) - R1_ref).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((mat3(c.right.R) - R2_ref).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(c.left.P[0], 435.2046959714599, 0.005 * 435.2);
  // alpha 0 keeps only valid pixels: the rectified f is below both raw ones.
  EXPECT_LT(c.left.P[0], std::min(l.fu, r.fu));
}

TEST(AslSensor, ImuSensorAndMalformedFiles) {
  const std::string dir = std::string(HAPI_DATASET_FIXTURES) + "/euroc_mh01";
  const hapi_dataset::ImuSensor imu = hapi_dataset::readImuSensor(dir + "/imu0/sensor.yaml");
  EXPECT_TRUE(imu.T_BS.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_DOUBLE_EQ(imu.rate_hz, 200.0);
  EXPECT_DOUBLE_EQ(imu.gyroscope_noise_density, 1.6968e-04);
  EXPECT_DOUBLE_EQ(imu.accelerometer_random_walk, 3.0e-3);
  // A camera file read as an IMU has a T_BS; an IMU file read as a camera has no model.
  EXPECT_THROW(hapi_dataset::readCameraSensor(dir + "/imu0/sensor.yaml"), std::runtime_error);
  EXPECT_THROW(hapi_dataset::readCameraSensor(dir + "/missing.yaml"), std::runtime_error);
}

// Kalibr's camchain-imucam.yaml (fixtures/kalibr: EuRoC MH_01's calibration
// written in Kalibr's layout): the same rectified pair as the sensor.yaml
// files, the IMU's pose and the time shift; broken files are refused.
TEST(KalibrCamchain, GivesTheSameRigAsTheSensorFilesAndTheImuCalibration) {
  const std::string dir = std::string(HAPI_DATASET_FIXTURES);
  const CameraSensor l = hapi_dataset::readCameraSensor(dir + "/euroc_mh01/cam0/sensor.yaml");
  const CameraSensor r = hapi_dataset::readCameraSensor(dir + "/euroc_mh01/cam1/sensor.yaml");
  const hapi_dataset::KalibrCamchain k = hapi_dataset::readKalibrCamchain(dir + "/kalibr/camchain-imucam.yaml");
  EXPECT_EQ(k.cam1.width, 752);
  EXPECT_DOUBLE_EQ(k.cam1.fu, r.fu);
  EXPECT_DOUBLE_EQ(k.cam0.distortion[0], l.distortion[0]);
  EXPECT_TRUE(k.cam0.T_BS.isApprox(Eigen::Isometry3d::Identity()));
  const StereoCalibration from_kalibr = hapi_dataset::rectifyStereo(k.cam0, k.cam1);
  const StereoCalibration from_euroc = hapi_dataset::rectifyStereo(l, r);
  EXPECT_NEAR(from_kalibr.baseline, from_euroc.baseline, 1e-9);
  EXPECT_LT((mat3(from_kalibr.right.R) - mat3(from_euroc.right.R)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((mat34(from_kalibr.right.P) - mat34(from_euroc.right.P)).cwiseAbs().maxCoeff(), 1e-6);
  ASSERT_TRUE(k.has_imu);
  EXPECT_TRUE(k.T_cam_imu.isApprox(l.T_BS.inverse(), 1e-9));  // the IMU is EuRoC's body
  EXPECT_DOUBLE_EQ(k.timeshift_cam_imu, 0.0022);
}

TEST(KalibrCamchain, RefusesAMonoChainAndANonRigidTransform) {
  const std::string good = std::string(HAPI_DATASET_FIXTURES) + "/kalibr/camchain-imucam.yaml";
  std::ifstream in(good);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string path = ::testing::TempDir() + "/camchain_broken.yaml";
  auto write = [&](const std::string& s) { std::ofstream(path) << s; };
  write(text.substr(0, text.find("cam1:")));  // cam0 only
  EXPECT_THROW(hapi_dataset::readKalibrCamchain(path), std::runtime_error);
  std::string scaled = text;  // cam0's T_cam_imu rotation scaled by 2 in its first row
  scaled.replace(scaled.find("- [0.0148655429817943"), 21, "- [0.0297310859635886");
  write(scaled);
  EXPECT_THROW(hapi_dataset::readKalibrCamchain(path), std::runtime_error);
  EXPECT_THROW(hapi_dataset::readKalibrCamchain(path + ".missing"), std::runtime_error);
}

// The CameraInfo YAML read back with OpenCV's YAML parser: every matrix
// with its size and values.
TEST(CameraInfoYaml, ReadsBackAsWritten) {
  CameraInfoData info;
  info.width = 752;
  info.height = 480;
  info.D = {-0.28, 0.07, 1e-4, -3.5e-5, 0.0};
  info.K = {458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {436.2, 0, 364.4, -48.02, 0, 436.2, 256.1, 0, 0, 0, 1, 0};
  const std::string yaml = "%YAML:1.0\n" + hapi_dataset::cameraInfoYaml(info, "right");
  cv::FileStorage fs(yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  ASSERT_TRUE(fs.isOpened());
  EXPECT_EQ(static_cast<int>(fs["image_width"]), 752);
  EXPECT_EQ(static_cast<std::string>(fs["camera_name"]), "right");
  EXPECT_EQ(static_cast<std::string>(fs["distortion_model"]), "plumb_bob");
  EXPECT_EQ(static_cast<int>(fs["projection_matrix"]["cols"]), 4);
  std::vector<double> P, D;
  fs["projection_matrix"]["data"] >> P;
  fs["distortion_coefficients"]["data"] >> D;
  ASSERT_EQ(P.size(), 12u);
  for (int i = 0; i < 12; ++i) EXPECT_DOUBLE_EQ(P[i], info.P[i]) << i;
  ASSERT_EQ(D.size(), 5u);
  EXPECT_DOUBLE_EQ(D[3], -3.5e-5);
}
