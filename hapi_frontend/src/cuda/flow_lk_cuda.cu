// Host side of the CUDA image-flow stage (flow_lk_cuda.hpp): buffers, the
// two device pyramids (this frame's and the previous one's, swapped each
// frame), the stream order and the corner choice.
#include "hapi_frontend/cuda/flow_lk_cuda.hpp"

#include "cuda_buffers.hpp"
#include "cuda_check.hpp"
#include "flow_lk_kernels.cuh"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace hapi_frontend {

using cuda_detail::DeviceBuffer;
using cuda_detail::PinnedBuffer;
using flow_lk::Candidate;
using flow_lk::Level;

namespace {

// One frame's LK pyramid on the device.
struct DevicePyramid {
  DeviceBuffer<std::uint8_t> img;
  DeviceBuffer<std::int16_t> deriv;
  Level levels[flow_lk::kMaxLevels];
};

}  // namespace

struct FlowLkCuda::Impl {
  FlowLkCudaSettings s;
  flow_lk::LkSettings lk;
  cudaStream_t stream = nullptr;
  int width = -1, height = -1, n_levels = 0;
  DevicePyramid pyr[2];
  int cur = 0;                       // pyr[cur] receives this frame
  DeviceBuffer<Level> d_levels;      // pyr[0].levels then pyr[1].levels
  DeviceBuffer<float> d_eig, d_from, d_ahead, d_back;
  DeviceBuffer<unsigned int> d_max;
  DeviceBuffer<int> d_count;
  DeviceBuffer<Candidate> d_cand;
  DeviceBuffer<std::uint8_t> d_ok_ahead, d_ok_back;
  DeviceBuffer<std::int16_t> d_scratch;
  PinnedBuffer<std::uint8_t> h_img, h_ok;
  PinnedBuffer<float> h_pts;         // ahead + back, down
  PinnedBuffer<float> h_up;          // the corners for the next frame, up
  PinnedBuffer<int> h_count;
  PinnedBuffer<Candidate> h_cand;
  std::vector<float> corners;        // the previous frame's, window coordinates
  std::vector<Candidate> candidates;

  explicit Impl(const FlowLkCudaSettings& settings) : s(settings) {
    if (s.levels < 1 || s.levels > flow_lk::kMaxLevels)
      throw std::invalid_argument("FlowLkCuda: levels must be in [1, " + std::to_string(flow_lk::kMaxLevels) + "]");
    if (s.window < 3 || s.window > flow_lk::kMaxWindow || s.window % 2 == 0)
      throw std::invalid_argument("FlowLkCuda: window must be odd and in [3, " + std::to_string(flow_lk::kMaxWindow) +
                                  "]");
    if (s.max_features < 1 || s.iterations < 1)
      throw std::invalid_argument("FlowLkCuda: max_features and iterations must be >= 1");
    lk.window = s.window;
    // calcOpticalFlowPyrLK's limits of its termination criteria.
    lk.iterations = std::min(s.iterations, 100);
    const double eps = std::min(std::max(s.epsilon, 0.0), 10.0);
    lk.epsilon_sq = eps * eps;
    HAPI_CUDA_CHECK(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
    const std::size_t n = static_cast<std::size_t>(s.max_features);
    d_from.reserve(2 * n);
    d_ahead.reserve(2 * n);
    d_back.reserve(2 * n);
    d_ok_ahead.reserve(n);
    d_ok_back.reserve(n);
    d_scratch.reserve(n * 3 * s.window * s.window);
    d_max.reserve(1);
    d_count.reserve(1);
    d_levels.reserve(2 * flow_lk::kMaxLevels);
    h_pts.reserve(4 * n);
    h_up.reserve(2 * n);
    h_ok.reserve(2 * n);
    h_count.reserve(1);
  }

  ~Impl() {
    if (stream) {
      cudaStreamSynchronize(stream);
      cudaStreamDestroy(stream);
    }
  }

  // Buffers and level descriptors for windows of w x h.
  void configure(int w, int h) {
    width = w;
    height = h;
    n_levels = flow_lk::pyramidLevels(w, h, s.window, s.levels);
    lk.max_level = n_levels - 1;
    std::size_t total = 0;
    int lw = w, lh = h;
    for (int l = 0; l < n_levels; ++l, lw = (lw + 1) / 2, lh = (lh + 1) / 2) total += static_cast<std::size_t>(lw) * lh;
    Level host[2 * flow_lk::kMaxLevels] = {};
    for (int p = 0; p < 2; ++p) {
      pyr[p].img.reserve(total);
      pyr[p].deriv.reserve(2 * total);
      std::size_t off = 0;
      lw = w;
      lh = h;
      for (int l = 0; l < n_levels; ++l, lw = (lw + 1) / 2, lh = (lh + 1) / 2) {
        Level& L = pyr[p].levels[l];
        L.img = pyr[p].img.get() + off;
        L.deriv = pyr[p].deriv.get() + 2 * off;
        L.width = lw;
        L.height = lh;
        host[p * flow_lk::kMaxLevels + l] = L;
        off += static_cast<std::size_t>(lw) * lh;
      }
    }
    HAPI_CUDA_CHECK(
        cudaMemcpyAsync(d_levels.get(), host, sizeof(host), cudaMemcpyHostToDevice, stream));
    h_img.reserve(static_cast<std::size_t>(w) * h);
    HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));  // `host` leaves scope
    corners.clear();
  }

  void buildPyramid(const ImageView8& window) {
    std::uint8_t* hi = h_img.get();
    for (int y = 0; y < height; ++y)
      std::memcpy(hi + static_cast<std::size_t>(y) * width, window.data + static_cast<std::size_t>(y) * window.stride,
                  width);
    DevicePyramid& P = pyr[cur];
    HAPI_CUDA_CHECK(cudaMemcpyAsync(P.img.get(), hi, static_cast<std::size_t>(width) * height, cudaMemcpyHostToDevice,
                                    stream));
    for (int l = 0; l < n_levels; ++l) {
      const Level& L = P.levels[l];
      if (l > 0) {
        const Level& B = P.levels[l - 1];
        flow_lk_cuda::launchPyrDown(B.img, B.width, B.height, const_cast<std::uint8_t*>(L.img), L.width, L.height,
                                    stream);
      }
      flow_lk_cuda::launchScharr(L.img, L.width, L.height, const_cast<std::int16_t*>(L.deriv), stream);
    }
  }

  // Forward from the previous pyramid into this one, then back from where
  // each corner landed, started at its origin (calcOpticalFlowPyrLK with
  // OPTFLOW_USE_INITIAL_FLOW); results to pinned memory (not yet waited for).
  void launchTracks(int n) {
    const Level* prev = d_levels.get() + (cur ^ 1) * flow_lk::kMaxLevels;
    const Level* next = d_levels.get() + cur * flow_lk::kMaxLevels;
    const std::size_t bytes = 2 * sizeof(float) * n;
    flow_lk_cuda::launchTrack(prev, next, lk, d_from.get(), d_ahead.get(), false, d_ok_ahead.get(), n,
                              d_scratch.get(), stream);
    HAPI_CUDA_CHECK(cudaMemcpyAsync(d_back.get(), d_from.get(), bytes, cudaMemcpyDeviceToDevice, stream));
    flow_lk_cuda::launchTrack(next, prev, lk, d_ahead.get(), d_back.get(), true, d_ok_back.get(), n, d_scratch.get(),
                              stream);
    HAPI_CUDA_CHECK(cudaMemcpyAsync(h_pts.get(), d_ahead.get(), bytes, cudaMemcpyDeviceToHost, stream));
    HAPI_CUDA_CHECK(cudaMemcpyAsync(h_pts.get() + 2 * n, d_back.get(), bytes, cudaMemcpyDeviceToHost, stream));
    HAPI_CUDA_CHECK(cudaMemcpyAsync(h_ok.get(), d_ok_ahead.get(), n, cudaMemcpyDeviceToHost, stream));
    HAPI_CUDA_CHECK(cudaMemcpyAsync(h_ok.get() + n, d_ok_back.get(), n, cudaMemcpyDeviceToHost, stream));
  }

  // This frame's corners (goodFeaturesToTrack on the square) into
  // `corners`, uploaded for the next frame's tracking. Waits for the stream.
  void findCorners(int sx, int sy, int sw, int sh) {
    std::vector<float> found;
    if (sw >= 3 && sh >= 3) {  // as the CPU stage: a 3 px block must fit
      const std::size_t area = static_cast<std::size_t>(sw) * sh;
      d_eig.reserve(area);
      d_cand.reserve(area);
      h_cand.reserve(area);
      HAPI_CUDA_CHECK(cudaMemsetAsync(d_max.get(), 0, sizeof(unsigned int), stream));
      HAPI_CUDA_CHECK(cudaMemsetAsync(d_count.get(), 0, sizeof(int), stream));
      flow_lk_cuda::launchMinEigen(pyr[cur].levels[0].img, width, height, sx, sy, sw, sh, d_eig.get(), d_max.get(),
                                   stream);
      flow_lk_cuda::launchCandidates(d_eig.get(), sw, sh, d_max.get(), s.quality, d_cand.get(), d_count.get(), stream);
      HAPI_CUDA_CHECK(cudaMemcpyAsync(h_count.get(), d_count.get(), sizeof(int), cudaMemcpyDeviceToHost, stream));
      HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));
      const int n = *h_count.get();
      if (n > 0) {
        HAPI_CUDA_CHECK(
            cudaMemcpyAsync(h_cand.get(), d_cand.get(), sizeof(Candidate) * n, cudaMemcpyDeviceToHost, stream));
        HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));
      }
      candidates.assign(h_cand.get(), h_cand.get() + n);
      flow_lk::selectCorners(&candidates, sw, s.max_features, s.min_distance, &found);
      for (std::size_t k = 0; k < found.size(); k += 2) {
        found[k] += static_cast<float>(sx);
        found[k + 1] += static_cast<float>(sy);
      }
    } else {
      HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));
    }
    corners.swap(found);
    if (!corners.empty()) {
      // Staged in pinned memory that nothing reads until the next frame,
      // whose first wait comes after this copy in the stream.
      std::copy(corners.begin(), corners.end(), h_up.get());
      HAPI_CUDA_CHECK(cudaMemcpyAsync(d_from.get(), h_up.get(), sizeof(float) * corners.size(),
                                      cudaMemcpyHostToDevice, stream));
    }
  }
};

FlowLkCuda::FlowLkCuda(const FlowLkCudaSettings& s) : impl_(std::make_unique<Impl>(s)) {}
FlowLkCuda::~FlowLkCuda() = default;

void FlowLkCuda::frame(const ImageView8& window, int sx, int sy, int sw, int sh, bool track, FlowLkTracks* out) {
  Impl& m = *impl_;
  if (!window.data || window.width < 1 || window.height < 1 || window.stride < window.width)
    throw std::invalid_argument("FlowLkCuda: empty or malformed window");
  if (sx < 0 || sy < 0 || sw < 0 || sh < 0 || sx + sw > window.width || sy + sh > window.height)
    throw std::invalid_argument("FlowLkCuda: the corner square leaves the window");
  out->from.clear();
  out->ahead.clear();
  out->back.clear();
  out->ok.clear();
  if (window.width != m.width || window.height != m.height) {
    if (track) throw std::invalid_argument("FlowLkCuda: tracking across a change of the window size");
    m.configure(window.width, window.height);
  }
  m.buildPyramid(window);
  const int n = track ? static_cast<int>(m.corners.size() / 2) : 0;
  if (n > 0) m.launchTracks(n);
  const std::vector<float> tracked = n > 0 ? m.corners : std::vector<float>();
  m.findCorners(sx, sy, sw, sh);  // waits for the tracks too
  if (n > 0) {
    out->from = tracked;
    out->ahead.assign(m.h_pts.get(), m.h_pts.get() + 2 * n);
    out->back.assign(m.h_pts.get() + 2 * n, m.h_pts.get() + 4 * n);
    out->ok.resize(n);
    for (int i = 0; i < n; ++i) out->ok[i] = m.h_ok.get()[i] && m.h_ok.get()[n + i];
  }
  m.cur ^= 1;
}

}  // namespace hapi_frontend
