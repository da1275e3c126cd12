// The project's own ORB (OrbCpuCore, or the bit-identical OrbCudaCore when the
// library is built with CUDA and a device is present) as a FeatureExtractor.
#pragma once

#include "hapi_frontend/features.hpp"
#include "hapi_frontend/orb_core.hpp"

#include <memory>
#include <string>

namespace hapi_frontend {

// OrbResult -> FeatureSet: response = FAST score, octave = pyramid level,
// descriptors = n x 32 CV_8U (a copy, the FeatureSet owns its data).
FeatureSet orbResultToFeatureSet(const OrbResult& r);

class OrbExtractor : public FeatureExtractor {
 public:
  // use_gpu: try the CUDA core; without CUDA support in the build, without a
  // device, or if it fails at construction, the CPU core is used and
  // gpuStatus() says why.
  OrbExtractor(const OrbParams& p, bool use_gpu);
  ~OrbExtractor() override;
  // gray8 must be CV_8UC1 (any stride). A CUDA runtime error during extract()
  // switches this instance to the CPU core for good (reported by gpuStatus()).
  FeatureSet extract(const cv::Mat& gray8) override;
  std::string name() const override { return usingGpu() ? "orb_cuda" : "orb_cpu"; }
  bool usingGpu() const override;
  const std::string& gpuStatus() const { return gpu_status_; }

 private:
  struct GpuCore;  // hides the CUDA core type from users of this header
  OrbCpuCore cpu_;
  std::unique_ptr<GpuCore> gpu_;
  std::string gpu_status_;
};

}  // namespace hapi_frontend
