// The inertial model's start (docs/DESIGN.md "Inertial initialisation"): the
// IMU samples of the first alignment_window seconds give the direction of
// gravity, so the filter's world (the published map frame) is gravity-aligned,
// z up (REP-103); its origin is the first camera position and its yaw the
// smallest rotation that levels the body.
//  * Still start (imuWindowStats below): the mean gyro is the gyro bias (1
//    sigma: its standard error), the velocity is zero with
//    static_sigma_velocity.
//  * Moving start: the mean specific force still points up to within the
//    mean acceleration over the window (a hand's motion averages out), so
//    gravity gets a 1 sigma of the accelerometer's spread over the window
//    when that exceeds initial_sigma_gravity; the gyro bias starts at zero
//    (initial_sigma_gyro_bias) and the velocity at zero with
//    initial_sigma_velocity: the first visual updates determine them, since
//    the landmarks' apparent motion measures the camera's velocity and tilt.
// Either way the gravity vector stays a state with initial_sigma_gravity per
// component (the tilt's uncertainty, mostly the unknown accelerometer bias).
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/status.hpp"

#include <cmath>
#include <vector>

namespace hapi_eskf {

// A window of IMU samples: means, and whether the device was still. Still
// means all three: the gyro's RMS about gyro_bias below gyro_threshold
// (a steady turn has no spread, so the spread alone would call it still and
// take the turn rate for a bias), the accelerometer's RMS deviation from its
// mean below accel_threshold, and the mean specific force within
// accel_threshold of gravity_magnitude (no steady acceleration). The
// alignment (static_*_threshold: a bias estimate needs a device at rest) and
// the scene-motion check (held_*_threshold: a hand holding the device still
// still trembles) use this one rule.
struct ImuWindowStats {
  Vec3 gyro_mean = Vec3::Zero(), accel_mean = Vec3::Zero();
  double gyro_rms = 0.0;      // about the bias [rad/s]
  double accel_spread = 0.0;  // RMS deviation from the mean [m/s^2]
  bool still = false;
};
template <typename Iterator>
ImuWindowStats imuWindowStats(Iterator begin, Iterator end, const Vec3& gyro_bias, double gyro_threshold,
                              double accel_threshold, const EskfSettings& s);

struct InertialStart {
  NominalState x;  // at the stamp of the window's last sample
  PoseMat C;       // 18 x 18
  ImuWindowStats window;  // the alignment window, about a zero gyro bias (window.still: a still start)
};

// `window`: increasing stamps, at least 2 samples; the model must be the
// inertial one. kInvalidArgument otherwise, kNonFinite for a non-finite
// sample, kEmptyInput when the mean specific force is too small to give a
// direction (free fall, a dead accelerometer).
Status alignInertialStart(const std::vector<ImuSample>& window, const MotionModel& model, const EskfSettings& s,
                          InertialStart* out);

template <typename Iterator>
ImuWindowStats imuWindowStats(Iterator begin, Iterator end, const Vec3& gyro_bias, double gyro_threshold,
                              double accel_threshold, const EskfSettings& s) {
  ImuWindowStats r;
  double n = 0.0, w2 = 0.0;
  for (Iterator it = begin; it != end; ++it) {
    r.gyro_mean += it->gyro;
    r.accel_mean += it->accel;
    w2 += (it->gyro - gyro_bias).squaredNorm();
    n += 1.0;
  }
  if (n < 2.0) return r;
  r.gyro_mean /= n;
  r.accel_mean /= n;
  double f2 = 0.0;
  for (Iterator it = begin; it != end; ++it) f2 += (it->accel - r.accel_mean).squaredNorm();
  r.gyro_rms = std::sqrt(w2 / n);
  r.accel_spread = std::sqrt(f2 / n);
  r.still = r.gyro_rms < gyro_threshold && r.accel_spread < accel_threshold &&
            std::abs(r.accel_mean.norm() - s.gravity_magnitude) < accel_threshold;
  return r;
}

}  // namespace hapi_eskf
