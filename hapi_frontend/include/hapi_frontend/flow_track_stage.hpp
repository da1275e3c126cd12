// The backend of ImageFlowTracker (image_flow_tracker.hpp): per frame, the
// processed window's LK pyramid, the previous frame's corners tracked into
// it and back, and this frame's corners for the next frame. Two
// implementations with the same arithmetic (OpenCV's): the CPU stage calls
// OpenCV (buildOpticalFlowPyramid, calcOpticalFlowPyrLK,
// goodFeaturesToTrack), the CUDA stage runs flow_lk_math.hpp on the device
// and keeps the pyramid there (docs/DESIGN.md "Image flow on the GPU").
// Everything else (restarts, track checks, the affine fit) is the tracker's,
// written once.
#pragma once

#include "hapi_frontend/image_flow_params.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hapi_frontend {

// The previous frame's corners and where they went (window coordinates).
struct FlowTracks {
  std::vector<cv::Point2f> from, ahead, back;  // back: tracked back from `ahead`, started at `from`
  std::vector<std::uint8_t> ok;                // forward and backward LK both succeeded
};

class FlowTrackStage {
 public:
  virtual ~FlowTrackStage() = default;
  // window: this frame's processed window (CV_8UC1, may be a view of the
  // caller's image, which need not outlive the call); search: the corner
  // square in window coordinates. With `track` (the previous window had the
  // same size) *out receives the tracks, else it is left empty. Either way
  // the window becomes the previous one. A CUDA runtime error throws
  // std::runtime_error.
  virtual void frame(const cv::Mat& window, const cv::Rect& search, bool track, FlowTracks* out) = 0;
  virtual bool onGpu() const = 0;
};

std::unique_ptr<FlowTrackStage> makeCpuFlowStage(const ImageFlowParams& p);
// The CUDA stage, or null (with the reason in *status) when the build has no
// CUDA or no device can be used; *status names the device otherwise.
std::unique_ptr<FlowTrackStage> makeCudaFlowStage(const ImageFlowParams& p, std::string* status);

}  // namespace hapi_frontend
