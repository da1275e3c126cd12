// ORB kernels. Bit-exactness with orb_core.cpp rests on: identical integer
// expressions (same rounding offsets and shifts), the same FAST circle order,
// keys that make the order total (orb_rank_key is unique per pixel), and the
// orientation bin computed with explicitly rounded double operations (no FMA
// contraction) from the same integer moments.
#include "orb_kernels.cuh"

#include "hapi_frontend/orb_core.hpp"
#include "cuda_check.hpp"

#include <cub/device/device_radix_sort.cuh>

namespace hapi_frontend {
namespace orb_cuda {

namespace {

// Small tables travel as kernel parameters (by value): no __constant__
// symbols whose initialisation depends on module loading.
// FAST-9 circle of radius 3, clockwise from the top (same order as the CPU),
// as row-major offsets for one level width.
struct CircleOffsets {
  int off[16];
};
struct Umax {
  int u[kOrbHalfPatch + 1];
};
const int kCircleDx[16] = {0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3, -3, -3, -2, -1};
const int kCircleDy[16] = {-3, -3, -2, -1, 0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3};

__global__ void resizeKernel(const uint8_t* __restrict__ src, int sw, int sh, uint8_t* __restrict__ dst, int w, int h,
                             const int* __restrict__ xi, const int* __restrict__ xw, const int* __restrict__ yi,
                             const int* __restrict__ yw) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x >= w || y >= h) return;
  const uint8_t* r0 = src + static_cast<size_t>(yi[y]) * sw;
  const uint8_t* r1 = src + static_cast<size_t>(min(yi[y] + 1, sh - 1)) * sw;
  const int fy = yw[y], k = xi[x], k1 = min(k + 1, sw - 1), fx = xw[x];
  const int a = r0[k] * (256 - fx) + r0[k1] * fx;
  const int b = r1[k] * (256 - fx) + r1[k1] * fx;
  dst[static_cast<size_t>(y) * w + x] = static_cast<uint8_t>((a * (256 - fy) + b * fy + 32768) >> 16);
}

__global__ void smoothRowsKernel(const uint8_t* __restrict__ img, uint16_t* __restrict__ tmp, int w, int h) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x >= w || y >= h) return;
  const uint8_t* r = img + static_cast<size_t>(y) * w;
  const int xm2 = max(x - 2, 0), xm1 = max(x - 1, 0), xp1 = min(x + 1, w - 1), xp2 = min(x + 2, w - 1);
  tmp[static_cast<size_t>(y) * w + x] = static_cast<uint16_t>(r[xm2] + 4 * r[xm1] + 6 * r[x] + 4 * r[xp1] + r[xp2]);
}

__global__ void smoothColsKernel(const uint16_t* __restrict__ tmp, uint8_t* __restrict__ out, int w, int h) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x >= w || y >= h) return;
  const int a = tmp[static_cast<size_t>(max(y - 2, 0)) * w + x];
  const int b = tmp[static_cast<size_t>(max(y - 1, 0)) * w + x];
  const int c = tmp[static_cast<size_t>(y) * w + x];
  const int d = tmp[static_cast<size_t>(min(y + 1, h - 1)) * w + x];
  const int e = tmp[static_cast<size_t>(min(y + 2, h - 1)) * w + x];
  out[static_cast<size_t>(y) * w + x] = static_cast<uint8_t>((a + 4 * b + 6 * c + 4 * d + e + 128) >> 8);
}

// Score on [edge-1, w-edge] x [edge-1, h-edge] (inclusive), zero elsewhere,
// exactly like the CPU (the NMS reads one pixel beyond its own range).
__global__ void fastKernel(const uint8_t* __restrict__ img, uint8_t* __restrict__ score, int w, int h, int t, int edge,
                           CircleOffsets circle) {
  const int x = blockIdx.x * blockDim.x + threadIdx.x, y = blockIdx.y * blockDim.y + threadIdx.y;
  if (x >= w || y >= h) return;
  int best = 0;
  if (x >= edge - 1 && x <= w - edge && y >= edge - 1 && y <= h - edge) {
    const uint8_t* p = img + static_cast<size_t>(y) * w + x;
    const int c = p[0];
    int nb = 0, nd = 0;
#pragma unroll
    for (int i = 0; i < 16; i += 4) {
      const int v = p[circle.off[i]];
      nb += v > c + t;
      nd += v < c - t;
    }
    if (nb >= 2 || nd >= 2) {
      // Same value as the CPU's max_k max(min_arc d, -max_arc d), written
      // without negating a max: ptxas (CUDA 13.0, sm_90, -O3) fused
      // max(mn, -mx) into one min/max instruction that dropped the negation,
      // so the score became the largest brighter difference (seen on the H100:
      // GPU score 126 where the CPU and a brute-force check give 40).
      // -max_arc(p - c) == min_arc(c - p): two min chains, no neg.
      int bright[16], dark[16];
#pragma unroll
      for (int i = 0; i < 16; ++i) {
        const int v = p[circle.off[i]];
        bright[i] = v - c;
        dark[i] = c - v;
      }
#pragma unroll
      for (int k = 0; k < 16; ++k) {
        int mb = 255, md = 255;
#pragma unroll
        for (int j = 0; j < 9; ++j) {
          mb = min(mb, bright[(k + j) & 15]);
          md = min(md, dark[(k + j) & 15]);
        }
        best = max(best, max(mb, md));
      }
      if (best <= t) best = 0;
    } else {
      best = 0;
    }
  }
  score[static_cast<size_t>(y) * w + x] = static_cast<uint8_t>(best);
}

// Strict 3x3 maximum; candidates are appended with one atomic per warp. The
// append order is arbitrary, the later sort makes it deterministic.
__global__ void nmsKernel(const uint8_t* __restrict__ score, int w, int h, int edge, unsigned long long level_bits,
                          unsigned long long* __restrict__ keys, int* __restrict__ count) {
  const int x = edge + static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  const int y = edge + static_cast<int>(blockIdx.y * blockDim.y + threadIdx.y);
  bool is_max = false;
  int v = 0;
  if (x < w - edge && y < h - edge) {
    const uint8_t* s = score + static_cast<size_t>(y) * w + x;
    v = s[0];
    is_max = v && v > s[-1] && v > s[1] && v > s[-w - 1] && v > s[-w] && v > s[-w + 1] && v > s[w - 1] && v > s[w] &&
             v > s[w + 1];
  }
  const unsigned mask = __ballot_sync(0xffffffffu, is_max);
  if (!mask) return;
  const int lane = threadIdx.x & 31;  // blockDim.x is a multiple of 32 (launcher)
  const int leader = __ffs(mask) - 1;
  int base = 0;
  if (lane == leader) base = atomicAdd(count, __popc(mask));
  base = __shfl_sync(0xffffffffu, base, leader);  // every lane calls it: full mask
  if (is_max) {
    const int pos = base + __popc(mask & ((1u << lane) - 1u));
    keys[pos] = level_bits | (static_cast<unsigned long long>(255 - v) << 40) |
                (static_cast<unsigned long long>(y) << 20) | static_cast<unsigned long long>(x);
  }
}

// Same expression as orb_angle_bin(), each double operation rounded on its
// own (the CPU build does not contract either: no FMA in baseline x86-64).
__device__ int angleBin(long long m10, long long m01, double rad2deg) {
  double a = __dmul_rn(atan2(static_cast<double>(m01), static_cast<double>(m10)), rad2deg);
  if (a < 0) a = __dadd_rn(a, 360.0);
  const int bin = static_cast<int>(floor(__dadd_rn(__ddiv_rn(a, 360.0 / kOrbAngleBins), 0.5)));
  return bin % kOrbAngleBins;
}

__global__ void describeKernel(const LevelDev* __restrict__ levels, int n_levels, const int* __restrict__ counts,
                               const unsigned long long* __restrict__ sorted, const int8_t* __restrict__ rotated,
                               int quota_total, double rad2deg, Umax umax, KeypointDev* __restrict__ out_kp,
                               uint8_t* __restrict__ out_desc) {
  const int slot = static_cast<int>((blockIdx.x * blockDim.x + threadIdx.x) >> 5);
  const int lane = threadIdx.x & 31;
  if (slot >= quota_total) return;  // uniform per warp
  int l = 0;
  while (l + 1 < n_levels && slot >= levels[l].qstart + levels[l].quota) ++l;
  const LevelDev lv = levels[l];
  const int i = slot - lv.qstart;
  if (i >= min(lv.quota, counts[l])) return;  // uniform per warp
  int seg = 0, out = 0;
  for (int k = 0; k < l; ++k) {
    seg += counts[k];
    out += min(levels[k].quota, counts[k]);
  }
  out += i;
  const unsigned long long key = sorted[seg + i];
  const int lx = static_cast<int>(key & 0xFFFFFull), ly = static_cast<int>((key >> 20) & 0xFFFFFull);
  const int W = lv.width;

  // Intensity centroid on the circular patch: lane v+15 sums row v.
  long long m10 = 0, m01 = 0;
  if (lane < 2 * kOrbHalfPatch + 1) {
    const int v = lane - kOrbHalfPatch;
    const int um = umax.u[v < 0 ? -v : v];
    const uint8_t* r = lv.img + static_cast<size_t>(ly + v) * W + lx;
    int rs = 0, rx = 0;
    for (int u = -um; u <= um; ++u) {
      const int p = r[u];
      rs += p;
      rx += u * p;
    }
    m10 = rx;
    m01 = static_cast<long long>(v) * rs;
  }
#pragma unroll
  for (int o = 16; o > 0; o >>= 1) {
    m10 += __shfl_down_sync(0xffffffffu, m10, o);
    m01 += __shfl_down_sync(0xffffffffu, m01, o);
  }
  int bin = 0;
  if (lane == 0) bin = angleBin(m10, m01, rad2deg);
  bin = __shfl_sync(0xffffffffu, bin, 0);

  // Steered BRIEF: lane b produces descriptor byte b.
  const int8_t* pat = rotated + bin * 1024 + lane * 32;
  const uint8_t* sc = lv.smooth + static_cast<size_t>(ly) * W + lx;
  int val = 0;
#pragma unroll
  for (int j = 0; j < 8; ++j) {
    const int8_t* pp = pat + j * 4;
    val |= (sc[pp[1] * W + pp[0]] < sc[pp[3] * W + pp[2]]) << j;
  }
  out_desc[static_cast<size_t>(out) * kOrbDescBytes + lane] = static_cast<uint8_t>(val);
  if (lane == 0) {
    KeypointDev k;
    k.lx = lx;
    k.ly = ly;
    k.level = l;
    k.score = 255 - static_cast<int>((key >> 40) & 0xFFull);
    k.angle_bin = bin;
    out_kp[out] = k;
  }
}

dim3 grid2d(int w, int h, dim3 b) { return dim3((w + b.x - 1) / b.x, (h + b.y - 1) / b.y); }

}  // namespace

void launchResize(const uint8_t* src, int sw, int sh, uint8_t* dst, int w, int h, const int* xi, const int* xw,
                  const int* yi, const int* yw, cudaStream_t s) {
  const dim3 b(32, 8);
  resizeKernel<<<grid2d(w, h, b), b, 0, s>>>(src, sw, sh, dst, w, h, xi, xw, yi, yw);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

void launchSmooth(const uint8_t* img, uint16_t* tmp, uint8_t* out, int w, int h, cudaStream_t s) {
  const dim3 b(32, 8);
  smoothRowsKernel<<<grid2d(w, h, b), b, 0, s>>>(img, tmp, w, h);
  smoothColsKernel<<<grid2d(w, h, b), b, 0, s>>>(tmp, out, w, h);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

void launchFastNms(const uint8_t* img, uint8_t* score, int w, int h, int threshold, int edge, int level,
                   unsigned long long* keys, int* count, cudaStream_t s) {
  const dim3 b(32, 8);
  CircleOffsets circle;
  for (int i = 0; i < 16; ++i) circle.off[i] = kCircleDy[i] * w + kCircleDx[i];
  fastKernel<<<grid2d(w, h, b), b, 0, s>>>(img, score, w, h, threshold, edge, circle);
  const int rw = w - 2 * edge, rh = h - 2 * edge;
  if (rw > 0 && rh > 0) {
    nmsKernel<<<grid2d(rw, rh, b), b, 0, s>>>(score, w, h, edge, static_cast<unsigned long long>(level) << kRankKeyBits,
                                              keys, count);
  }
  HAPI_CUDA_CHECK(cudaGetLastError());
}

std::size_t sortTempBytes(int n, int end_bit) {
  std::size_t bytes = 0;
  HAPI_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(nullptr, bytes, static_cast<const unsigned long long*>(nullptr),
                                                 static_cast<unsigned long long*>(nullptr), n, 0, end_bit));
  return bytes;
}

void launchSortKeys(void* temp, std::size_t temp_bytes, const unsigned long long* in, unsigned long long* out, int n,
                    int end_bit, cudaStream_t s) {
  HAPI_CUDA_CHECK(cub::DeviceRadixSort::SortKeys(temp, temp_bytes, in, out, n, 0, end_bit, s));
}

void launchDescribe(const LevelDev* levels, int n_levels, const int* counts, const unsigned long long* sorted,
                    const int8_t* rotated_patterns, int quota_total, double rad2deg, KeypointDev* out_kp,
                    uint8_t* out_desc, cudaStream_t s) {
  if (quota_total <= 0) return;
  Umax umax;
  const int* um = orb_umax();  // the CPU table itself
  for (int v = 0; v <= kOrbHalfPatch; ++v) umax.u[v] = um[v];
  const int threads = 128;  // 4 warps = 4 keypoints per block
  const int blocks = (quota_total * 32 + threads - 1) / threads;
  describeKernel<<<blocks, threads, 0, s>>>(levels, n_levels, counts, sorted, rotated_patterns, quota_total, rad2deg,
                                            umax, out_kp, out_desc);
  HAPI_CUDA_CHECK(cudaGetLastError());
}

}  // namespace orb_cuda
}  // namespace hapi_frontend
