// Block matching of a rectified pair, the matcher of DenseDepth's GPU path
// (docs/DESIGN.md "Dense depth", GPU block matching): per left pixel the
// sum of absolute differences over a block for every disparity of the
// search (borders replicated, as the SGBM path pads), the first minimum, a
// uniqueness test against every disparity more than 1 px away, and a
// parabola through the three costs about the minimum for the sub-pixel
// part. The per-pixel rule below is compiled for the CPU and for CUDA (one
// copy): integer costs, and one double division for the sub-pixel part
// (correctly rounded on both), so both give the same bits.
#pragma once

#include <cstdint>
#include <string>

#if defined(__CUDACC__)
#define HAPI_SURFACE_HD __host__ __device__
#else
#define HAPI_SURFACE_HD
#endif

namespace hapi_surface {

struct BlockMatchParams {
  int min_disparity = 0;
  int num_disparities = 16;
  int block_size = 5;        // odd
  int uniqueness_ratio = 10;  // %
};

namespace block_match_detail {

HAPI_SURFACE_HD inline int clampi(int v, int lo, int hi) { return v < lo ? lo : (v > hi ? hi : v); }

HAPI_SURFACE_HD inline std::int64_t sad(const std::uint8_t* l, const std::uint8_t* r, int w, int h, int stride, int x,
                                        int y, int d, int radius) {
  std::int64_t s = 0;
  for (int dy = -radius; dy <= radius; ++dy) {
    const int yy = clampi(y + dy, 0, h - 1);
    const std::uint8_t* lr = l + static_cast<std::int64_t>(yy) * stride;
    const std::uint8_t* rr = r + static_cast<std::int64_t>(yy) * stride;
    for (int dx = -radius; dx <= radius; ++dx) {
      const int a = lr[clampi(x + dx, 0, w - 1)], b = rr[clampi(x + dx - d, 0, w - 1)];
      s += a > b ? a - b : b - a;
    }
  }
  return s;
}

// The disparity of left pixel (x, y) in px, or min_disparity - 1 where the
// minimum is not unique.
HAPI_SURFACE_HD inline float matchPixel(const std::uint8_t* l, const std::uint8_t* r, int w, int h, int stride, int x,
                                        int y, const BlockMatchParams& p) {
  const int radius = p.block_size / 2;
  const int d0 = p.min_disparity, d1 = p.min_disparity + p.num_disparities;  // [d0, d1)
  std::int64_t best = -1;
  int best_d = d0;
  for (int d = d0; d < d1; ++d) {
    const std::int64_t c = sad(l, r, w, h, stride, x, y, d, radius);
    if (best < 0 || c < best) {
      best = c;
      best_d = d;
    }
  }
  for (int d = d0; d < d1; ++d) {
    if (d >= best_d - 1 && d <= best_d + 1) continue;
    if (sad(l, r, w, h, stride, x, y, d, radius) * 100 <= best * (100 + p.uniqueness_ratio))
      return static_cast<float>(d0 - 1);
  }
  if (best_d == d0 || best_d == d1 - 1) return static_cast<float>(best_d);
  const std::int64_t cm = sad(l, r, w, h, stride, x, y, best_d - 1, radius);
  const std::int64_t cp = sad(l, r, w, h, stride, x, y, best_d + 1, radius);
  const std::int64_t denom = cm + cp - 2 * best;
  if (denom <= 0) return static_cast<float>(best_d);
  return static_cast<float>(best_d + static_cast<double>(cm - cp) / static_cast<double>(2 * denom));
}

}  // namespace block_match_detail

// The CPU reference: disparity (w x h floats, row-major) of the pair (8-bit,
// `stride` bytes per row).
void blockMatchCpu(const std::uint8_t* left, const std::uint8_t* right, int w, int h, int stride,
                   const BlockMatchParams& p, float* disparity);

}  // namespace hapi_surface
