// IMU / vision agreement (scene_motion_monitor.hpp).
#include "hapi_eskf/eskf/scene_motion_monitor.hpp"

#include "hapi_eskf/eskf/inertial_alignment.hpp"

namespace hapi_eskf {

void SceneMotionMonitor::addImu(const ImuSample& m, const Vec3& gyro_bias) {
  recent_.push_back(m);
  gyro_bias_ = gyro_bias;
  while (!recent_.empty() && recent_.front().stamp < m.stamp - s_.alignment_window) recent_.pop_front();
}

SceneMotionVerdict SceneMotionMonitor::onFrame(int fit_inliers, int inliers_gated_out) const {
  SceneMotionVerdict v;
  if (!(s_.disagreement_fraction < 1.0) || fit_inliers <= 0) return v;
  v.device_still = heldStill(imuWindowStats(recent_.begin(), recent_.end(), gyro_bias_), s_);
  v.disagreed = inliers_gated_out > s_.disagreement_fraction * fit_inliers;
  return v;
}

void SceneMotionMonitor::reset() { recent_.clear(); }

}  // namespace hapi_eskf
