#include "hapi_eskf/ros/pose_propagator.hpp"

#include "hapi_eskf/jacobians.hpp"

#include <cmath>

namespace hapi_eskf {
namespace ros_glue {

void PosePropagator::rebase(const PoseState& pose, const Mat12& covariance, double stamp) {
  pose_ = pose;
  C_ = covariance;
  time_ = stamp;
  valid_ = true;
}

// Mirrors Eskf::predictWithGyro (src/core/eskf.cpp): F = F_cv F_rep with
// F_rep = diag(I, I, I, 0) (w replaced by the measurement) and
// Q = F_cv Q_rep F_cv^T + Q_cv, Q_rep,ww = sigma^2 / dt.
Status PosePropagator::step(double stamp, const Vec3& gyro_camera, double sigma_gyro) {
  if (!valid_) return Status::kBackendUnavailable;
  if (!std::isfinite(stamp) || !gyro_camera.allFinite() || !std::isfinite(sigma_gyro)) return Status::kNonFinite;
  if (stamp < time_ || !(sigma_gyro > 0.0)) return Status::kInvalidArgument;
  const double dt = stamp - time_;
  if (dt == 0.0) return Status::kOk;
  PoseState x = pose_;
  x.w = gyro_camera;
  Mat12 F_rep = Mat12::Identity();
  F_rep.block<3, 3>(kIdxW, kIdxW).setZero();
  Mat12 Q_rep = Mat12::Zero();
  Q_rep.block<3, 3>(kIdxW, kIdxW).diagonal().setConstant(sigma_gyro * sigma_gyro / dt);
  const Mat12 F_cv = predictJacobian(x, dt, settings_);
  const Mat12 F = F_cv * F_rep;
  const Mat12 Q = F_cv * Q_rep * F_cv.transpose() + processNoise(dt, settings_);
  const Mat12 C = F * C_ * F.transpose() + Q;
  C_ = 0.5 * (C + C.transpose());  // keep it exactly symmetric over many steps
  pose_ = predictPose(x, dt, settings_);
  time_ = stamp;
  return Status::kOk;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
