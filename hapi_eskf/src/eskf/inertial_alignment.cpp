// Gravity alignment of the inertial start (inertial_alignment.hpp).
#include "hapi_eskf/eskf/inertial_alignment.hpp"

#include <algorithm>
#include <cmath>

namespace hapi_eskf {

Status alignInertialStart(const std::vector<ImuSample>& window, const MotionModel& model, const EskfSettings& s,
                          InertialStart* out) {
  if (out == nullptr || window.size() < 2 || model.kind() != MotionModelKind::kInertial)
    return Status::kInvalidArgument;
  for (const ImuSample& m : window)
    if (!m.gyro.allFinite() || !m.accel.allFinite() || !std::isfinite(m.stamp)) return Status::kNonFinite;
  InertialStart r;
  r.window = imuWindowStats(window.begin(), window.end(), Vec3::Zero(), s.static_gyro_threshold,
                            s.static_accel_threshold, s);
  const Vec3 w_mean = r.window.gyro_mean, f_mean = r.window.accel_mean;
  // Below a quarter of g no direction is trustworthy.
  if (!(f_mean.norm() > 0.25 * s.gravity_magnitude)) return Status::kEmptyInput;

  // At rest the accelerometer reads -R_wb^T g = |g| R_wb^T z: R_wb takes the
  // mean specific force to +z.
  const Eigen::Quaterniond q_wb = Eigen::Quaterniond::FromTwoVectors(f_mean, Vec3::UnitZ());
  PoseState camera;
  camera.q = (q_wb * Eigen::Quaterniond(model.extrinsic().R_imu_cam)).normalized();
  camera.p = Vec3::Zero();
  r.x = model.fromCamera(camera);
  r.x.g = Vec3(0.0, 0.0, -s.gravity_magnitude);
  r.x.w = window.back().gyro;
  r.x.f = window.back().accel;
  r.x.has_imu = true;
  r.C = model.initialCovariance();
  const double span = window.back().stamp - window.front().stamp;
  if (!r.window.still) {
    // Moving: the mean specific force is gravity plus the mean acceleration
    // over the window, which the spread bounds; the gravity direction is
    // that uncertain (fast turns: metres per second squared, tens of degrees).
    const double sigma_g = std::max(s.initial_sigma_gravity, r.window.accel_spread);
    r.C.block<3, 3>(kIdxG, kIdxG) = Mat3::Identity() * sigma_g * sigma_g;
  }
  if (r.window.still) {
    r.x.b_g = w_mean;
    // Standard error of the mean of white noise of density n over the span.
    const double sigma_bg = s.gyro_noise_density / std::sqrt(std::max(span, 1e-3));
    r.C.block<3, 3>(kIdxBg, kIdxBg) = Mat3::Identity() * sigma_bg * sigma_bg;
    r.C.block<3, 3>(kIdxV, kIdxV) = Mat3::Identity() * s.static_sigma_velocity * s.static_sigma_velocity;
  }
  *out = r;
  return Status::kOk;
}

}  // namespace hapi_eskf
