// The CameraInfo pair of an unrectified stereo rig, as ROS camera_calibration
// writes it: K and plumb_bob D unchanged, R1/R2/P1/P2 from cv::stereoRectify
// (alpha 0). See docs/DESIGN.md "Dataset calibration".
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

#include "hapi_dataset/asl_sensor.hpp"
#include "hapi_dataset/camera_info.hpp"

namespace hapi_dataset {

struct StereoCalibration {
  CameraInfoData left, right;
  Eigen::Isometry3d T_left_right = Eigen::Isometry3d::Identity();  // right camera pose in the left camera
  double baseline = 0;                                              // [m], |t_left_right|
};

// Throws std::invalid_argument when the two cameras differ in resolution or
// coincide (no baseline).
StereoCalibration rectifyStereo(const CameraSensor& left, const CameraSensor& right);

}  // namespace hapi_dataset
