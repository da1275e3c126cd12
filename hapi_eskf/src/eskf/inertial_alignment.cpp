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
  r.window = imuWindowStats(window.begin(), window.end(), Vec3::Zero());
  r.still = stillStart(r.window, s);
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
  if (!r.still) {
    // Moving: the mean specific force is gravity plus the mean acceleration
    // over the window, which the spread bounds; the gravity direction is
    // that uncertain (fast turns: metres per second squared, tens of degrees).
    const double sigma_g = std::max(s.initial_sigma_gravity, r.window.accel_spread);
    r.C.block<3, 3>(kIdxG, kIdxG) = Mat3::Identity() * sigma_g * sigma_g;
    r.x.v = q_wb * r.window.velocity_end;
  }
  if (r.still) {
    r.x.b_g = w_mean;
    // The mean's uncertainty, the larger of: the standard error of white
    // noise of density n over the span; the spread of the block means (slow
    // rotation left in the window, in-situ noise above the datasheet's; a
    // slow turn's mean over a fraction of its period is off by about that
    // much, so it is no standard error: not divided by sqrt(blocks)).
    const double span = window.back().stamp - window.front().stamp;
    const double sigma_bg = std::max(s.gyro_noise_density / std::sqrt(std::max(span, 1e-3)), r.window.gyro_block_spread);
    r.C.block<3, 3>(kIdxBg, kIdxBg) = Mat3::Identity() * sigma_bg * sigma_bg;
    r.C.block<3, 3>(kIdxV, kIdxV) = Mat3::Identity() * s.static_sigma_velocity * s.static_sigma_velocity;
  }
  *out = r;
  return Status::kOk;
}

bool stillStart(const ImuWindowStats& w, const EskfSettings& s) {
  const Vec3 turn_slope = -w.gyro_mean.cross(w.accel_mean);
  const bool fits_a_turn_better = turn_slope.norm() > 2.0 * w.accel_slope_sigma &&
                                  (w.accel_slope - turn_slope).norm() < w.accel_slope.norm();
  return w.samples >= 2 && w.velocity_rms < s.static_sigma_velocity && w.gyro_mean.norm() < s.static_gyro_threshold &&
         !fits_a_turn_better && std::abs(w.accel_mean.norm() - s.gravity_magnitude) < s.static_accel_threshold;
}

bool heldStill(const ImuWindowStats& w, const EskfSettings& s) {
  return w.samples >= 2 && w.gyro_rms < s.held_gyro_threshold && w.accel_spread < s.held_accel_threshold &&
         std::abs(w.accel_mean.norm() - s.gravity_magnitude) < s.held_accel_threshold;
}

}  // namespace hapi_eskf
