// ImageFlowTracker: the image-flow measurement of the imaging camera
// (docs/DESIGN.md "Surface motion: image flow"). For each grey frame: the
// Shi-Tomasi corners of the previous frame within search_radius of the pixel
// (u, v) are tracked into this frame by pyramidal Lucas-Kanade, kept when
// tracking back lands within fb_threshold of where they started, and the
// local affine flow about (u, v) is fitted to their displacements
// (affine_flow_fit.hpp): hapi_msgs/ImageFlow's six parameters [px/frame]
// with their covariance. Only a window of the image about the pixel is ever
// processed. Each frame's pyramid and corners are kept for the next frame.
// The pyramid, corners and LK run in a backend (flow_track_stage.hpp): the
// CPU (OpenCV) or, with use_gpu, CUDA, which falls back to the CPU with its
// reason in backendStatus() when no device can be used.
// ROS-free (OpenCV imgproc + video).
#pragma once

#include "hapi_frontend/affine_flow_fit.hpp"
#include "hapi_frontend/flow_track_stage.hpp"
#include "hapi_frontend/image_flow_params.hpp"
#include "hapi_frontend/input_error.hpp"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hapi_frontend {

// The values of hapi_msgs/ImageFlow's status.
enum class FlowStatus : std::uint8_t { kOk = 0, kTooFewFeatures = 1, kFirstFrame = 2 };

struct ImageFlowResult {
  FlowStatus status = FlowStatus::kFirstFrame;
  std::int64_t stamp_ns = 0;
  // The frame the flow is from; with kFirstFrame the frame before this one
  // (0 at the start), which the flow does not connect to.
  std::int64_t previous_stamp_ns = 0;
  double u = 0, v = 0;  // [px] the pixel the flow is about
  Eigen::Matrix<double, 6, 1> affine = Eigen::Matrix<double, 6, 1>::Zero();      // [px/frame, 1/frame]
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  // zero unless kOk
  std::uint32_t inliers = 0, tracked = 0;
  std::uint32_t consistent = 0;  // tracks that passed the forward-backward check (inliers <= consistent <= tracked)
  double sigma = 0;  // [px] residual sigma of the fit (kOk)
  // kFirstFrame: why ("start", "stamp_not_increasing", "gap", "size_changed",
  // "gpu_failed": the CUDA backend failed at run time, the CPU took over).
  std::string restart_reason;
};

class ImageFlowTracker {
 public:
  // Throws std::invalid_argument with ImageFlowParams::validate()'s text.
  explicit ImageFlowTracker(const ImageFlowParams& params);
  ~ImageFlowTracker();

  // One frame (CV_8UC1, any size >= 1 x 1) stamped stamp_ns (mid-exposure).
  // A stamp not after the previous one, or more than max_gap after it,
  // restarts: the result is kFirstFrame, as for the first frame. An error
  // (not 8-bit grey: "malformed_image"; the pixel outside the image:
  // "pixel_outside_image"; another size than the previous frame:
  // "size_changed") leaves *out with kFirstFrame; after a size change the
  // tracker restarts from this frame, otherwise the frame is ignored.
  InputError process(const cv::Mat& grey, std::int64_t stamp_ns, ImageFlowResult* out);

  // Forgets the previous frame: the next one is a first frame.
  void reset() { have_previous_ = false; }

  const ImageFlowParams& params() const { return params_; }
  // True while the CUDA backend runs; backendStatus() says which backend
  // runs and, where use_gpu is set but the CPU runs, why.
  bool usingGpu() const { return stage_->onGpu(); }
  const std::string& backendStatus() const { return backend_status_; }

 private:
  // Sets roi_ and pixel_ for frames of this size; false when the pixel is
  // outside such a frame.
  bool layoutFor(const cv::Size& size);
  // The checked tracks' affine fit into *out.
  void fit(const FlowTracks& tracks, ImageFlowResult* out) const;
  // Covariance factor for the overlap of the inliers' LK windows.
  double overlapInflation(const std::vector<Eigen::Vector2d>& from, const std::vector<bool>& inlier) const;

  ImageFlowParams params_;
  AffineFitSettings fit_;
  std::unique_ptr<FlowTrackStage> stage_;
  std::string backend_status_;
  cv::Size size_;            // of the frames the layout is for
  cv::Rect roi_;             // the processed window of the image
  cv::Rect search_;          // the corner search square, in roi_ coordinates
  Eigen::Vector2d pixel_;    // (u, v) in image coordinates
  bool have_layout_ = false;
  bool have_previous_ = false;
  std::int64_t previous_stamp_ns_ = 0;
};

}  // namespace hapi_frontend
