// One gyro-driven prediction step: argument checks, the step of the motion
// model with w replaced by the gyro (jacobians.hpp gyroStep, docs/DESIGN.md
// "Gyro prediction") and the commit of the new pose and time. Eskf::predictWithGyro
// (covariance in the backend) and the nodelet's IMU-rate PosePropagator (its
// own 12 x 12 pose covariance) both run this one path, so the copy cannot
// step or reject differently from the filter.
#pragma once

#include "hapi_eskf/jacobians.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <cmath>

namespace hapi_eskf {

// Steps *pose from *time to `stamp` with the gyro sample (camera-frame rate
// [rad/s], noise density sigma_gyro [rad/s/sqrt(Hz)]). The covariance part is
// the caller's: apply(F, Q) must propagate it and return its Status.
// kNonFinite, kInvalidArgument (stamp before *time, sigma_gyro <= 0) or the
// Status of apply(); on any error *pose and *time are unchanged. stamp ==
// *time is a no-op (kOk, apply not called).
template <typename ApplyCovariance>
Status predictWithGyroStep(PoseState* pose, double* time, double stamp, const Vec3& gyro_camera, double sigma_gyro,
                           const EskfSettings& settings, ApplyCovariance&& apply) {
  if (!std::isfinite(stamp) || !gyro_camera.allFinite() || !std::isfinite(sigma_gyro)) return Status::kNonFinite;
  if (stamp < *time || !(sigma_gyro > 0.0)) return Status::kInvalidArgument;
  const double dt = stamp - *time;
  if (dt == 0.0) return Status::kOk;
  PoseState next;
  Mat12 F, Q;
  gyroStep(*pose, gyro_camera, sigma_gyro, dt, settings, &next, &F, &Q);
  const Status st = apply(F, Q);
  if (st != Status::kOk) return st;
  *pose = next;
  *time = stamp;
  return Status::kOk;
}

}  // namespace hapi_eskf
