// sensor.yaml of an ASL/EuRoC sensor (asl_sensor.hpp).
#include "hapi_dataset/asl_sensor.hpp"

#include <opencv2/core.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hapi_dataset {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

// EuRoC's sensor.yaml files start with a comment, not with the "%YAML:1.0"
// directive OpenCV's FileStorage needs to recognise YAML: the text is read and
// the directive prepended when it is missing.
cv::FileStorage open(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open");
  std::ostringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  if (yaml.rfind("%YAML", 0) != 0) yaml = "%YAML:1.0\n" + yaml;
  cv::FileStorage fs;
  try {
    fs.open(yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& e) {
    fail(path, std::string("not readable as YAML: ") + e.what());
  }
  if (!fs.isOpened()) fail(path, "not readable as YAML");
  return fs;
}

std::vector<double> numbers(const cv::FileNode& n, const std::string& path, const std::string& key, size_t count) {
  if (!n.isSeq()) fail(path, "'" + key + "' is not a list");
  std::vector<double> v;
  for (const auto& e : n) {
    if (!e.isReal() && !e.isInt()) fail(path, "'" + key + "' holds a non-number");
    v.push_back(static_cast<double>(e));
  }
  if (count != 0 && v.size() != count)
    fail(path, "'" + key + "' has " + std::to_string(v.size()) + " numbers, expected " + std::to_string(count));
  return v;
}

double optionalNumber(const cv::FileStorage& fs, const std::string& key) {
  const cv::FileNode n = fs[key];
  return (n.isReal() || n.isInt()) ? static_cast<double>(n) : 0.0;
}

std::string text(const cv::FileStorage& fs, const std::string& key) {
  const cv::FileNode n = fs[key];
  return n.isString() ? static_cast<std::string>(n) : std::string();
}

Eigen::Isometry3d bodyTransform(const cv::FileStorage& fs, const std::string& path) {
  const cv::FileNode n = fs["T_BS"];
  if (n.empty()) fail(path, "no T_BS");
  const std::vector<double> d = numbers(n["data"], path, "T_BS.data", 16);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = d[4 * r + c];
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  // EuRoC's rotations are orthonormal to ~1e-9; a wrong file (e.g. a
  // transposed or scaled block) is far off.
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-5 || R.determinant() < 0 ||
      (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9)
    fail(path, "T_BS is not a rigid transform");
  // Re-orthonormalise so that products of transforms stay rigid.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = svd.matrixU() * svd.matrixV().transpose();
  T.translation() = m.topRightCorner<3, 1>();
  return T;
}

}  // namespace

Eigen::Isometry3d readBodyTransform(const std::string& sensor_yaml) {
  const cv::FileStorage fs = open(sensor_yaml);
  return bodyTransform(fs, sensor_yaml);
}

CameraSensor readCameraSensor(const std::string& path) {
  const cv::FileStorage fs = open(path);
  CameraSensor c;
  c.T_BS = bodyTransform(fs, path);
  const std::string model = text(fs, "camera_model");
  if (model != "pinhole") fail(path, "camera_model '" + model + "' is not supported (pinhole only)");
  const std::string dist = text(fs, "distortion_model");
  if (dist != "radial-tangential" && dist != "radtan")
    fail(path, "distortion_model '" + dist + "' is not supported (radial-tangential only)");
  const std::vector<double> res = numbers(fs["resolution"], path, "resolution", 2);
  c.width = static_cast<int>(res[0]);
  c.height = static_cast<int>(res[1]);
  if (c.width <= 0 || c.height <= 0 || c.width != res[0] || c.height != res[1])
    fail(path, "resolution must be two positive integers");
  const std::vector<double> k = numbers(fs["intrinsics"], path, "intrinsics", 4);
  c.fu = k[0];
  c.fv = k[1];
  c.cu = k[2];
  c.cv = k[3];
  if (!(c.fu > 0 && c.fv > 0)) fail(path, "focal lengths must be positive");
  c.distortion = numbers(fs["distortion_coefficients"], path, "distortion_coefficients", 4);
  c.rate_hz = optionalNumber(fs, "rate_hz");
  return c;
}

ImuSensor readImuSensor(const std::string& path) {
  const cv::FileStorage fs = open(path);
  ImuSensor s;
  s.T_BS = bodyTransform(fs, path);
  s.rate_hz = optionalNumber(fs, "rate_hz");
  s.gyroscope_noise_density = optionalNumber(fs, "gyroscope_noise_density");
  s.gyroscope_random_walk = optionalNumber(fs, "gyroscope_random_walk");
  s.accelerometer_noise_density = optionalNumber(fs, "accelerometer_noise_density");
  s.accelerometer_random_walk = optionalNumber(fs, "accelerometer_random_walk");
  return s;
}

}  // namespace hapi_dataset
