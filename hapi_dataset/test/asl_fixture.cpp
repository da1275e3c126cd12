// The tiny ASL recording of the tests (asl_fixture.hpp).
#include "asl_fixture.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>
#include <vector>

namespace hapi_dataset_test {
namespace {

void mkdirs(const std::string& p) {
  std::string cur;
  for (size_t i = 0; i <= p.size(); ++i) {
    if (i == p.size() || p[i] == '/') {
      if (!cur.empty()) ::mkdir(cur.c_str(), 0755);
    }
    if (i < p.size()) cur += p[i];
  }
}

std::string matrixRows(const Eigen::Isometry3d& T) {
  std::ostringstream s;
  s << std::setprecision(17) << "[";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) s << T.matrix()(r, c) << (r == 3 && c == 3 ? "]" : ", ");
  return s.str();
}

void writeCameraYaml(const std::string& path, const Eigen::Isometry3d& T_BS, double fu, double cu) {
  std::ofstream f(path);
  f << "# General sensor definitions.\nsensor_type: camera\ncomment: tiny test camera\n\n"
    << "# Sensor extrinsics wrt. the body-frame.\nT_BS:\n  cols: 4\n  rows: 4\n  data: " << matrixRows(T_BS) << "\n\n"
    << "rate_hz: 20\nresolution: [" << TinyAsl::kWidth << ", " << TinyAsl::kHeight << "]\n"
    << "camera_model: pinhole\nintrinsics: [" << fu << ", " << fu << ", " << cu << ", 24.5] #fu, fv, cu, cv\n"
    << "distortion_model: radial-tangential\ndistortion_coefficients: [-0.28, 0.07, 0.0002, 1.8e-05]\n";
}

}  // namespace

Eigen::Isometry3d TinyAsl::T_BS_cam0() {
  Eigen::Matrix4d m;
  m << 0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975, 0.999557249008, 0.0149672133247,
      0.025715529948, -0.064676986768, -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949, 0, 0,
      0, 1;
  Eigen::Isometry3d T(m);
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(T.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  T.linear() = svd.matrixU() * svd.matrixV().transpose();
  return T;
}

Eigen::Isometry3d TinyAsl::T_BS_cam1() {
  Eigen::Isometry3d T_01 = Eigen::Isometry3d::Identity();
  T_01.linear() = Eigen::AngleAxisd(M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T_01.translation() = Eigen::Vector3d(0.11, 0.0, 0.0);
  return T_BS_cam0() * T_01;
}

uint8_t TinyAsl::pixel(int k, int camera, int x, int y) {
  return static_cast<uint8_t>((7 * k + 3 * x + 5 * y + 101 * camera) % 256);
}

Eigen::Isometry3d TinyAsl::bodyPose(int64_t stamp_ns) {
  const double t = (stamp_ns - kT0) * 1e-9;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(kYawRate * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(kSpeed * t, 0.0, 1.5);
  return T;
}

void writeTinyAsl(const std::string& root, bool with_truth, const std::string& scene) {
  const std::string mav0 = root + "/mav0";
  for (const char* d : {"cam0/data", "cam1/data", "imu0"}) mkdirs(mav0 + "/" + d);
  writeCameraYaml(mav0 + "/cam0/sensor.yaml", TinyAsl::T_BS_cam0(), 40.0, 31.5);
  writeCameraYaml(mav0 + "/cam1/sensor.yaml", TinyAsl::T_BS_cam1(), 41.0, 32.0);
  for (int cam = 0; cam < 2; ++cam) {
    std::ofstream csv(mav0 + "/cam" + std::to_string(cam) + "/data.csv");
    csv << "#timestamp [ns],filename\r\n";  // EuRoC's files end lines with CR LF
    // cam1 has one extra image between frames 2 and 3 (no partner in cam0).
    for (int k = 0; k < TinyAsl::kFrames; ++k) {
      const int64_t t = TinyAsl::kT0 + k * TinyAsl::kFramePeriod;
      cv::Mat img(TinyAsl::kHeight, TinyAsl::kWidth, CV_8UC1);
      for (int y = 0; y < img.rows; ++y)
        for (int x = 0; x < img.cols; ++x) img.at<uint8_t>(y, x) = TinyAsl::pixel(k, cam, x, y);
      const std::string name = std::to_string(t) + ".png";
      if (!cv::imwrite(mav0 + "/cam" + std::to_string(cam) + "/data/" + name, img))
        throw std::runtime_error("cannot write test image");
      csv << t << "," << name << "\r\n";
      if (cam == 1 && k == 2) {
        const int64_t odd = t + TinyAsl::kFramePeriod / 2;
        cv::imwrite(mav0 + "/cam1/data/" + std::to_string(odd) + ".png", img);
        csv << odd << "," << odd << ".png\r\n";
      }
    }
  }
  {
    std::ofstream y(mav0 + "/imu0/sensor.yaml");
    y << "%YAML:1.0\nsensor_type: imu\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0,\n"
      << "         0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]\nrate_hz: 200\n"
      << "gyroscope_noise_density: 1.6968e-04\ngyroscope_random_walk: 1.9393e-05\n"
      << "accelerometer_noise_density: 2.0000e-3\naccelerometer_random_walk: 3.0000e-3\n";
    std::ofstream csv(mav0 + "/imu0/data.csv");
    csv << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
        << "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\r\n" << std::setprecision(17);
    for (int i = 0; i < TinyAsl::kImuRows; ++i) {
      const int64_t t = TinyAsl::kT0 - TinyAsl::kImuPeriod + i * TinyAsl::kImuPeriod;
      csv << t << ",0.001," << -0.002 << "," << TinyAsl::kYawRate << "," << 0.01 * i << ",0.02,9.81\r\n";
    }
  }
  if (with_truth) {
    mkdirs(mav0 + "/state_groundtruth_estimate0");
    std::ofstream csv(mav0 + "/state_groundtruth_estimate0/data.csv");
    csv << "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
        << "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], "
        << "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\r\n"
        << std::setprecision(17);
    for (int i = 0; i < TinyAsl::kImuRows; ++i) {
      const int64_t t = TinyAsl::kT0 - TinyAsl::kImuPeriod + i * TinyAsl::kImuPeriod;
      const Eigen::Isometry3d T = TinyAsl::bodyPose(t);
      const Eigen::Quaterniond q(T.linear());
      csv << t << "," << T.translation().x() << "," << T.translation().y() << "," << T.translation().z() << ","
          << q.w() << "," << q.x() << "," << q.y() << "," << q.z() << "," << TinyAsl::kSpeed
          << ",0,0,-0.002,0.02,0.08,-0.02,0.1,0.07\r\n";
    }
  }
  if (!scene.empty()) std::ofstream(mav0 + "/scene.yaml") << scene;
}

std::string makeTempDir(const std::string& tag) {
  const char* base = std::getenv("TMPDIR");
  std::string templ = std::string(base && *base ? base : "/tmp") + "/hapi_dataset_" + tag + "_XXXXXX";
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  if (!::mkdtemp(buf.data())) throw std::runtime_error("mkdtemp failed");
  return buf.data();
}

}  // namespace hapi_dataset_test
