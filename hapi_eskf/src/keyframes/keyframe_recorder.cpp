// KeyframeRecorder (keyframe_recorder.hpp).
#include "hapi_eskf/keyframes/keyframe_recorder.hpp"

#include <cmath>

namespace hapi_eskf {

bool KeyframeRecorder::offer(const StereoFrame& frame, const Eigen::Isometry3d& T_world_cam,
                             const std::function<Mat6()>& pose_covariance) {
  if (frame.measurements.size() < s_.min_points) return false;
  std::lock_guard<std::mutex> lk(mu_);
  if (!kept_.empty()) {
    const Eigen::Isometry3d& last = kept_.back().T_map_cam;
    const double moved = (T_world_cam.translation() - last.translation()).norm();
    const double turned =
        Eigen::AngleAxisd(last.linear().transpose() * T_world_cam.linear()).angle() * 180.0 / M_PI;
    if (moved < s_.min_distance && turned < s_.min_angle_deg) return false;
  }
  if (kept_.size() >= s_.max_keyframes) {
    ++not_kept_full_;
    return false;
  }
  kept_.push_back(keyframeOf(next_id_++, frame, T_world_cam, pose_covariance()));
  return true;
}

std::vector<Keyframe> KeyframeRecorder::keyframes(const Eigen::Isometry3d& T_map_world) const {
  std::lock_guard<std::mutex> lk(mu_);
  std::vector<Keyframe> out = kept_;
  const Mat3 R = T_map_world.linear();
  for (Keyframe& k : out) {
    k.T_map_cam = T_map_world * k.T_map_cam;
    // Position rows and columns turn; the rotation error is on the right
    // (camera frame), unchanged by a change of world frame.
    Mat6 J = Mat6::Identity();
    J.topLeftCorner<3, 3>() = R;
    k.pose_covariance = J * k.pose_covariance * J.transpose();
  }
  return out;
}

std::size_t KeyframeRecorder::size() const {
  std::lock_guard<std::mutex> lk(mu_);
  return kept_.size();
}

std::size_t KeyframeRecorder::notKeptFull() const {
  std::lock_guard<std::mutex> lk(mu_);
  return not_kept_full_;
}

void KeyframeRecorder::clear() {
  std::lock_guard<std::mutex> lk(mu_);
  kept_.clear();
  not_kept_full_ = 0;
}

}  // namespace hapi_eskf
