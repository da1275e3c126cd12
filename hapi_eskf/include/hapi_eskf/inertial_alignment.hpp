// The inertial model's start (docs/DESIGN.md "Inertial initialisation"): the
// IMU samples of the first alignment_window seconds give the direction of
// gravity, so the filter's world (the published map frame) is gravity-aligned,
// z up (REP-103); its origin is the first camera position and its yaw the
// smallest rotation that levels the body.
//  * Still start (the spread of both the gyro and the accelerometer over the
//    window below static_gyro_threshold / static_accel_threshold): the mean
//    gyro is the gyro bias (1 sigma: its standard error), the velocity is
//    zero with static_sigma_velocity.
//  * Moving start: the mean specific force still points up to within the
//    mean acceleration over the window (a hand's motion averages out); the
//    gyro bias starts at zero (initial_sigma_gyro_bias) and the velocity at
//    zero with initial_sigma_velocity: the first visual updates determine it,
//    since the landmarks' apparent motion measures the camera's velocity.
// Either way the gravity vector stays a state with initial_sigma_gravity per
// component (the tilt's uncertainty, mostly the unknown accelerometer bias).
#pragma once

#include "hapi_eskf/motion_model.hpp"
#include "hapi_eskf/status.hpp"

#include <vector>

namespace hapi_eskf {

struct InertialStart {
  NominalState x;  // at the stamp of the window's last sample
  PoseMat C;       // 18 x 18
  bool still = false;
  double gyro_spread = 0.0, accel_spread = 0.0;  // RMS deviation from the mean [rad/s], [m/s^2]
  double specific_force = 0.0;                   // |mean accelerometer| [m/s^2]
};

// `window`: increasing stamps, at least 2 samples; the model must be the
// inertial one. kInvalidArgument otherwise, kNonFinite for a non-finite
// sample, kEmptyInput when the mean specific force is too small to give a
// direction (free fall, a dead accelerometer).
Status alignInertialStart(const std::vector<ImuSample>& window, const MotionModel& model, const EskfSettings& s,
                          InertialStart* out);

}  // namespace hapi_eskf
