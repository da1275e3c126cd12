#include "hapi_eskf/surface_motion/camera_odometry.hpp"

#include "hapi_eskf/so3.hpp"

#include <cmath>

namespace hapi_eskf {
namespace surface_motion {

bool CameraOdometry::valid() const {
  constexpr double kMaxPosition = 1e6, kMaxSpeed = 1e3, kMaxRate = 1e3;
  return std::isfinite(t) && T_world_cam.matrix().allFinite() && v.allFinite() && w.allFinite() &&
         twist_covariance.allFinite() && T_world_cam.translation().norm() < kMaxPosition && v.norm() < kMaxSpeed &&
         w.norm() < kMaxRate;
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

Eigen::Isometry3d interpolatePose(const CameraOdometry& a, const CameraOdometry& b, double t) {
  const double span = b.t - a.t;
  const double f = span > 0 ? (t - a.t) / span : 0.0;
  const Eigen::Quaterniond qa(a.T_world_cam.linear()), qb(b.T_world_cam.linear());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = qa.slerp(f, qb).toRotationMatrix();
  T.translation() = (1 - f) * a.T_world_cam.translation() + f * b.T_world_cam.translation();
  return T;
}

}  // namespace surface_motion
}  // namespace hapi_eskf
