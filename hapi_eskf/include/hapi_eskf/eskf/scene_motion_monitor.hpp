// Watches whether IMU and vision agree (docs/DESIGN.md "Scene motion"). The
// HAPI device scans skin: when the subject moves while the device is held
// still, the IMU (correctly) reports no motion while every landmark moves in
// the images. The filter must then follow the camera relative to the
// surface, which is what motion compensation needs, instead of trusting the
// IMU prediction and gating all landmarks out. Per frame this looks at the
// map's rigid fit (RANSAC): when the gate around the IMU-predicted pose
// rejects more than disagreement_fraction of the fit's inliers, the map
// agrees with itself on a pose the prediction does not allow, and vision
// leads for that frame. The test is scale-free: it needs no
// distance threshold, only the covariances the gate already uses. Whether
// the device itself was still meanwhile (the last alignment_window of IMU
// samples, inertial_alignment.hpp imuWindowStats about the filter's gyro
// bias) tells "the scene moved" from "the prediction was wrong".
#pragma once

#include "hapi_eskf/eskf/motion_model.hpp"

#include <deque>

namespace hapi_eskf {

struct SceneMotionVerdict {
  bool disagreed = false;     // this frame's fit inliers were mostly gated out: vision leads
  bool device_still = false;  // the recent IMU samples say the device did not move
};

class SceneMotionMonitor {
 public:
  explicit SceneMotionMonitor(const EskfSettings& s) : s_(s) {}

  // Each sample the filter used, with its current gyro bias estimate.
  void addImu(const ImuSample& m, const Vec3& gyro_bias);
  // One frame with a fit of fit_inliers landmarks, of which the gate around
  // the prediction rejected inliers_gated_out.
  SceneMotionVerdict onFrame(int fit_inliers, int inliers_gated_out) const;
  void reset();

 private:

  EskfSettings s_;
  std::deque<ImuSample> recent_;  // the last alignment_window seconds
  Vec3 gyro_bias_ = Vec3::Zero();
};

}  // namespace hapi_eskf
