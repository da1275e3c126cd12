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
  bool finite() const;
};

// The same rigid motion seen by another camera fixed to the first:
// T_cam_other its pose in the first camera's frame. v' = R^T (v + w x p),
// w' = R^T w, the covariance through that linear map.
CameraOdometry toRigidlyAttached(const CameraOdometry& odom, const Eigen::Isometry3d& T_cam_other);

// The pose at t between two samples (a.t <= t <= b.t): position linear,
// rotation by slerp.
Eigen::Isometry3d interpolatePose(const CameraOdometry& a, const CameraOdometry& b, double t);
Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, double ta, const Eigen::Isometry3d& b, double tb,
                                  double t);

// The camera's motion from sample a to sample b integrated from their
// twists (T_a_b, b after a). The odometry's poses jump where the filter
// corrects them (at every stereo frame, about a millimetre); its twist does
// not integrate those jumps, so relative motion over a flow interval is
// taken from it (DESIGN "Surface motion", fusion).
Eigen::Isometry3d twistStep(const CameraOdometry& a, const CameraOdometry& b);

}  // namespace surface_motion
}  // namespace hapi_eskf
