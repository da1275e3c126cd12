#include "hapi_frontend/cpu_stereo_matcher.hpp"

#ifdef HAPI_FRONTEND_WITH_CUDA
#include "hapi_frontend/cuda/orb_cuda.hpp"
#include "hapi_frontend/cuda/stereo_match_cuda.hpp"
#endif

#include <stdexcept>

namespace hapi_frontend {

MatchCoreParams toMatchCoreParams(const StereoMatchParams& p) {
  MatchCoreParams c;
  c.max_epipolar_px = p.max_epipolar_px;
  c.min_disparity = p.min_disparity;
  c.max_disparity = p.max_disparity;
  c.ratio = p.ratio;
  c.max_hamming = p.max_hamming;
  c.cross_check = p.cross_check;
  return c;
}

namespace {
// Contiguous float copy of the points and a continuous descriptor block.
bool flatten(const FeatureSet& fs, const std::vector<Eigen::Vector2d>& pts, std::vector<float>* xy, cv::Mat* desc) {
  const int n = static_cast<int>(fs.keypoints.size());
  if (static_cast<int>(pts.size()) != n || fs.descriptors.rows != n || (n > 0 && fs.descriptors.type() != CV_8U))
    return false;
  xy->resize(2 * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    (*xy)[2 * i] = static_cast<float>(pts[i].x());
    (*xy)[2 * i + 1] = static_cast<float>(pts[i].y());
  }
  *desc = fs.descriptors.isContinuous() ? fs.descriptors : fs.descriptors.clone();
  return true;
}

// Shared by the CPU and CUDA adapters: validated flat inputs for the core.
struct FlatInputs {
  std::vector<float> xl, xr;
  cv::Mat dl, dr;
  double f[9];
  bool ok = false;
};
FlatInputs makeFlat(const FeatureSet& left, const std::vector<Eigen::Vector2d>& left_undist, const FeatureSet& right,
                    const std::vector<Eigen::Vector2d>& right_undist, const Eigen::Matrix3d& F) {
  FlatInputs in;
  if (!flatten(left, left_undist, &in.xl, &in.dl) || !flatten(right, right_undist, &in.xr, &in.dr)) return in;
  if (in.dl.rows == 0 || in.dr.rows == 0 || in.dl.cols != in.dr.cols) return in;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) in.f[3 * r + c] = F(r, c);
  in.ok = true;
  return in;
}

std::vector<StereoMatch> toStereoMatches(const std::vector<MatchCoreResult>& m) {
  std::vector<StereoMatch> out;
  out.reserve(m.size());
  for (const auto& r : m) out.push_back({r.left, r.right, r.distance});
  return out;
}
}  // namespace

std::vector<StereoMatch> CpuStereoMatcher::match(const FeatureSet& left, const std::vector<Eigen::Vector2d>& left_undist,
                                                 const FeatureSet& right,
                                                 const std::vector<Eigen::Vector2d>& right_undist,
                                                 const Eigen::Matrix3d& F, const StereoMatchParams& params) {
  const FlatInputs in = makeFlat(left, left_undist, right, right_undist, F);
  if (!in.ok) return {};
  return toStereoMatches(stereo_match_core(in.dl.data, in.xl.data(), in.dl.rows, in.dr.data, in.xr.data(),
                                           in.dr.rows, in.dl.cols, in.f, toMatchCoreParams(params)));
}

#ifdef HAPI_FRONTEND_WITH_CUDA
namespace {
class CudaStereoMatcher : public StereoMatcher {
 public:
  std::vector<StereoMatch> match(const FeatureSet& left, const std::vector<Eigen::Vector2d>& left_undist,
                                 const FeatureSet& right, const std::vector<Eigen::Vector2d>& right_undist,
                                 const Eigen::Matrix3d& F, const StereoMatchParams& params) override {
    if (gpu_) {
      const FlatInputs in = makeFlat(left, left_undist, right, right_undist, F);
      if (!in.ok) return {};
      try {
        return toStereoMatches(gpu_->match(in.dl.data, in.xl.data(), in.dl.rows, in.dr.data, in.xr.data(),
                                           in.dr.rows, in.dl.cols, in.f, toMatchCoreParams(params)));
      } catch (const std::runtime_error&) {
        gpu_.reset();  // same results from the CPU core from now on
      }
    }
    return cpu_.match(left, left_undist, right, right_undist, F, params);
  }
  std::string name() const override { return gpu_ ? "cuda_bruteforce_hamming" : cpu_.name(); }
  bool usingGpu() const override { return gpu_ != nullptr; }
  std::unique_ptr<StereoMatchCuda> gpu_ = std::make_unique<StereoMatchCuda>();

 private:
  CpuStereoMatcher cpu_;
};
}  // namespace
#endif

std::unique_ptr<StereoMatcher> makeStereoMatcher(bool use_gpu, std::string* status) {
  std::string st = use_gpu ? "built without CUDA, CPU matcher" : "CPU matcher";
#ifdef HAPI_FRONTEND_WITH_CUDA
  std::string info;
  if (use_gpu && cudaDeviceAvailable(&info)) {
    try {
      auto m = std::make_unique<CudaStereoMatcher>();
      if (status) *status = "CUDA matcher on " + info;
      return m;
    } catch (const std::exception& e) {
      st = std::string("CUDA matcher failed (") + e.what() + "), CPU matcher";
    }
  } else if (use_gpu) {
    st = "no usable CUDA device (" + info + "), CPU matcher";
  }
#endif
  if (status) *status = st;
  return std::make_unique<CpuStereoMatcher>();
}

}  // namespace hapi_frontend
