// CPU StereoMatcher: adapts FeatureSets to the plain matching core
// (stereo_match_core.hpp), whose semantics the CUDA matcher reproduces.
#pragma once

#include "hapi_frontend/features.hpp"
#include "hapi_frontend/stereo_match_core.hpp"

namespace hapi_frontend {

MatchCoreParams toMatchCoreParams(const StereoMatchParams& p);

class CpuStereoMatcher : public StereoMatcher {
 public:
  // Both descriptor matrices must be CV_8U with the same number of columns
  // and one row per keypoint; otherwise no match is returned.
  std::vector<StereoMatch> match(const FeatureSet& left, const std::vector<Eigen::Vector2d>& left_undist,
                                 const FeatureSet& right, const std::vector<Eigen::Vector2d>& right_undist,
                                 const Eigen::Matrix3d& F, const StereoMatchParams& params) override;
  std::string name() const override { return "cpu_bruteforce_hamming"; }
};

}  // namespace hapi_frontend
