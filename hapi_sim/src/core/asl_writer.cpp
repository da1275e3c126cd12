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

std::string cameraYaml(const std::string& what, const CameraModel& c, const Pose& T_BS, double rate) {
  return "# General sensor definitions.\nsensor_type: camera\ncomment: hapi_sim " + what +
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

std::string surfaceMotionYaml(const Eigen::Vector2d& pixel, double frame_rate) {
  return "# The surface-motion truth's pixel of cam_imaging and its frame rate (image velocity in px per frame).\n"
         "sensor_type: surface_motion\ncomment: hapi_sim ground truth (docs/DESIGN.md \"Data\")\n"
         "camera: cam_imaging\npixel: [" + n(pixel.x()) + ", " + n(pixel.y()) + "]\nframe_rate_hz: " +
         n(frame_rate) + "\n";
}

std::string surfaceMotionColumns(const SurfaceMotionTruth& m) {
  const double c[] = {m.point.x(), m.point.y(), m.point.z(), m.normal.x(), m.normal.y(), m.normal.z(),
                      m.surface_velocity.x(), m.surface_velocity.y(), m.surface_velocity.z(), m.speed,
                      m.normal_velocity, m.image_velocity.x(), m.image_velocity.y()};
  std::string s;
  for (double v : c) s += n(v) + ",";
  return s + std::to_string(m.status());
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
// In the imaging optical frame; status as hapi_msgs/SurfaceMotion's (0 OK,
// 3 the ray misses the scene: the other columns are then 0).
const char* const AslWriter::kSurfaceMotionHeader =
    "#timestamp [ns], p_x [m], p_y [m], p_z [m], n_x [], n_y [], n_z [], s_x [mm s^-1], s_y [mm s^-1], "
    "s_z [mm s^-1], speed [mm s^-1], v_n [mm s^-1], i_u [px frame^-1], i_v [px frame^-1], status []";

AslWriter::AslWriter(const std::string& root, const Scenario& s)
    : s_(s), mav_(root + "/mav0"), imaging_(s.config().imaging_rate > 0) {
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
  writeFile(mav_ + "/cam0/sensor.yaml", cameraYaml("stereo cam0", s.rig().left, T_BC0, rate));
  writeFile(mav_ + "/cam1/sensor.yaml", cameraYaml("stereo cam1", s.rig().right, composePoses(T_BC0, T_C0C1), rate));
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
  if (!imaging_) return;
  // The imaging camera is the left camera: cam0's extrinsic and intrinsics.
  for (const char* d : {"cam_imaging/data", "surface_motion_groundtruth0"}) fs::create_directories(mav_ + "/" + d);
  writeFile(mav_ + "/cam_imaging/sensor.yaml",
            cameraYaml("imaging camera", s.imagingCamera(), T_BC0, s.config().imaging_rate));
  writeFile(mav_ + "/surface_motion_groundtruth0/sensor.yaml", surfaceMotionYaml(s.imagingPixel(), s.config().imaging_rate));
  cam_imaging_ = openCsv(mav_ + "/cam_imaging/data.csv", kCameraHeader);
  surface_gt_ = openCsv(mav_ + "/surface_motion_groundtruth0/data.csv", kSurfaceMotionHeader);
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
  if (imaging_) surface_gt_ << stamp << "," << surfaceMotionColumns(s_.surfaceMotion(t)) << "\n";
}

void AslWriter::addImaging(int64_t j, const cv::Mat& image) {
  const std::string stamp = std::to_string(kSimEpochNs + s_.imagingStampNs(j));
  const std::string path = mav_ + "/cam_imaging/data/" + stamp + ".png";
  // Perfusion content (32FC1, PU): a mono16 PNG of the PU rounded (PNG has no float).
  cv::Mat png = image;
  if (image.depth() == CV_32F) image.convertTo(png, CV_16U);
  if (!cv::imwrite(path, png)) throw std::runtime_error("cannot write " + path);
  cam_imaging_ << stamp << "," << stamp << ".png\n";
}

void AslWriter::close() {
  for (std::ofstream* f : {&cam_[0], &cam_[1], &imu_, &gt_, &scene_gt_, &cam_imaging_, &surface_gt_}) {
    if (!f->is_open()) continue;
    f->close();
    if (f->fail()) throw std::runtime_error("writing the ASL folder " + mav_ + " failed");
  }
}

void writeAslDataset(const Scenario& scenario, const std::string& root) {
  AslWriter w(root, scenario);
  scenario.play([&w](int64_t i, const ImuReading& r) { w.addImu(i, r); },
                [&w](int64_t k, const cv::Mat& l, const cv::Mat& r) { w.addFrame(k, l, r); },
                [&w](int64_t j, const cv::Mat& image) { w.addImaging(j, image); });
  w.close();
}

}  // namespace hapi_sim
