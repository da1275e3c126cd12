// Host side of the CUDA stereo matcher: pinned staging (descriptor rows padded
// to 32-bit words), async copies on the instance's stream, two kernels, one
// small download, compaction in left-index order (rule 5).
#include "hapi_frontend/cuda/stereo_match_cuda.hpp"

#include "cuda_buffers.hpp"
#include "cuda_check.hpp"
#include "stereo_match_kernels.cuh"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace hapi_frontend {

using cuda_detail::DeviceBuffer;
using cuda_detail::PinnedBuffer;

struct StereoMatchCuda::Impl {
  cudaStream_t stream = nullptr;
  cudaEvent_t ev[4] = {};
  bool timing = false;
  StereoMatchCudaTimes times;
  // Layout of the one upload buffer: desc_l | desc_r | pts_l | pts_r (32-bit words).
  PinnedBuffer<uint32_t> h_in;
  PinnedBuffer<int> h_out;
  DeviceBuffer<uint32_t> d_in;
  DeviceBuffer<int> d_out;
  DeviceBuffer<unsigned long long> d_col;

  Impl() {
    HAPI_CUDA_CHECK(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
    for (auto& e : ev) HAPI_CUDA_CHECK(cudaEventCreate(&e));
  }
  ~Impl() {
    if (stream) cudaStreamSynchronize(stream);
    for (auto& e : ev)
      if (e) cudaEventDestroy(e);
    if (stream) cudaStreamDestroy(stream);
  }
  void mark(int i) {
    if (timing) HAPI_CUDA_CHECK(cudaEventRecord(ev[i], stream));
  }

  std::vector<MatchCoreResult> match(const uint8_t* desc_l, const float* pts_l, int n_l, const uint8_t* desc_r,
                                     const float* pts_r, int n_r, int desc_bytes, const double F[9],
                                     const MatchCoreParams& p) {
    std::vector<MatchCoreResult> out;
    if (n_l <= 0 || n_r <= 0 || desc_bytes <= 0) return out;
    if (desc_bytes > 128) throw std::invalid_argument("StereoMatchCuda: descriptors longer than 128 bytes");
    const int words = (desc_bytes + 3) / 4;
    const size_t dl_w = static_cast<size_t>(n_l) * words, dr_w = static_cast<size_t>(n_r) * words;
    const size_t total = dl_w + dr_w + 2 * static_cast<size_t>(n_l) + 2 * static_cast<size_t>(n_r);
    h_in.reserve(total);
    d_in.reserve(total);
    h_out.reserve(2 * static_cast<size_t>(n_l));
    d_out.reserve(2 * static_cast<size_t>(n_l));
    d_col.reserve(static_cast<size_t>(n_r));

    uint32_t* hw = h_in.get();
    auto stage = [&](uint32_t* dst, const uint8_t* src, int n) {
      if (desc_bytes == words * 4) {
        std::memcpy(dst, src, static_cast<size_t>(n) * desc_bytes);
      } else {
        std::memset(dst, 0, static_cast<size_t>(n) * words * 4);
        for (int r = 0; r < n; ++r)
          std::memcpy(reinterpret_cast<uint8_t*>(dst + static_cast<size_t>(r) * words),
                      src + static_cast<size_t>(r) * desc_bytes, desc_bytes);
      }
    };
    stage(hw, desc_l, n_l);
    stage(hw + dl_w, desc_r, n_r);
    std::memcpy(hw + dl_w + dr_w, pts_l, 2 * sizeof(float) * n_l);
    std::memcpy(hw + dl_w + dr_w + 2 * n_l, pts_r, 2 * sizeof(float) * n_r);

    match_cuda::MatchGeometry g;
    for (int k = 0; k < 9; ++k) g.F[k] = F[k];
    g.max_e2 = p.max_epipolar_px * p.max_epipolar_px;  // host double, same as the CPU core
    g.min_disparity = p.min_disparity;
    g.max_disparity = p.max_disparity;
    g.ratio = p.ratio;
    g.max_hamming = p.max_hamming;
    g.cross_check = p.cross_check ? 1 : 0;

    uint32_t* d = d_in.get();
    const uint32_t* ddl = d;
    const uint32_t* ddr = d + dl_w;
    const float* dpl = reinterpret_cast<const float*>(d + dl_w + dr_w);
    const float* dpr = dpl + 2 * n_l;
    mark(0);
    HAPI_CUDA_CHECK(cudaMemcpyAsync(d, hw, total * sizeof(uint32_t), cudaMemcpyHostToDevice, stream));
    mark(1);
    if (p.cross_check) {
      HAPI_CUDA_CHECK(cudaMemsetAsync(d_col.get(), 0xFF, n_r * sizeof(unsigned long long), stream));
      match_cuda::launchColumnBest(ddl, dpl, n_l, ddr, dpr, n_r, words, g, d_col.get(), stream);
    }
    match_cuda::launchRowDecide(ddl, dpl, n_l, ddr, dpr, n_r, words, g, d_col.get(), d_out.get(), d_out.get() + n_l,
                                stream);
    mark(2);
    HAPI_CUDA_CHECK(cudaMemcpyAsync(h_out.get(), d_out.get(), 2 * sizeof(int) * n_l, cudaMemcpyDeviceToHost, stream));
    mark(3);
    HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));
    if (timing) {
      HAPI_CUDA_CHECK(cudaEventElapsedTime(&times.upload_ms, ev[0], ev[1]));
      HAPI_CUDA_CHECK(cudaEventElapsedTime(&times.match_ms, ev[1], ev[2]));
      HAPI_CUDA_CHECK(cudaEventElapsedTime(&times.download_ms, ev[2], ev[3]));
      HAPI_CUDA_CHECK(cudaEventElapsedTime(&times.total_ms, ev[0], ev[3]));
    }
    const int* oj = h_out.get();
    const int* od = oj + n_l;
    for (int i = 0; i < n_l; ++i)
      if (oj[i] >= 0) out.push_back({i, oj[i], od[i]});
    return out;
  }
};

StereoMatchCuda::StereoMatchCuda() : impl_(new Impl()) {}
StereoMatchCuda::~StereoMatchCuda() = default;
std::vector<MatchCoreResult> StereoMatchCuda::match(const uint8_t* desc_l, const float* pts_l, int n_l,
                                                    const uint8_t* desc_r, const float* pts_r, int n_r, int desc_bytes,
                                                    const double F[9], const MatchCoreParams& p) {
  return impl_->match(desc_l, pts_l, n_l, desc_r, pts_r, n_r, desc_bytes, F, p);
}
void StereoMatchCuda::setTiming(bool on) { impl_->timing = on; }
const StereoMatchCudaTimes& StereoMatchCuda::lastTimes() const { return impl_->times; }

}  // namespace hapi_frontend
