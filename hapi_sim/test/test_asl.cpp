// The EuRoC/ASL writer: the documented files and headers exist, sensor.yaml
// carries the true extrinsic and intrinsics, and every CSV parses back to the
// numbers the scenario produces (images, IMU, ground truth, scene motion);
// with an imaging camera, its folder and the surface-motion truth.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "hapi_sim/asl_writer.hpp"

using namespace hapi_sim;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> lines(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> out;
  for (std::string l; std::getline(f, l);) out.push_back(l);
  return out;
}

std::vector<double> csvNumbers(const std::string& line) {
  std::vector<double> v;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
  return v;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

// The numbers of a "key: [a, b, ...]" entry (possibly over several lines).
std::vector<double> yamlList(const std::string& text, const std::string& key) {
  const size_t k = text.find(key + ":");
  EXPECT_NE(k, std::string::npos) << key;
  if (k == std::string::npos) return {};
  const size_t a = text.find('[', k), b = text.find(']', a);
  std::string body = text.substr(a + 1, b - a - 1);
  for (char& c : body) if (c == '\n') c = ' ';
  return csvNumbers(body);
}

class AslTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = "/tmp/hapi_sim_asl_test_" + std::to_string(::getpid());
    ScenarioConfig c;
    c.scene = SceneKind::Skin;
    c.trajectory = TrajectoryKind::Subject;  // the scene moves: scene_groundtruth0 is not the identity
    c.seed = 3;
    c.duration = 0.5;
    c.image_scale = 0.25;
    c.blur_samples = 4;
    scenario_ = new Scenario(c);
    writeAslDataset(*scenario_, root_);
  }
  static void TearDownTestSuite() {
    fs::remove_all(root_);
    delete scenario_;
  }
  static std::string root_;
  static Scenario* scenario_;
};
std::string AslTest::root_;
Scenario* AslTest::scenario_ = nullptr;

}  // namespace

TEST_F(AslTest, LayoutAndHeaders) {
  const std::string m = root_ + "/mav0/";
  for (const char* f : {"cam0/sensor.yaml", "cam1/sensor.yaml", "imu0/sensor.yaml", "cam0/data.csv", "cam1/data.csv",
                        "imu0/data.csv", "state_groundtruth_estimate0/data.csv", "state_groundtruth_estimate0/sensor.yaml",
                        "scene.yaml", "calibration.yaml", "scene_groundtruth0/data.csv"})
    EXPECT_TRUE(fs::is_regular_file(m + f)) << f;
  EXPECT_EQ(lines(m + "cam0/data.csv").at(0), "#timestamp [ns],filename");
  EXPECT_EQ(lines(m + "imu0/data.csv").at(0),
            "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
            "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]");
  EXPECT_EQ(lines(m + "state_groundtruth_estimate0/data.csv").at(0),
            "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
            "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], "
            "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]");
  EXPECT_EQ(slurp(m + "scene.yaml"), scenario_->scene().yaml());
  EXPECT_EQ(slurp(m + "calibration.yaml"), scenario_->calibrationYaml());
  const std::string imu = slurp(m + "imu0/sensor.yaml");
  for (const char* key : {"sensor_type: imu", "rate_hz: 200", "gyroscope_noise_density: 0.00016968",
                          "gyroscope_random_walk: 1.9393e-05", "accelerometer_noise_density: 0.002",
                          "accelerometer_random_walk: 0.003"})
    EXPECT_NE(imu.find(key), std::string::npos) << key;
  const std::vector<double> id = yamlList(imu, "data");
  ASSERT_EQ(id.size(), 16u);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(id[i], (i % 5 == 0) ? 1.0 : 0.0);
}

TEST_F(AslTest, CameraSensorYamlCarriesTheCalibration) {
  const StereoRigModel& rig = scenario_->rig();
  const Pose T_BC0 = inversePose(scenario_->calibration().T_cam_imu);
  for (int c = 0; c < 2; ++c) {
    const std::string y = slurp(root_ + "/mav0/cam" + std::to_string(c) + "/sensor.yaml");
    const CameraModel& cam = c == 0 ? rig.left : rig.right;
    for (const char* key : {"sensor_type: camera", "rate_hz: 10", "camera_model: pinhole",
                            "distortion_model: radial-tangential", "resolution: [160, 120]"})
      EXPECT_NE(y.find(key), std::string::npos) << key;
    EXPECT_EQ(yamlList(y, "intrinsics"), (std::vector<double>{cam.fx, cam.fy, cam.cx, cam.cy}));
    EXPECT_EQ(yamlList(y, "distortion_coefficients"), (std::vector<double>{cam.k1, cam.k2, cam.p1, cam.p2}));
    const std::vector<double> T = yamlList(y, "data");
    ASSERT_EQ(T.size(), 16u);
    // The camera origin in the body frame: cam1 is cam0 shifted by the baseline.
    const Eigen::Vector3d origin = T_BC0.p + (c == 1 ? Eigen::Vector3d(T_BC0.q * Eigen::Vector3d(rig.baseline, 0, 0))
                                                     : Eigen::Vector3d::Zero());
    EXPECT_NEAR(T[3], origin.x(), 1e-15);
    EXPECT_NEAR(T[7], origin.y(), 1e-15);
    EXPECT_NEAR(T[11], origin.z(), 1e-15);
    const Eigen::Matrix3d R = T_BC0.q.toRotationMatrix();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(T[4 * r + k], R(r, k), 1e-15);
    EXPECT_EQ(T[15], 1.0);
  }
}

TEST_F(AslTest, CsvRowsParseBackToTheScenario) {
  const Scenario& s = *scenario_;
  const std::string m = root_ + "/mav0/";
  // Cameras: one row and one readable PNG per frame, equal to a re-render.
  for (int c = 0; c < 2; ++c) {
    const auto rows = lines(m + "cam" + std::to_string(c) + "/data.csv");
    ASSERT_EQ(static_cast<int64_t>(rows.size()), s.frameCount() + 1);
    for (int64_t k = 0; k < s.frameCount(); ++k) {
      const std::string stamp = std::to_string(kSimEpochNs + s.frameStampNs(k));
      EXPECT_EQ(rows[k + 1], stamp + "," + stamp + ".png");
    }
  }
  cv::Mat l, r;
  s.renderStereo(2, &l, &r);
  const std::string name = std::to_string(kSimEpochNs + s.frameStampNs(2)) + ".png";
  EXPECT_EQ(cv::norm(cv::imread(m + "cam0/data/" + name, cv::IMREAD_UNCHANGED), l, cv::NORM_L1), 0.0);
  EXPECT_EQ(cv::norm(cv::imread(m + "cam1/data/" + name, cv::IMREAD_UNCHANGED), r, cv::NORM_L1), 0.0);
  // IMU, ground truth and scene motion: exactly the replayed numbers.
  const auto imu = lines(m + "imu0/data.csv"), gt = lines(m + "state_groundtruth_estimate0/data.csv"),
             sc = lines(m + "scene_groundtruth0/data.csv");
  ASSERT_EQ(static_cast<int64_t>(imu.size()), s.imuCount() + 1);
  ASSERT_EQ(gt.size(), imu.size());
  ASSERT_EQ(sc.size(), imu.size());
  ImuModel model = s.makeImuModel();
  for (int64_t i = 0; i < s.imuCount(); ++i) {
    const double t = s.imuTimeNs(i) * 1e-9;
    const ImuReading want = model.measure(s.imuInInertial(t));
    const std::vector<double> a = csvNumbers(imu[i + 1]), g = csvNumbers(gt[i + 1]), q = csvNumbers(sc[i + 1]);
    ASSERT_EQ(a.size(), 7u);
    ASSERT_EQ(g.size(), 17u);
    ASSERT_EQ(q.size(), 8u);
    EXPECT_EQ(imu[i + 1].substr(0, imu[i + 1].find(',')), std::to_string(kSimEpochNs + s.imuTimeNs(i)));
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a[1 + k], want.gyro[k]);
      EXPECT_EQ(a[4 + k], want.accel[k]);
      EXPECT_EQ(g[11 + k], want.gyro_bias[k]);
      EXPECT_EQ(g[14 + k], want.accel_bias[k]);
    }
    const MotionSample b = s.imuInInertial(t), scene = s.sceneInInertial(t);
    const double bw[] = {b.p.x(), b.p.y(), b.p.z(), b.q.w(), b.q.x(), b.q.y(), b.q.z(), b.v.x(), b.v.y(), b.v.z()};
    for (int k = 0; k < 10; ++k) EXPECT_EQ(g[1 + k], bw[k]);
    const double sw[] = {scene.p.x(), scene.p.y(), scene.p.z(), scene.q.w(), scene.q.x(), scene.q.y(), scene.q.z()};
    for (int k = 0; k < 7; ++k) EXPECT_EQ(q[1 + k], sw[k]);
  }
  // The scene really moves in this scenario.
  EXPECT_GT(std::abs(csvNumbers(sc.back())[1] - csvNumbers(sc[1])[1]), 1e-4);
}

// No imaging camera by default: no folder for it.
TEST_F(AslTest, NoImagingFoldersWithoutAnImagingCamera) {
  EXPECT_FALSE(fs::exists(root_ + "/mav0/cam_imaging"));
  EXPECT_FALSE(fs::exists(root_ + "/mav0/surface_motion_groundtruth0"));
}

// With --imaging-rate: cam_imaging as cam0 at its own rate (its PNGs are the
// scenario's imaging frames) and the surface-motion truth at IMU rate, every
// number exactly the scenario's.
TEST(AslImaging, ImagingCameraAndSurfaceMotionTruth) {
  const std::string root = "/tmp/hapi_sim_asl_imaging_test_" + std::to_string(::getpid());
  ScenarioConfig c;
  c.scene = SceneKind::Skin;
  c.trajectory = TrajectoryKind::Measurement;
  c.seed = 2;
  c.duration = 0.5;
  c.image_scale = 0.25;
  c.blur_samples = 4;
  c.imaging_rate = 40;
  c.imaging_pixel = Eigen::Vector2d(70, 50);
  const Scenario s(c);
  writeAslDataset(s, root);
  const std::string m = root + "/mav0/";
  const auto rows = lines(m + "cam_imaging/data.csv");
  ASSERT_EQ(rows.size(), 21u);
  EXPECT_EQ(rows[0], AslWriter::kCameraHeader);
  for (int64_t j = 0; j < 20; ++j) {
    const std::string stamp = std::to_string(kSimEpochNs + s.imagingStampNs(j));
    EXPECT_EQ(rows[j + 1], stamp + "," + stamp + ".png");
  }
  const std::string png = m + "cam_imaging/data/" + std::to_string(kSimEpochNs + s.imagingStampNs(7)) + ".png";
  EXPECT_EQ(cv::norm(cv::imread(png, cv::IMREAD_UNCHANGED), s.renderImaging(7), cv::NORM_L1), 0.0);
  const std::string yaml = slurp(m + "cam_imaging/sensor.yaml");
  EXPECT_EQ(yamlList(yaml, "intrinsics"), yamlList(slurp(m + "cam0/sensor.yaml"), "intrinsics"));
  EXPECT_EQ(yamlList(yaml, "data"), yamlList(slurp(m + "cam0/sensor.yaml"), "data"));
  EXPECT_NE(yaml.find("rate_hz: 40\n"), std::string::npos);
  const std::string sm = slurp(m + "surface_motion_groundtruth0/sensor.yaml");
  EXPECT_EQ(yamlList(sm, "pixel"), (std::vector<double>{70, 50}));
  EXPECT_NE(sm.find("frame_rate_hz: 40\n"), std::string::npos);
  const auto truth = lines(m + "surface_motion_groundtruth0/data.csv");
  ASSERT_EQ(static_cast<int64_t>(truth.size()), s.imuCount() + 1);
  EXPECT_EQ(truth[0], AslWriter::kSurfaceMotionHeader);
  for (int64_t i = 0; i < s.imuCount(); ++i) {
    const SurfaceMotionTruth t = s.surfaceMotion(s.imuTimeNs(i) * 1e-9);
    const std::vector<double> v = csvNumbers(truth[i + 1]);
    ASSERT_EQ(v.size(), 15u);
    EXPECT_EQ(truth[i + 1].substr(0, truth[i + 1].find(',')), std::to_string(kSimEpochNs + s.imuTimeNs(i)));
    const double want[] = {t.point.x(), t.point.y(), t.point.z(), t.normal.x(), t.normal.y(), t.normal.z(),
                           t.surface_velocity.x(), t.surface_velocity.y(), t.surface_velocity.z(), t.speed,
                           t.normal_velocity, t.image_velocity.x(), t.image_velocity.y(), 0.0};
    for (int k = 0; k < 14; ++k) EXPECT_EQ(v[1 + k], want[k]) << "row " << i << " column " << k + 1;
    EXPECT_GT(t.speed, 0.0);
  }
  fs::remove_all(root);
}
