// Pinhole camera + lens distortion (plumb_bob / rational_polynomial) and the
// stereo rig built from two ROS-style calibrations. ROS-free: the nodelet
// copies CameraInfo fields into CameraCalib.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace hapi_frontend {

// Mirror of the sensor_msgs/CameraInfo fields we use.
struct CameraCalib {
  int width = 0, height = 0;
  std::string distortion_model = "plumb_bob";
  std::vector<double> D;
  std::array<double, 9> K{};
  std::array<double, 9> R{{1, 0, 0, 0, 1, 0, 0, 0, 1}};
  std::array<double, 12> P{};
  // Empty string when usable, else a human-readable reason (zero K, bad model...).
  std::string validate() const;
};

// The fields of anything shaped like sensor_msgs/CameraInfo (the message, the
// simulator's and the dataset reader's CameraInfoData): size, model, D, K,
// R, P, copied as they are. Checks are the caller's (validate(), the
// nodelet's toCalib).
template <typename Info>
CameraCalib copyCameraInfo(const Info& info) {
  CameraCalib c;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.distortion_model = info.distortion_model;
  c.D.assign(info.D.begin(), info.D.end());
  std::copy(info.K.begin(), info.K.end(), c.K.begin());
  std::copy(info.R.begin(), info.R.end(), c.R.begin());
  std::copy(info.P.begin(), info.P.end(), c.P.begin());
  return c;
}

// Maps observed keypoints to undistorted pixels expressed with this camera's K
// (the convention of hapi_msgs/StereoLandmark). Only keypoints are undistorted,
// never images: a few hundred points cost microseconds.
class CameraModel {
 public:
  // rectified_input: images are already rectified, so K := P[0:3,0:3], no distortion.
  CameraModel(const CameraCalib& calib, bool rectified_input);
  std::vector<Eigen::Vector2d> undistort(const std::vector<cv::Point2f>& px) const;
  Eigen::Vector2d distort(const Eigen::Vector2d& undist_px) const;  // inverse, for tests
  const Eigen::Matrix3d& K() const { return K_; }

 private:
  cv::Mat Kcv_, Dcv_;
  Eigen::Matrix3d K_;
};

// Extrinsics: p_left = R_lr * p_right + t_lr. From a ROS stereo calibration the
// rectifying rotations R_l, R_r and P_right(0,3) = -fx*B give
// R_lr = R_l^T R_r, t_lr = R_l^T [B,0,0]^T. For rectified input R_l = R_r = I.
struct StereoRig {
  Eigen::Matrix3d R_lr = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_lr = Eigen::Vector3d::Zero();
  static StereoRig fromCalib(const CameraCalib& left, const CameraCalib& right, bool rectified_input);
  // F with l_right = F * [x_l; 1] between undistorted pixel coordinates.
  Eigen::Matrix3d fundamental(const Eigen::Matrix3d& K_l, const Eigen::Matrix3d& K_r) const;
};

}  // namespace hapi_frontend
