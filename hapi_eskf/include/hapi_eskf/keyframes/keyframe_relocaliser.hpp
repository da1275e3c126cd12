// Places a camera in a map of keyframes with no pose hint (docs/DESIGN.md
// "Keyframes"): the index's candidates, then per candidate the Hamming
// matches of the frame's descriptors to the keyframe's (best within
// max_hamming and clearly better than the second, as the association's
// ratio test) and a RANSAC rigid fit of the frame's points onto the
// keyframe's points in the map frame (ransacRigidInliers, association.hpp).
// The fit with the most inliers, at least min_inliers, places the camera.
#pragma once

#include "hapi_eskf/keyframes/keyframe.hpp"
#include "hapi_eskf/keyframes/keyframe_index.hpp"

#include <optional>
#include <vector>

namespace hapi_eskf {

struct KeyframeRelocaliserSettings {
  std::size_t candidates = 5;  // keyframes tried, most votes first
  int min_votes = 8;           // a candidate needs this many word votes
  int max_hamming = 64;        // bits, of a 256-bit descriptor
  double match_ratio = 0.8;    // best < ratio * second best
  int ransac_iterations = 200;
  double gate_chi2 = 11.34;    // 3 dof, 99 %
  int min_inliers = 12;
};

struct KeyframeFit {
  std::size_t keyframe = 0;  // index of the keyframe that placed it
  Eigen::Isometry3d T_map_cam = Eigen::Isometry3d::Identity();
  int inliers = 0;
  int matches = 0;
};

class KeyframeRelocaliser {
 public:
  explicit KeyframeRelocaliser(const KeyframeRelocaliserSettings& s = KeyframeRelocaliserSettings()) : s_(s) {}

  // Keeps a keyframe (its descriptor length must be the store's; false
  // otherwise, nothing kept).
  bool add(Keyframe kf);
  void clear();
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }

  // The camera of `frame` in the map frame, or nothing.
  std::optional<KeyframeFit> place(const StereoFrame& frame) const;

 private:
  std::optional<KeyframeFit> fitTo(const StereoFrame& frame, std::size_t k) const;

  KeyframeRelocaliserSettings s_;
  std::vector<Keyframe> keyframes_;
  KeyframeIndex index_;
};

}  // namespace hapi_eskf
