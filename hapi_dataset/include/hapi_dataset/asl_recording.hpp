// One ASL/EuRoC recording folder (mav0/): the stereo image lists of cam0 and
// cam1, the IMU samples of imu0, the optional ground truth of
// state_groundtruth_estimate0 and an optional scene description (scene.yaml,
// not part of EuRoC: the surfaces of a simulated scene, passed on verbatim).
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

#include "hapi_dataset/asl_sensor.hpp"

namespace hapi_dataset {

struct StereoFrame {
  int64_t stamp_ns = 0;
  std::string left_png, right_png;  // absolute paths
};

// imu0/data.csv: w_RS_S [rad/s], a_RS_S [m/s^2] in the IMU frame.
struct ImuSample {
  int64_t stamp_ns = 0;
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();
};

// state_groundtruth_estimate0/data.csv: the body pose in the world
// (p_RS_R, q_RS as w, x, y, z) and the body velocity in the world.
struct BodyPose {
  int64_t stamp_ns = 0;
  Eigen::Isometry3d T_W_B = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();  // [m/s]
};

struct AslRecording {
  std::string mav0;  // folder read
  CameraSensor cam0, cam1;
  ImuSensor imu0;
  std::vector<StereoFrame> frames;      // stamps present in both cameras, increasing
  std::vector<ImuSample> imu;           // increasing stamps
  std::vector<BodyPose> ground_truth;   // empty when the folder has none
  std::string scene_yaml;               // mav0/scene.yaml verbatim, empty when absent
};

// `folder` is mav0 itself or a folder holding mav0/. Throws std::runtime_error
// naming what is missing or malformed. Rows with stamps out of order are an
// error (a dataset that needs sorting is not what it claims to be).
AslRecording readAslRecording(const std::string& folder);

// The mav0 folder of `folder` (itself or folder/mav0), empty when neither has cam0/.
std::string findMav0(const std::string& folder);

}  // namespace hapi_dataset
