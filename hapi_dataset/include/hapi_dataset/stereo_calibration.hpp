// The CameraInfo pair of an unrectified stereo rig, as ROS camera_calibration
// writes it: K and plumb_bob D unchanged, R1/R2/P1/P2 from cv::stereoRectify
// (alpha 0). See docs/DESIGN.md "Dataset calibration".
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

#include "hapi_dataset/asl_sensor.hpp"

namespace hapi_dataset {

// sensor_msgs/CameraInfo without ROS (row-major K, R, P).
struct CameraInfoData {
  int width = 0, height = 0;
  std::string distortion_model = "plumb_bob";
  std::vector<double> D;  // k1 k2 p1 p2 k3
  std::array<double, 9> K{};
  std::array<double, 9> R{};
  std::array<double, 12> P{};
};

struct StereoCalibration {
  CameraInfoData left, right;
  Eigen::Isometry3d T_left_right = Eigen::Isometry3d::Identity();  // right camera pose in the left camera
  double baseline = 0;                                              // [m], |t_left_right|
};

// Throws std::invalid_argument when the two cameras differ in resolution or
// coincide (no baseline).
StereoCalibration rectifyStereo(const CameraSensor& left, const CameraSensor& right);

}  // namespace hapi_dataset
