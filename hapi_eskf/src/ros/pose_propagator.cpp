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

// The same step as Eskf::predictWithGyro (jacobians.hpp gyroStep), applied
// to the 12x12 pose covariance only.
Status PosePropagator::step(double stamp, const Vec3& gyro_camera, double sigma_gyro) {
  if (!valid_) return Status::kBackendUnavailable;
  if (!std::isfinite(stamp) || !gyro_camera.allFinite() || !std::isfinite(sigma_gyro)) return Status::kNonFinite;
  if (stamp < time_ || !(sigma_gyro > 0.0)) return Status::kInvalidArgument;
  const double dt = stamp - time_;
  if (dt == 0.0) return Status::kOk;
  PoseState next;
  Mat12 F, Q;
  gyroStep(pose_, gyro_camera, sigma_gyro, dt, settings_, &next, &F, &Q);
  const Mat12 C = F * C_ * F.transpose() + Q;
  C_ = 0.5 * (C + C.transpose());  // keep it exactly symmetric over many steps
  pose_ = next;
  time_ = stamp;
  return Status::kOk;
}

}  // namespace ros_glue
}  // namespace hapi_eskf
