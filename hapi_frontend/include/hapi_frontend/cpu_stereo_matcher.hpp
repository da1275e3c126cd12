// CPU StereoMatcher: adapts FeatureSets to the plain matching core
// (stereo_match_core.hpp), whose semantics the CUDA matcher reproduces.
#pragma once

#include "hapi_frontend/features.hpp"
#include "hapi_frontend/stereo_match_core.hpp"

#include <memory>
#include <string>

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
  bool usingGpu() const override { return false; }
};

// use_gpu: the CUDA matcher (StereoMatchCuda, same output as the CPU one) when
// the library is built with CUDA and a device is usable, else the CPU matcher.
// A CUDA runtime error during match() falls back to the CPU core for good.
// status (optional) says which one and why.
std::unique_ptr<StereoMatcher> makeStereoMatcher(bool use_gpu, std::string* status = nullptr);

}  // namespace hapi_frontend
