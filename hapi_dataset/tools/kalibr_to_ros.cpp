// kalibr_to_ros: a Kalibr stereo (+ IMU) calibration into what the system
// reads (docs/CALIBRATION.md):
//   OUT/left.yaml, OUT/right.yaml  CameraInfo YAML (K, D unchanged; R, P of
//                                  the stereo rectification, as
//                                  cameracalibrator.py writes them) for the
//                                  drivers' camera_info_url
//   OUT/eskf_calibration.yaml      T_cam_imu (16 numbers) and imu_time_offset,
//                                  to load after config/eskf.yaml
//
//   kalibr_to_ros camchain-imucam.yaml OUT_DIR
#include "hapi_dataset/asl_sensor.hpp"
#include "hapi_dataset/camera_info.hpp"
#include "hapi_dataset/stereo_calibration.hpp"

#include <cstdio>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <iostream>
#include <string>

namespace {

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
  std::cout << "wrote " << path << "\n";
}

std::string eskfYaml(const hapi_dataset::KalibrCamchain& k) {
  std::string s = "# From Kalibr (kalibr_to_ros): the IMU in the left camera and the time shift.\nT_cam_imu: [";
  const Eigen::Matrix4d T = k.T_cam_imu.matrix();
  for (int i = 0; i < 16; ++i) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%s%.15g", i ? ", " : "", T(i / 4, i % 4));
    s += buf;
  }
  char buf[64];
  std::snprintf(buf, sizeof(buf), "]\nimu_time_offset: %.9g\n", k.timeshift_cam_imu);
  return s + buf;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: kalibr_to_ros camchain-imucam.yaml OUT_DIR\n";
    return 1;
  }
  try {
    const hapi_dataset::KalibrCamchain k = hapi_dataset::readKalibrCamchain(argv[1]);
    const hapi_dataset::StereoCalibration c = hapi_dataset::rectifyStereo(k.cam0, k.cam1);
    const std::string out = argv[2];
    writeFile(out + "/left.yaml", hapi_dataset::cameraInfoYaml(c.left, "left"));
    writeFile(out + "/right.yaml", hapi_dataset::cameraInfoYaml(c.right, "right"));
    std::cout << "baseline " << c.baseline << " m\n";
    if (k.has_imu) writeFile(out + "/eskf_calibration.yaml", eskfYaml(k));
    else std::cout << "no T_cam_imu in the file (a camchain without the IMU): eskf_calibration.yaml not written\n";
  } catch (const std::exception& e) {
    std::cerr << "kalibr_to_ros: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
