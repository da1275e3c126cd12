// One IMU-rate odometry sample of a camera (the ESKF's ~odom: the camera's
// pose in the world and its twist in its own frame), and its change of
// camera by a rigid extrinsic (docs/DESIGN.md "Surface motion").
#pragma once

#include "hapi_eskf/types.hpp"

namespace hapi_eskf {
namespace surface_motion {

struct CameraOdometry {
  double t = 0;                                        // [s]
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();             // camera frame [m/s, rad/s]
  Mat6 twist_covariance = Mat6::Zero();                // of (v, w)
  // Finite and physically possible (|p| < 1e6 m, |v| < 1e3 m/s, |w| < 1e3
  // rad/s, a finite covariance): what the estimator accepts.
  bool valid() const;
};

// The same rigid motion seen by another camera fixed to the first:
// T_cam_other its pose in the first camera's frame. v' = R^T (v + w x p),
// w' = R^T w, the covariance through that linear map.
CameraOdometry toRigidlyAttached(const CameraOdometry& odom, const Eigen::Isometry3d& T_cam_other);

// The pose at t between two samples (a.t <= t <= b.t): position linear,
// rotation by slerp.
Eigen::Isometry3d interpolatePose(const CameraOdometry& a, const CameraOdometry& b, double t);

}  // namespace surface_motion
}  // namespace hapi_eskf
