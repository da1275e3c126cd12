// Frame changes between an ASL recording (body B = IMU, world W) and the
// frames the system uses (the left camera optical frame). One place for each
// rule; docs/DESIGN.md "Dataset calibration".
#pragma once

#include <Eigen/Geometry>

#include <cstdint>

#include <vector>

#include "hapi_dataset/asl_recording.hpp"
#include "hapi_dataset/asl_sensor.hpp"

namespace hapi_dataset {

// True left camera pose in the world: T_W_cam = T_W_B * T_BS(cam0).
Eigen::Isometry3d cameraInWorld(const Eigen::Isometry3d& T_W_B, const CameraSensor& cam0);

// IMU pose in the left camera frame (static TF stereo_left_optical_frame ->
// imu_link): T_cam_imu = T_BS(cam0)^-1 * T_BS(imu0).
Eigen::Isometry3d imuInCamera(const CameraSensor& cam0, const ImuSensor& imu0);

// True twist of the left camera in its own frame (nav_msgs/Odometry's twist
// convention: child frame) at ground-truth sample i. The body rate comes from
// the neighbouring orientations (central difference, one-sided at the ends),
// the camera velocity from the body's: v_cam = v_B + w x (R_WB t_BS).
// Requires at least two samples.
struct CameraTwist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   // [m/s]
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  // [rad/s]
};
CameraTwist cameraTwistAt(const std::vector<BodyPose>& ground_truth, size_t i, const CameraSensor& cam0);

// Integer nanoseconds -> (sec, nsec) without floating-point rounding.
struct SecNsec {
  uint32_t sec = 0, nsec = 0;
};
SecNsec toSecNsec(int64_t stamp_ns);

}  // namespace hapi_dataset
