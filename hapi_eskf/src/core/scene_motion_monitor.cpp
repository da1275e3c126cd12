// IMU / vision agreement (scene_motion_monitor.hpp).
#include "hapi_eskf/scene_motion_monitor.hpp"

#include <cmath>

namespace hapi_eskf {

void SceneMotionMonitor::addImu(const ImuSample& m) {
  recent_.push_back(m);
  while (!recent_.empty() && recent_.front().stamp < m.stamp - s_.alignment_window) recent_.pop_front();
}

bool SceneMotionMonitor::deviceStill() const {
  if (recent_.size() < 2) return false;
  Vec3 w = Vec3::Zero(), f = Vec3::Zero();
  for (const ImuSample& m : recent_) {
    w += m.gyro;
    f += m.accel;
  }
  const double n = static_cast<double>(recent_.size());
  w /= n;
  f /= n;
  double wv = 0.0, fv = 0.0;
  for (const ImuSample& m : recent_) {
    wv += (m.gyro - w).squaredNorm();
    fv += (m.accel - f).squaredNorm();
  }
  return std::sqrt(wv / n) < s_.static_gyro_threshold && std::sqrt(fv / n) < s_.static_accel_threshold;
}

SceneMotionVerdict SceneMotionMonitor::onFrame(double stamp, int fit_inliers, int inliers_gated_out) {
  SceneMotionVerdict v;
  if (!(s_.disagreement_fraction < 1.0) || fit_inliers <= 0) return v;
  v.device_still = deviceStill();
  v.disagreed = inliers_gated_out > s_.disagreement_fraction * fit_inliers;
  if (v.disagreed) last_disagreement_ = stamp;
  v.vision_leads = stamp - last_disagreement_ <= s_.disagreement_hold;
  return v;
}

void SceneMotionMonitor::reset() {
  recent_.clear();
  last_disagreement_ = -std::numeric_limits<double>::infinity();
}

}  // namespace hapi_eskf
