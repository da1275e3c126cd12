// CUDA stage of the image-flow tracker (docs/DESIGN.md "Image flow on the
// GPU"), with a CUDA-free interface: per frame the processed window is
// uploaded, its LK pyramid and Scharr derivatives are built on the device and
// kept there for the next frame, the previous frame's corners are tracked
// into it and back (one warp per point), and this frame's Shi-Tomasi corners
// are found for the next frame (eigenvalue map and candidates on the device,
// the ordered minimum-distance choice on the host). The arithmetic is
// flow_lk_math.hpp's, i.e. OpenCV's (buildOpticalFlowPyramid,
// calcOpticalFlowPyrLK, goodFeaturesToTrack), so both backends of
// ImageFlowTracker give the same tracks to rounding.
// CUDA runtime errors throw std::runtime_error; invalid settings throw
// std::invalid_argument. Not thread-safe: one instance per tracker.
#pragma once

#include "hapi_frontend/orb_core.hpp"  // ImageView8

#include <cstdint>
#include <memory>
#include <vector>

namespace hapi_frontend {

// The tracker's settings this stage uses (ImageFlowParams, where their
// defaults and ranges are declared; copied by flow_track_stage_cuda.cpp).
struct FlowLkCudaSettings {
  int levels = 0;           // LK pyramid levels (fewer where the window is small)
  int window = 0;           // [px] LK window side, odd, <= flow_lk::kMaxWindow
  int iterations = 0;       // per level
  double epsilon = 0;       // [px] LK stops when the update is smaller
  int max_features = 0;
  double quality = 0;       // weakest corner kept, relative to the strongest
  double min_distance = 0;  // [px]
};

// The previous frame's corners and where they went (window coordinates).
struct FlowLkTracks {
  std::vector<float> from, ahead, back;  // x, y interleaved
  std::vector<std::uint8_t> ok;          // forward and backward LK both succeeded
};

class FlowLkCuda {
 public:
  explicit FlowLkCuda(const FlowLkCudaSettings& s);
  ~FlowLkCuda();
  FlowLkCuda(const FlowLkCuda&) = delete;
  FlowLkCuda& operator=(const FlowLkCuda&) = delete;

  // One frame's window (8-bit, any stride); the corner square [sx, sx + sw) x
  // [sy, sy + sh) in window coordinates. With `track` (the previous frame's
  // window had the same size), *out receives the previous corners tracked
  // into this window and back; without, *out is left empty. Either way this
  // window becomes the previous one.
  void frame(const ImageView8& window, int sx, int sy, int sw, int sh, bool track, FlowLkTracks* out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hapi_frontend
