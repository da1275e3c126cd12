// sensor.yaml of an ASL/EuRoC sensor (asl_sensor.hpp).
#include "hapi_dataset/asl_sensor.hpp"

#include <opencv2/core.hpp>

#include <cmath>
#include <fstream>
#include <stdexcept>

namespace hapi_dataset {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

// EuRoC's sensor.yaml files start with a comment, not with the "%YAML:1.0"
// directive OpenCV's FileStorage needs to recognise YAML: the text is read and
// the directive prepended when it is missing. Kalibr writes a matrix as a
// block sequence at its key's indentation ("T_cam_imu:" then "- [...]"
// rows), valid YAML that OpenCV's parser refuses: such rows are indented
// two more spaces.
cv::FileStorage open(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open");
  std::string yaml, line;
  while (std::getline(in, line)) {
    const size_t first = line.find_first_not_of(' ');
    if (first != std::string::npos && line.compare(first, 2, "- ") == 0) line.insert(0, "  ");
    yaml += line + "\n";
  }
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

double optionalNumber(const cv::FileNode& fs, const std::string& key) {
  const cv::FileNode n = fs[key];
  return (n.isReal() || n.isInt()) ? static_cast<double>(n) : 0.0;
}

std::string text(const cv::FileNode& fs, const std::string& key) {
  const cv::FileNode n = fs[key];
  return n.isString() ? static_cast<std::string>(n) : std::string();
}

// A rigid transform from 16 numbers, row-major; `key` names it in errors.
Eigen::Isometry3d rigidTransform(const std::vector<double>& d, const std::string& path, const std::string& key) {
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = d[4 * r + c];
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  // EuRoC's rotations are orthonormal to ~1e-9; a wrong file (e.g. a
  // transposed or scaled block) is far off.
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-5 || R.determinant() < 0 ||
      (m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9)
    fail(path, key + " is not a rigid transform");
  // Re-orthonormalise so that products of transforms stay rigid.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = svd.matrixU() * svd.matrixV().transpose();
  T.translation() = m.topRightCorner<3, 1>();
  return T;
}

Eigen::Isometry3d bodyTransform(const cv::FileNode& fs, const std::string& path) {
  const cv::FileNode n = fs["T_BS"];
  if (n.empty()) fail(path, "no T_BS");
  return rigidTransform(numbers(n["data"], path, "T_BS.data", 16), path, "T_BS");
}

// Kalibr's 4 x 4 matrix: a list of four rows of four numbers.
Eigen::Isometry3d kalibrTransform(const cv::FileNode& n, const std::string& path, const std::string& key) {
  if (!n.isSeq() || n.size() != 4) fail(path, "'" + key + "' is not a list of 4 rows");
  std::vector<double> d;
  for (const auto& row : n) {
    const std::vector<double> r = numbers(row, path, key, 4);
    d.insert(d.end(), r.begin(), r.end());
  }
  return rigidTransform(d, path, key);
}

// The pinhole + radial-tangential fields EuRoC's sensor.yaml and Kalibr's
// camchain share (the distortion's key differs); c->T_BS is the caller's.
CameraSensor cameraFields(const cv::FileNode& fs, const std::string& path, const std::string& distortion_key) {
  CameraSensor c;
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
  c.distortion = numbers(fs[distortion_key], path, distortion_key, 4);
  return c;
}

}  // namespace

Eigen::Isometry3d readBodyTransform(const std::string& sensor_yaml) {
  const cv::FileStorage fs = open(sensor_yaml);
  return bodyTransform(fs.root(), sensor_yaml);
}

CameraSensor readCameraSensor(const std::string& path) {
  const cv::FileStorage fs = open(path);
  CameraSensor c = cameraFields(fs.root(), path, "distortion_coefficients");
  c.T_BS = bodyTransform(fs.root(), path);
  c.rate_hz = optionalNumber(fs.root(), "rate_hz");
  return c;
}

ImuSensor readImuSensor(const std::string& path) {
  const cv::FileStorage fs = open(path);
  ImuSensor s;
  const cv::FileNode root = fs.root();
  s.T_BS = bodyTransform(root, path);
  s.rate_hz = optionalNumber(root, "rate_hz");
  s.gyroscope_noise_density = optionalNumber(root, "gyroscope_noise_density");
  s.gyroscope_random_walk = optionalNumber(root, "gyroscope_random_walk");
  s.accelerometer_noise_density = optionalNumber(root, "accelerometer_noise_density");
  s.accelerometer_random_walk = optionalNumber(root, "accelerometer_random_walk");
  return s;
}

KalibrCamchain readKalibrCamchain(const std::string& path) {
  const cv::FileStorage fs = open(path);
  const cv::FileNode cam0 = fs["cam0"], cam1 = fs["cam1"];
  if (cam0.empty() || cam1.empty()) fail(path, "needs cam0 and cam1 (a stereo camchain)");
  KalibrCamchain k;
  k.cam0 = cameraFields(cam0, path, "distortion_coeffs");
  k.cam1 = cameraFields(cam1, path, "distortion_coeffs");
  if (cam1["T_cn_cnm1"].empty()) fail(path, "cam1 has no T_cn_cnm1 (its pose relative to cam0)");
  // T_cn_cnm1 maps cam0 points into cam1: cam1's pose in cam0 is its inverse.
  k.cam1.T_BS = kalibrTransform(cam1["T_cn_cnm1"], path, "cam1.T_cn_cnm1").inverse();
  k.has_imu = !cam0["T_cam_imu"].empty();
  if (k.has_imu) {
    k.T_cam_imu = kalibrTransform(cam0["T_cam_imu"], path, "cam0.T_cam_imu");
    k.timeshift_cam_imu = optionalNumber(cam0, "timeshift_cam_imu");
  }
  return k;
}

}  // namespace hapi_dataset
