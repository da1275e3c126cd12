// AslWriter: the EuRoC / ASL folder layout and file formats (headers, units,
// nanosecond stamps and sensor.yaml keys as in EuRoC's MH_01_easy).
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "hapi_sim/asl_writer.hpp"
#include "hapi_sim/text_format.hpp"

namespace hapi_sim {
namespace {

namespace fs = std::filesystem;

std::string n(double v) { return formatNumber(v); }

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path);
}

std::ofstream openCsv(const std::string& path, const char* header) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << header << "\n";
  return f;
}

std::string tbs(const Pose& T_BS) {
  return "# Sensor extrinsics wrt. the body-frame.\nT_BS:\n  cols: 4\n  rows: 4\n  data: [" +
         formatMatrix4(T_BS, ",\n         ") + "]\n";
}

std::string cameraYaml(int index, const CameraModel& c, const Pose& T_BS, double rate) {
  return "# General sensor definitions.\nsensor_type: camera\ncomment: hapi_sim stereo cam" + std::to_string(index) +
         " (simulated)\n\n" + tbs(T_BS) + "\n# Camera specific definitions.\nrate_hz: " + n(rate) +
         "\nresolution: [" + std::to_string(c.width) + ", " + std::to_string(c.height) +
         "]\ncamera_model: pinhole\nintrinsics: [" + n(c.fx) + ", " + n(c.fy) + ", " + n(c.cx) + ", " + n(c.cy) +
         "] #fu, fv, cu, cv\ndistortion_model: radial-tangential\ndistortion_coefficients: [" + n(c.k1) + ", " +
         n(c.k2) + ", " + n(c.p1) + ", " + n(c.p2) + "]\n";
}

std::string imuYaml(const ImuSpec& s, double rate) {
  return std::string("#Default imu sensor yaml file\nsensor_type: imu\ncomment: hapi_sim IMU (") + s.part +
         " noise model)\n\n" + tbs(Pose()) + "rate_hz: " + n(rate) +
         "\n\n# inertial sensor noise model parameters (static)\n"
         "gyroscope_noise_density: " + n(s.gyro_noise_density) + "     # [ rad / s / sqrt(Hz) ]   ( gyro \"white noise\" )\n"
         "gyroscope_random_walk: " + n(s.gyro_random_walk) + "       # [ rad / s^2 / sqrt(Hz) ] ( gyro bias diffusion )\n"
         "accelerometer_noise_density: " + n(s.accel_noise_density) + "  # [ m / s^2 / sqrt(Hz) ]   ( accel \"white noise\" )\n"
         "accelerometer_random_walk: " + n(s.accel_random_walk) + "    # [ m / s^3 / sqrt(Hz) ].  ( accel bias diffusion )\n";
}

std::string poseColumns(const MotionSample& m) {
  return n(m.p.x()) + "," + n(m.p.y()) + "," + n(m.p.z()) + "," + n(m.q.w()) + "," + n(m.q.x()) + "," + n(m.q.y()) +
         "," + n(m.q.z());
}

}  // namespace

const char* const AslWriter::kCameraHeader = "#timestamp [ns],filename";
const char* const AslWriter::kImuHeader =
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]";
const char* const AslWriter::kGroundTruthHeader =
    "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
    "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], "
    "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]";
const char* const AslWriter::kPoseHeader =
    "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z []";

AslWriter::AslWriter(const std::string& root, const Scenario& s) : s_(s), mav_(root + "/mav0") {
  for (const char* d : {"cam0/data", "cam1/data", "imu0", "state_groundtruth_estimate0", "scene_groundtruth0"})
    fs::create_directories(mav_ + "/" + d);
  // T_BS of the cameras: the camera in the body (= IMU) frame, as the device
  // believes it (a reader's calibration); calibration.yaml keeps the truth.
  const Pose T_BC0 = inversePose(s.believedCalibration().T_cam_imu);
  Pose T_C0C1;
  T_C0C1.p = Eigen::Vector3d(s.rig().baseline, 0, 0);
  const double rate = s.config().rate;
  if (s.rig().left.k3 != 0.0 || s.rig().right.k3 != 0.0)
    throw std::runtime_error("radial-tangential has no k3: the rig's k3 must be 0");
  writeFile(mav_ + "/cam0/sensor.yaml", cameraYaml(0, s.rig().left, T_BC0, rate));
  writeFile(mav_ + "/cam1/sensor.yaml", cameraYaml(1, s.rig().right, composePoses(T_BC0, T_C0C1), rate));
  writeFile(mav_ + "/imu0/sensor.yaml", imuYaml(s.imuSpec(), s.config().imu_rate));
  writeFile(mav_ + "/state_groundtruth_estimate0/sensor.yaml",
            "# Ground truth of the body (= imu0) frame in the inertial frame R, exact (simulated).\n"
            "sensor_type: visual-inertial\ncomment: hapi_sim ground truth\n\n" + tbs(Pose()));
  writeFile(mav_ + "/scene.yaml", s.scene().yaml());
  writeFile(mav_ + "/calibration.yaml", s.calibrationYaml());
  cam_[0] = openCsv(mav_ + "/cam0/data.csv", kCameraHeader);
  cam_[1] = openCsv(mav_ + "/cam1/data.csv", kCameraHeader);
  imu_ = openCsv(mav_ + "/imu0/data.csv", kImuHeader);
  gt_ = openCsv(mav_ + "/state_groundtruth_estimate0/data.csv", kGroundTruthHeader);
  scene_gt_ = openCsv(mav_ + "/scene_groundtruth0/data.csv", kPoseHeader);
}

void AslWriter::addFrame(int64_t k, const cv::Mat& left, const cv::Mat& right) {
  const std::string stamp = std::to_string(kSimEpochNs + s_.frameStampNs(k));
  const cv::Mat* img[2] = {&left, &right};
  for (int c = 0; c < 2; ++c) {
    const std::string path = mav_ + "/cam" + std::to_string(c) + "/data/" + stamp + ".png";
    if (!cv::imwrite(path, *img[c])) throw std::runtime_error("cannot write " + path);
    cam_[c] << stamp << "," << stamp << ".png\n";
  }
}

void AslWriter::addImu(int64_t i, const ImuReading& r) {
  const int64_t t_ns = s_.imuTimeNs(i);
  const std::string stamp = std::to_string(kSimEpochNs + t_ns);
  imu_ << stamp << "," << n(r.gyro.x()) << "," << n(r.gyro.y()) << "," << n(r.gyro.z()) << "," << n(r.accel.x()) << ","
       << n(r.accel.y()) << "," << n(r.accel.z()) << "\n";
  const double t = t_ns * 1e-9;
  const MotionSample b = s_.imuInInertial(t);
  gt_ << stamp << "," << poseColumns(b) << "," << n(b.v.x()) << "," << n(b.v.y()) << "," << n(b.v.z()) << ","
      << n(r.gyro_bias.x()) << "," << n(r.gyro_bias.y()) << "," << n(r.gyro_bias.z()) << "," << n(r.accel_bias.x())
      << "," << n(r.accel_bias.y()) << "," << n(r.accel_bias.z()) << "\n";
  scene_gt_ << stamp << "," << poseColumns(s_.sceneInInertial(t)) << "\n";
}

void AslWriter::close() {
  for (std::ofstream* f : {&cam_[0], &cam_[1], &imu_, &gt_, &scene_gt_}) {
    f->close();
    if (f->fail()) throw std::runtime_error("writing the ASL folder " + mav_ + " failed");
  }
}

void writeAslDataset(const Scenario& scenario, const std::string& root) {
  AslWriter w(root, scenario);
  scenario.play([&w](int64_t i, const ImuReading& r) { w.addImu(i, r); },
                [&w](int64_t k, const cv::Mat& l, const cv::Mat& r) { w.addFrame(k, l, r); });
  w.close();
}

}  // namespace hapi_sim
