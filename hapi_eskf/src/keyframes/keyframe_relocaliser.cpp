#include "hapi_eskf/keyframes/keyframe_relocaliser.hpp"

#include "hapi_eskf/backend/association.hpp"
#include "hapi_eskf/backend/descriptor_pool.hpp"

#include <algorithm>

namespace hapi_eskf {

bool KeyframeRelocaliser::add(Keyframe kf) {
  if (kf.descriptor_length <= 0 || kf.descriptors.size() != kf.size() * kf.descriptor_length ||
      kf.point_covariances.size() != kf.size())
    return false;
  if (!keyframes_.empty() && kf.descriptor_length != keyframes_.front().descriptor_length) return false;
  index_.add(keyframes_.size(), kf);
  keyframes_.push_back(std::move(kf));
  return true;
}

void KeyframeRelocaliser::clear() {
  keyframes_.clear();
  index_.clear();
}

std::optional<KeyframeFit> KeyframeRelocaliser::place(const StereoFrame& frame) const {
  if (keyframes_.empty() || frame.measurements.empty() ||
      frame.descriptor_length != keyframes_.front().descriptor_length)
    return std::nullopt;
  std::optional<KeyframeFit> best;
  for (const KeyframeVotes& c : index_.candidates(frame.descriptors.data(), frame.measurements.size(),
                                                  frame.descriptor_length, s_.candidates, s_.min_votes)) {
    const std::optional<KeyframeFit> fit = fitTo(frame, c.keyframe);
    if (fit && (!best || fit->inliers > best->inliers)) best = fit;
  }
  return best;
}

std::optional<KeyframeFit> KeyframeRelocaliser::fitTo(const StereoFrame& frame, std::size_t k) const {
  const Keyframe& kf = keyframes_[k];
  const int n = static_cast<int>(frame.measurements.size());
  std::vector<DescriptorMatch> matches(n);
  matchHamming(frame.descriptors.data(), n, kf.descriptors.data(), static_cast<int>(kf.size()),
               kf.descriptor_length, &matches);
  const Mat3 R_kf = kf.T_map_cam.linear();
  std::vector<Vec3> X, Z;
  std::vector<Mat3> W, Cz;
  for (int i = 0; i < n; ++i) {
    const DescriptorMatch& m = matches[i];
    if (!m.within(s_.max_hamming) || !m.distinct(s_.match_ratio)) continue;
    X.push_back(kf.T_map_cam * kf.points[m.best_slot]);
    Z.push_back(frame.measurements[i].z);
    W.push_back(R_kf * kf.point_covariances[m.best_slot] * R_kf.transpose());
    Cz.push_back(frame.measurements[i].Cz);
  }
  if (static_cast<int>(X.size()) < s_.min_inliers) return std::nullopt;
  KeyframeFit fit;
  fit.keyframe = k;
  fit.matches = static_cast<int>(X.size());
  Mat3 R;
  Vec3 t;
  const std::vector<char> inl = ransacRigidInliers(X, Z, W, Cz, s_.ransac_iterations, s_.gate_chi2, &R, &t);
  fit.inliers = static_cast<int>(std::count(inl.begin(), inl.end(), 1));
  if (fit.inliers < s_.min_inliers) return std::nullopt;
  fit.T_map_cam.linear() = R;
  fit.T_map_cam.translation() = t;
  return fit;
}

}  // namespace hapi_eskf
