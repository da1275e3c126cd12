// Keeps a session's keyframes for the map file (docs/DESIGN.md "Keyframes"):
// a filtered frame becomes a keyframe when the camera has moved min_distance
// or turned min_angle_deg since the last one kept, so the store covers the
// scanned area once rather than every frame of it. At max_keyframes the
// store is full and later frames are counted, not kept (the first pass over
// a skin area is the one a follow-up scan is placed against). Thread-safe:
// the filter thread offers frames, a ~save_map snapshot reads them.
#pragma once

#include "hapi_eskf/keyframes/keyframe.hpp"

#include <Eigen/Geometry>

#include <functional>
#include <mutex>
#include <vector>

namespace hapi_eskf {

struct KeyframeRecorderSettings {
  double min_distance = 0.02;        // [m] camera travel between keyframes
  double min_angle_deg = 10.0;       // [deg] camera turn between keyframes
  std::size_t max_keyframes = 1000;  // the store's size (relocalisation in ~35 ms at 1000, BENCHMARKS.md)
  std::size_t min_points = 12;       // a frame with fewer points cannot place a camera (KeyframeRelocaliser)
};

class KeyframeRecorder {
 public:
  explicit KeyframeRecorder(const KeyframeRecorderSettings& s = KeyframeRecorderSettings()) : s_(s) {}

  // The frame at camera pose T_world_cam is kept when it is far enough from
  // the last keyframe; only then is pose_covariance called (the covariance
  // of [dp, dtheta]: world position, rotation error on the right), since a
  // back end may have to read it back or solve for it. Returns whether the
  // frame was kept.
  bool offer(const StereoFrame& frame, const Eigen::Isometry3d& T_world_cam,
             const std::function<Mat6()>& pose_covariance);
  // The keyframes with their poses in another frame: T_map_world * pose
  // (the position rows of the covariance turn with it).
  std::vector<Keyframe> keyframes(const Eigen::Isometry3d& T_map_world) const;
  std::size_t size() const;
  std::size_t notKeptFull() const;  // keyframes due while the store was full
  void clear();  // a new timeline (filter reset)

 private:
  KeyframeRecorderSettings s_;
  mutable std::mutex mu_;
  std::vector<Keyframe> kept_;
  std::uint64_t next_id_ = 1;
  std::size_t not_kept_full_ = 0;
};

}  // namespace hapi_eskf
