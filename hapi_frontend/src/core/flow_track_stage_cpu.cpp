// The CPU backend of ImageFlowTracker (flow_track_stage.hpp): OpenCV's
// pyramidal LK and Shi-Tomasi corners.
#include "hapi_frontend/flow_track_stage.hpp"

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <utility>

namespace hapi_frontend {
namespace {

class CpuFlowStage : public FlowTrackStage {
 public:
  explicit CpuFlowStage(const ImageFlowParams& p)
      : p_(p),
        win_(p.lk_window, p.lk_window),
        stop_(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, p.lk_iterations, p.lk_epsilon) {}

  void frame(const cv::Mat& window, const cv::Rect& search, bool track, FlowTracks* out) override {
    *out = FlowTracks{};
    std::vector<cv::Mat> pyramid;
    // Never reuse the input as level 0 (tryReuseInputImage = false): the
    // pyramid outlives this call, the caller's buffer (a message) need not.
    cv::buildOpticalFlowPyramid(window, pyramid, win_, p_.pyramid_levels - 1, true, cv::BORDER_REFLECT_101,
                                cv::BORDER_CONSTANT, false);
    if (track && !corners_.empty()) trackInto(pyramid, out);
    previous_ = std::move(pyramid);
    corners_.clear();
    // goodFeaturesToTrack needs a block (3 px) inside the square. The square
    // is a view of the window: its Sobel sees the pixels about it.
    if (search.width >= 3 && search.height >= 3) {
      cv::goodFeaturesToTrack(window(search), corners_, p_.max_features, p_.feature_quality, p_.min_feature_distance);
      for (cv::Point2f& c : corners_) c += cv::Point2f(search.tl());
    }
  }

  bool onGpu() const override { return false; }

 private:
  void trackInto(const std::vector<cv::Mat>& pyramid, FlowTracks* out) const {
    const int max_level = p_.pyramid_levels - 1;
    std::vector<std::uint8_t> ok_ahead, ok_back;
    std::vector<float> err;
    out->from = corners_;
    cv::calcOpticalFlowPyrLK(previous_, pyramid, corners_, out->ahead, ok_ahead, err, win_, max_level, stop_);
    // Backwards from where each corner landed, started at its origin.
    out->back = corners_;
    cv::calcOpticalFlowPyrLK(pyramid, previous_, out->ahead, out->back, ok_back, err, win_, max_level, stop_,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    out->ok.resize(corners_.size());
    for (std::size_t i = 0; i < corners_.size(); ++i) out->ok[i] = ok_ahead[i] && ok_back[i];
  }

  ImageFlowParams p_;
  cv::Size win_;
  cv::TermCriteria stop_;
  std::vector<cv::Mat> previous_;
  std::vector<cv::Point2f> corners_;  // the previous window's
};

}  // namespace

std::unique_ptr<FlowTrackStage> makeCpuFlowStage(const ImageFlowParams& p) { return std::make_unique<CpuFlowStage>(p); }

}  // namespace hapi_frontend
