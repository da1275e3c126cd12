// CUDA ORB extractor with a CUDA-free C++ interface (no CUDA header needed by
// its users). It reproduces OrbCpuCore (orb_core.hpp) bit for bit: same
// integer pyramid and smoothing, FAST-9 score, strict 3x3 NMS, orb_rank_key
// order with per-level quotas, binned intensity-centroid orientation and
// steered BRIEF. Output order is the CPU's: level by level, rank order within
// a level. The identity is checked by hapi_frontend_gpu_test.
#pragma once

#include "hapi_frontend/orb_core.hpp"

#include <memory>
#include <string>

namespace hapi_frontend {

// True when a CUDA device can be used; `info` receives the device name or the
// reason why not (no driver, no device, ...). Never throws.
bool cudaDeviceAvailable(std::string* info = nullptr);

// GPU time of each stage of the last extract(), from CUDA events [ms]
// (all zero unless timing is enabled).
struct OrbCudaTimes {
  float upload_ms = 0.f;    // pinned host -> device copy of the image
  float pyramid_ms = 0.f;   // resize of levels 1.. + 5x5 smoothing of all levels
  float detect_ms = 0.f;    // FAST-9 score + 3x3 NMS + candidate compaction
  float select_ms = 0.f;    // radix sort of the rank keys (per-level quota = sorted prefix)
  float describe_ms = 0.f;  // orientation moments + angle bin + steered BRIEF
  float download_ms = 0.f;  // keypoints + descriptors + counts back to pinned host memory
  float total_ms = 0.f;     // first to last event
};

// One instance owns one CUDA stream, its device buffers and pinned host
// buffers; they are reused across frames and re-allocated only when the image
// size changes. Not thread-safe: use one instance per thread (e.g. left and
// right image extracted concurrently by two instances).
// Errors of the CUDA runtime throw std::runtime_error (the caller can fall
// back to the CPU core); invalid parameters throw std::invalid_argument.
class OrbCudaCore {
 public:
  explicit OrbCudaCore(const OrbParams& p = OrbParams());
  ~OrbCudaCore();
  OrbCudaCore(const OrbCudaCore&) = delete;
  OrbCudaCore& operator=(const OrbCudaCore&) = delete;

  OrbResult extract(const ImageView8& img);
  const OrbParams& params() const;

  // Per-stage event timing (a few microseconds of overhead per frame).
  void setTiming(bool on);
  const OrbCudaTimes& lastTimes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapi_frontend
