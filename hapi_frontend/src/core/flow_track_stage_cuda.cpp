// The CUDA backend of ImageFlowTracker (flow_track_stage.hpp): FlowLkCuda
// behind the stage interface, converting OpenCV types to its plain ones.
#include "hapi_frontend/flow_track_stage.hpp"

#ifdef HAPI_FRONTEND_WITH_CUDA
#include "hapi_frontend/cuda/flow_lk_cuda.hpp"
#include "hapi_frontend/cuda/orb_cuda.hpp"  // cudaDeviceAvailable
#endif

namespace hapi_frontend {

#ifdef HAPI_FRONTEND_WITH_CUDA
namespace {

std::vector<cv::Point2f> points(const std::vector<float>& xy) {
  std::vector<cv::Point2f> out(xy.size() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = cv::Point2f(xy[2 * i], xy[2 * i + 1]);
  return out;
}

FlowLkCudaSettings settingsOf(const ImageFlowParams& p) {
  FlowLkCudaSettings s;
  s.levels = p.pyramid_levels;
  s.window = p.lk_window;
  s.iterations = p.lk_iterations;
  s.epsilon = p.lk_epsilon;
  s.max_features = p.max_features;
  s.quality = p.feature_quality;
  s.min_distance = p.min_feature_distance;
  return s;
}

class CudaFlowStage : public FlowTrackStage {
 public:
  explicit CudaFlowStage(const ImageFlowParams& p) : lk_(settingsOf(p)) {}

  void frame(const cv::Mat& window, const cv::Rect& search, bool track, FlowTracks* out) override {
    ImageView8 v;
    v.data = window.data;
    v.width = window.cols;
    v.height = window.rows;
    v.stride = static_cast<int>(window.step[0]);
    lk_.frame(v, search.x, search.y, search.width, search.height, track, &tracks_);
    out->from = points(tracks_.from);
    out->ahead = points(tracks_.ahead);
    out->back = points(tracks_.back);
    out->ok = tracks_.ok;
  }

  bool onGpu() const override { return true; }

 private:
  FlowLkCuda lk_;
  FlowLkTracks tracks_;
};

}  // namespace

std::unique_ptr<FlowTrackStage> makeCudaFlowStage(const ImageFlowParams& p, std::string* status) {
  std::string info;
  if (!cudaDeviceAvailable(&info)) {
    *status = "no usable CUDA device (" + info + ")";
    return nullptr;
  }
  try {
    auto stage = std::make_unique<CudaFlowStage>(p);
    *status = "CUDA on " + info;
    return stage;
  } catch (const std::exception& e) {
    *status = std::string("the CUDA stage failed to start (") + e.what() + ")";
    return nullptr;
  }
}
#else
std::unique_ptr<FlowTrackStage> makeCudaFlowStage(const ImageFlowParams&, std::string* status) {
  *status = "built without CUDA";
  return nullptr;
}
#endif

}  // namespace hapi_frontend
