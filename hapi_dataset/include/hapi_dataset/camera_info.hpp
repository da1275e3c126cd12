// sensor_msgs/CameraInfo without ROS (row-major K, R, P): what the ASL
// calibration conversion produces and what the simulator's rig writes, so
// both bag writers fill the message from one type.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace hapi_dataset {

struct CameraInfoData {
  int width = 0, height = 0;
  std::string distortion_model = "plumb_bob";
  std::vector<double> D;  // k1 k2 p1 p2 k3
  std::array<double, 9> K{};
  std::array<double, 9> R{};
  std::array<double, 12> P{};
};

// The CameraInfo YAML that camera_calibration_parsers reads (a driver's
// camera_info_url) and cameracalibrator.py writes.
std::string cameraInfoYaml(const CameraInfoData& info, const std::string& camera_name);

}  // namespace hapi_dataset
