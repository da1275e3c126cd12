// CUDA brute-force Hamming stereo matcher with a CUDA-free C++ interface. It
// takes exactly the inputs of stereo_match_core() and returns exactly its
// output (same candidates, same tie-breaking, same order): the contract is
// spelled out in stereo_match_core.hpp and checked by hapi_frontend_gpu_test.
#pragma once

#include "hapi_frontend/stereo_match_core.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace hapi_frontend {

// GPU time of each stage of the last match() [ms] (zero unless timing is on).
struct StereoMatchCudaTimes {
  float upload_ms = 0.f;    // descriptors + points, pinned host -> device
  float match_ms = 0.f;     // right-side best (cross-check) + left best/second + decision
  float download_ms = 0.f;  // per-left decision back to the host
  float total_ms = 0.f;
};

// One instance owns one CUDA stream and reuses its device/pinned buffers
// (grown on demand). Not thread-safe. CUDA runtime errors throw
// std::runtime_error; memory use is O(n_l + n_r) (no distance matrix).
class StereoMatchCuda {
 public:
  StereoMatchCuda();
  ~StereoMatchCuda();
  StereoMatchCuda(const StereoMatchCuda&) = delete;
  StereoMatchCuda& operator=(const StereoMatchCuda&) = delete;

  std::vector<MatchCoreResult> match(const uint8_t* desc_l, const float* pts_l, int n_l, const uint8_t* desc_r,
                                     const float* pts_r, int n_r, int desc_bytes, const double F[9],
                                     const MatchCoreParams& p);

  void setTiming(bool on);
  const StereoMatchCudaTimes& lastTimes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapi_frontend
