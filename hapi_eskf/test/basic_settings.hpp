// Settings of the basic filter iteration that the unit tests pin down: the
// defaults (settings.hpp, the tuned values of config/eskf.yaml) with the
// tuned extras switched off, i.e. no RANSAC before gating, no bootstrap batch,
// no relocalisation after a gap, C_z as the front end gives it and no
// frame-shared vision error and no online calibration (the pose block is the
// motion model's 12, 15 or 18 rows). A test's
// expected counts and bounds then depend on the basic iteration only; the
// tests of an extra switch it on themselves.
#pragma once

#include "hapi_eskf/settings.hpp"

namespace hapi_eskf {
namespace testing_settings {

inline EskfSettings basicFilter() {
  EskfSettings s;
  s.ransac_iterations = 0;
  s.bootstrap_landmarks = 0;
  s.relocalise_gap = 0.0;
  s.measurement_angular_sigma = 0.0;
  s.frame_rotation_sigma = 0.0;
  s.frame_optical_axis_sigma = 0.0;
  s.frame_translation_sigma = 0.0;
  s.calib_cam_extrinsics = false;
  s.calib_cam_timeoffset = false;
  return s;
}

// The inertial filter of the analytic-trajectory runs (inertial_scenario.hpp):
// a small pool and RANSAC with the IMU / vision agreement check.
inline EskfSettings inertialTrajectoryFilter() {
  EskfSettings s = basicFilter();
  s.motion_model = MotionModelKind::kInertial;
  s.max_landmarks = 300;
  s.max_new_landmarks = 30;
  s.max_update_landmarks = 60;
  s.ransac_iterations = 200;
  s.initial_sigma_accel_bias = 0.1;
  return s;
}

}  // namespace testing_settings
}  // namespace hapi_eskf
