#include "hapi_eskf/surface_motion/camera_odometry.hpp"

#include "hapi_eskf/so3.hpp"

#include <cmath>

namespace hapi_eskf {
namespace surface_motion {

bool CameraOdometry::finite() const {
  return std::isfinite(t) && T_world_cam.matrix().allFinite() && v.allFinite() && w.allFinite() &&
         twist_covariance.allFinite();
}

CameraOdometry toRigidlyAttached(const CameraOdometry& odom, const Eigen::Isometry3d& T_cam_other) {
  const Mat3 Rt = T_cam_other.linear().transpose();
  const Vec3 p = T_cam_other.translation();
  CameraOdometry out = odom;
  out.T_world_cam = odom.T_world_cam * T_cam_other;
  out.v = Rt * (odom.v + odom.w.cross(p));
  out.w = Rt * odom.w;
  Mat6 M = Mat6::Zero();
  M.block<3, 3>(0, 0) = Rt;
  M.block<3, 3>(0, 3) = -Rt * skew(p);
  M.block<3, 3>(3, 3) = Rt;
  out.twist_covariance = M * odom.twist_covariance * M.transpose();
  return out;
}

Eigen::Isometry3d interpolatePose(const Eigen::Isometry3d& a, double ta, const Eigen::Isometry3d& b, double tb,
                                  double t) {
  const double span = tb - ta;
  const double f = span > 0 ? (t - ta) / span : 0.0;
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = qa.slerp(f, qb).toRotationMatrix();
  T.translation() = (1 - f) * a.translation() + f * b.translation();
  return T;
}

Eigen::Isometry3d interpolatePose(const CameraOdometry& a, const CameraOdometry& b, double t) {
  return interpolatePose(a.T_world_cam, a.t, b.T_world_cam, b.t, t);
}

Eigen::Isometry3d twistStep(const CameraOdometry& a, const CameraOdometry& b) {
  // The mean of the two samples' twists, each in its own camera frame: the
  // frames differ by a rotation of w dt, a second-order effect over an
  // odometry interval.
  const double dt = b.t - a.t;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = expSO3(0.5 * (a.w + b.w) * dt);
  T.translation() = 0.5 * (a.v + b.v) * dt;
  return T;
}

}  // namespace surface_motion
}  // namespace hapi_eskf
