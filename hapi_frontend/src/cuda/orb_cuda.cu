// Host side of the CUDA ORB: buffer management, stream orchestration, event
// timing and conversion to OrbResult. The level plan, resize tables, patterns
// and keypoint finalisation are the CPU functions themselves (orb_core.hpp),
// so both paths share every table by construction.
#include "hapi_frontend/cuda/orb_cuda.hpp"

#include "cuda_buffers.hpp"
#include "cuda_check.hpp"
#include "orb_kernels.cuh"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace hapi_frontend {

using cuda_detail::DeviceBuffer;
using cuda_detail::PinnedBuffer;
using orb_cuda::KeypointDev;
using orb_cuda::LevelDev;

namespace {
constexpr int kMinEdge = 19;  // same clamp as OrbCpuCore (BRIEF samples reach 18 px)
constexpr int kMaxCoord = 1 << 20;  // x and y have 20 bits in orb_rank_key
}  // namespace

struct OrbCudaCore::Impl {
  OrbParams p;
  bool timing = false;
  OrbCudaTimes times;
  cudaStream_t stream = nullptr;
  cudaEvent_t ev[7] = {};

  // Size-dependent state, rebuilt by configure() when the image size changes.
  int width = -1, height = -1;
  OrbLevelPlan plan;
  int n_levels = 0, edge = kMinEdge, quota_total = 0, end_bit = orb_cuda::kRankKeyBits;
  std::vector<size_t> level_off;              // offset of each level in img/smooth
  std::vector<size_t> key_base;               // first key slot of each level
  std::vector<size_t> table_off;              // xi,xw,yi,yw of level l>0 at table_off[l]
  std::vector<bool> detectable;               // level large enough for the border
  size_t key_cap = 0, sort_bytes = 0;

  DeviceBuffer<uint8_t> d_img, d_smooth, d_score, d_desc;
  DeviceBuffer<uint16_t> d_tmp;
  DeviceBuffer<int> d_tables, d_counts;
  DeviceBuffer<unsigned long long> d_keys, d_sorted;
  DeviceBuffer<unsigned char> d_sort_temp;
  DeviceBuffer<LevelDev> d_levels;
  DeviceBuffer<int8_t> d_patterns;
  DeviceBuffer<KeypointDev> d_kp;
  PinnedBuffer<uint8_t> h_img, h_desc;
  PinnedBuffer<KeypointDev> h_kp;
  PinnedBuffer<int> h_counts;

  explicit Impl(const OrbParams& params) : p(params) {
    if (p.n_features < 0) throw std::invalid_argument("OrbCudaCore: n_features must be >= 0");
    if (!(p.scale_factor > 1.f)) throw std::invalid_argument("OrbCudaCore: scale_factor must be > 1");
    if (p.fast_threshold < 0 || p.fast_threshold > 254)
      throw std::invalid_argument("OrbCudaCore: fast_threshold must be in [0, 254]");
    HAPI_CUDA_CHECK(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
    for (auto& e : ev) HAPI_CUDA_CHECK(cudaEventCreate(&e));
    const size_t pat_bytes = static_cast<size_t>(kOrbAngleBins) * 256 * 4;
    d_patterns.reserve(pat_bytes);
    // On our own stream and synchronised: a plain cudaMemcpy runs on the legacy
    // stream, which a non-blocking stream does not wait for.
    HAPI_CUDA_CHECK(
        cudaMemcpyAsync(d_patterns.get(), orb_rotated_patterns(), pat_bytes, cudaMemcpyHostToDevice, stream));
    HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));
  }

  ~Impl() {
    if (stream) cudaStreamSynchronize(stream);
    for (auto& e : ev)
      if (e) cudaEventDestroy(e);
    if (stream) cudaStreamDestroy(stream);
  }

  void configure(int w, int h) {
    if (w == width && h == height) return;
    if (w >= kMaxCoord || h >= kMaxCoord) throw std::invalid_argument("OrbCudaCore: image larger than 2^20 px");
    HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));
    plan = orb_plan_levels(w, h, p);
    n_levels = static_cast<int>(plan.width.size());
    edge = std::max(p.edge, kMinEdge);
    level_off.assign(n_levels + 1, 0);
    key_base.assign(n_levels + 1, 0);
    table_off.assign(n_levels, 0);
    detectable.assign(n_levels, false);
    std::vector<int> tables;
    std::vector<LevelDev> lv(n_levels);
    quota_total = 0;
    for (int l = 0; l < n_levels; ++l) {
      const int W = plan.width[l], H = plan.height[l];
      level_off[l + 1] = level_off[l] + static_cast<size_t>(W) * H;
      // Same skip rule as the CPU: no scoring when the border eats the level.
      detectable[l] = !(W <= 2 * edge + 2 || H <= 2 * edge + 2);
      // A strict 3x3 maximum has no 8-neighbour maximum: at most one per 2x2 cell.
      const size_t cap = detectable[l] ? static_cast<size_t>((W - 2 * edge + 1) / 2) * ((H - 2 * edge + 1) / 2) : 0;
      key_base[l + 1] = key_base[l] + cap;
      if (l > 0) {
        std::vector<int> xi, xw, yi, yw;
        orb_resize_table(plan.width[l - 1], W, xi, xw);
        orb_resize_table(plan.height[l - 1], H, yi, yw);
        table_off[l] = tables.size();
        tables.insert(tables.end(), xi.begin(), xi.end());
        tables.insert(tables.end(), xw.begin(), xw.end());
        tables.insert(tables.end(), yi.begin(), yi.end());
        tables.insert(tables.end(), yw.begin(), yw.end());
      }
      lv[l].width = W;
      lv[l].height = H;
      lv[l].quota = plan.quota[l];
      lv[l].qstart = quota_total;
      quota_total += plan.quota[l];
    }
    key_cap = key_base[n_levels];
    int level_bits = 1;
    while ((1 << level_bits) - 1 < n_levels) ++level_bits;  // all-ones level field = sentinel
    end_bit = orb_cuda::kRankKeyBits + level_bits;
    if (end_bit > 64) throw std::invalid_argument("OrbCudaCore: too many pyramid levels");

    const size_t npx = std::max<size_t>(level_off[n_levels], 1);
    d_img.reserve(npx);
    d_smooth.reserve(npx);
    d_score.reserve(static_cast<size_t>(w) * h);
    d_tmp.reserve(static_cast<size_t>(w) * h);
    d_tables.reserve(std::max<size_t>(tables.size(), 1));
    d_counts.reserve(n_levels);
    d_keys.reserve(std::max<size_t>(key_cap, 1));
    d_sorted.reserve(std::max<size_t>(key_cap, 1));
    sort_bytes = key_cap ? orb_cuda::sortTempBytes(static_cast<int>(key_cap), end_bit) : 0;
    d_sort_temp.reserve(std::max<size_t>(sort_bytes, 1));
    d_levels.reserve(n_levels);
    d_kp.reserve(std::max(quota_total, 1));
    d_desc.reserve(static_cast<size_t>(std::max(quota_total, 1)) * kOrbDescBytes);
    h_img.reserve(static_cast<size_t>(w) * h);
    h_kp.reserve(std::max(quota_total, 1));
    h_desc.reserve(static_cast<size_t>(std::max(quota_total, 1)) * kOrbDescBytes);
    h_counts.reserve(n_levels);
    for (int l = 0; l < n_levels; ++l) {
      lv[l].img = d_img.get() + level_off[l];
      lv[l].smooth = d_smooth.get() + level_off[l];
    }
    // Pageable sources: copy on our stream and wait, so the kernels of this
    // (non-blocking) stream see the tables and the host vectors may die.
    if (!tables.empty())
      HAPI_CUDA_CHECK(cudaMemcpyAsync(d_tables.get(), tables.data(), tables.size() * sizeof(int), cudaMemcpyHostToDevice,
                                      stream));
    HAPI_CUDA_CHECK(
        cudaMemcpyAsync(d_levels.get(), lv.data(), n_levels * sizeof(LevelDev), cudaMemcpyHostToDevice, stream));
    HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));
    width = w;
    height = h;
  }

  void mark(int i) {
    if (timing) HAPI_CUDA_CHECK(cudaEventRecord(ev[i], stream));
  }

  OrbResult extract(const ImageView8& img) {
    OrbResult res;
    if (!img.data || img.width <= 0 || img.height <= 0 || img.stride < img.width) return res;
    configure(img.width, img.height);
    const int W0 = width, H0 = height;
    // Stage the frame in pinned memory so the upload is a real async DMA.
    uint8_t* hi = h_img.get();
    if (img.stride == W0) {
      std::memcpy(hi, img.data, static_cast<size_t>(W0) * H0);
    } else {
      for (int y = 0; y < H0; ++y) std::memcpy(hi + static_cast<size_t>(y) * W0, img.data + static_cast<size_t>(y) * img.stride, W0);
    }
    mark(0);
    HAPI_CUDA_CHECK(cudaMemcpyAsync(d_img.get(), hi, static_cast<size_t>(W0) * H0, cudaMemcpyHostToDevice, stream));
    mark(1);
    for (int l = 0; l < n_levels; ++l) {
      const int W = plan.width[l], H = plan.height[l];
      uint8_t* L = d_img.get() + level_off[l];
      if (W <= 0 || H <= 0) continue;
      if (l > 0) {
        const int* t = d_tables.get() + table_off[l];
        orb_cuda::launchResize(d_img.get() + level_off[l - 1], plan.width[l - 1], plan.height[l - 1], L, W, H, t,
                               t + W, t + 2 * W, t + 2 * W + H, stream);
      }
      orb_cuda::launchSmooth(L, d_tmp.get(), d_smooth.get() + level_off[l], W, H, stream);
    }
    mark(2);
    HAPI_CUDA_CHECK(cudaMemsetAsync(d_counts.get(), 0, n_levels * sizeof(int), stream));
    if (key_cap) HAPI_CUDA_CHECK(cudaMemsetAsync(d_keys.get(), 0xFF, key_cap * sizeof(unsigned long long), stream));
    for (int l = 0; l < n_levels; ++l) {
      if (!detectable[l]) continue;
      orb_cuda::launchFastNms(d_img.get() + level_off[l], d_score.get(), plan.width[l], plan.height[l], p.fast_threshold,
                              edge, l, d_keys.get() + key_base[l], d_counts.get() + l, stream);
    }
    mark(3);
    if (key_cap)
      orb_cuda::launchSortKeys(d_sort_temp.get(), sort_bytes, d_keys.get(), d_sorted.get(), static_cast<int>(key_cap),
                               end_bit, stream);
    mark(4);
    if (key_cap)
      orb_cuda::launchDescribe(d_levels.get(), n_levels, d_counts.get(), d_sorted.get(), d_patterns.get(), quota_total,
                               180.0 / M_PI, d_kp.get(), d_desc.get(), stream);
    mark(5);
    HAPI_CUDA_CHECK(cudaMemcpyAsync(h_counts.get(), d_counts.get(), n_levels * sizeof(int), cudaMemcpyDeviceToHost, stream));
    if (quota_total > 0 && key_cap) {
      HAPI_CUDA_CHECK(cudaMemcpyAsync(h_kp.get(), d_kp.get(), quota_total * sizeof(KeypointDev), cudaMemcpyDeviceToHost, stream));
      HAPI_CUDA_CHECK(cudaMemcpyAsync(h_desc.get(), d_desc.get(), static_cast<size_t>(quota_total) * kOrbDescBytes,
                                      cudaMemcpyDeviceToHost, stream));
    }
    mark(6);
    HAPI_CUDA_CHECK(cudaStreamSynchronize(stream));
    if (timing) {
      float* dst[6] = {&times.upload_ms, &times.pyramid_ms, &times.detect_ms, &times.select_ms, &times.describe_ms,
                       &times.download_ms};
      for (int i = 0; i < 6; ++i) HAPI_CUDA_CHECK(cudaEventElapsedTime(dst[i], ev[i], ev[i + 1]));
      HAPI_CUDA_CHECK(cudaEventElapsedTime(&times.total_ms, ev[0], ev[6]));
    }

    int n = 0;
    for (int l = 0; l < n_levels; ++l) n += std::min(plan.quota[l], h_counts.get()[l]);
    if (!key_cap) n = 0;
    res.keypoints.resize(n);
    res.descriptors.assign(h_desc.get(), h_desc.get() + static_cast<size_t>(n) * kOrbDescBytes);
    for (int i = 0; i < n; ++i) {
      const KeypointDev& d = h_kp.get()[i];
      OrbKeypoint& k = res.keypoints[i];
      k.lx = d.lx;
      k.ly = d.ly;
      k.level = d.level;
      k.score = d.score;
      k.angle_bin = d.angle_bin;
      orb_finalize_keypoint(k, plan);
    }
    return res;
  }
};

OrbCudaCore::OrbCudaCore(const OrbParams& p) : impl_(new Impl(p)) {}
OrbCudaCore::~OrbCudaCore() = default;
OrbResult OrbCudaCore::extract(const ImageView8& img) { return impl_->extract(img); }
const OrbParams& OrbCudaCore::params() const { return impl_->p; }
void OrbCudaCore::setTiming(bool on) { impl_->timing = on; }
const OrbCudaTimes& OrbCudaCore::lastTimes() const { return impl_->times; }

}  // namespace hapi_frontend
