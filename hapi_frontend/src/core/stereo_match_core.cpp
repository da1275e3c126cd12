// Reference implementation of the matching contract in stereo_match_core.hpp.
#include "hapi_frontend/stereo_match_core.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace hapi_frontend {

int hamming_distance(const uint8_t* a, const uint8_t* b, int bytes) {
  int d = 0, k = 0;
  for (; k + 8 <= bytes; k += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + k, 8);
    std::memcpy(&y, b + k, 8);
    d += __builtin_popcountll(x ^ y);
  }
  for (; k < bytes; ++k) d += __builtin_popcount(static_cast<unsigned>(a[k] ^ b[k]));
  return d;
}

std::vector<MatchCoreResult> stereo_match_core(const uint8_t* desc_l, const float* pts_l, int n_l,
                                               const uint8_t* desc_r, const float* pts_r, int n_r, int desc_bytes,
                                               const double F[9], const MatchCoreParams& p) {
  std::vector<MatchCoreResult> out;
  if (n_l <= 0 || n_r <= 0 || desc_bytes <= 0) return out;
  constexpr int kInf = std::numeric_limits<int>::max();
  const double max_e2 = p.max_epipolar_px * p.max_epipolar_px;
  // Right keypoints sorted by y (ties by index): for a near-horizontal
  // epipolar line only a thin y band can pass the geometry test. The band is
  // a conservative pre-filter (1 px extra margin); the exact test of rule 1
  // decides, and rules 3/4 are written order-independently, so the result is
  // the brute-force one bit for bit.
  std::vector<int> by_y(n_r);
  for (int j = 0; j < n_r; ++j) by_y[j] = j;
  std::sort(by_y.begin(), by_y.end(), [pts_r](int a, int b) {
    return pts_r[2 * a + 1] < pts_r[2 * b + 1] || (pts_r[2 * a + 1] == pts_r[2 * b + 1] && a < b);
  });
  std::vector<float> ys(n_r);
  for (int k = 0; k < n_r; ++k) ys[k] = pts_r[2 * by_y[k] + 1];
  // Per right keypoint: best left distance and index (cross-check, rule 4).
  std::vector<int> rbest_d(n_r, kInf), rbest_i(n_r, -1);
  for (int i = 0; i < n_l; ++i) {
    const double xl = pts_l[2 * i], yl = pts_l[2 * i + 1];
    const double l0 = F[0] * xl + F[1] * yl + F[2];
    const double l1 = F[3] * xl + F[4] * yl + F[5];
    const double l2 = F[6] * xl + F[7] * yl + F[8];
    const double n2 = l0 * l0 + l1 * l1;
    const double lim = max_e2 * n2;
    const uint8_t* dl = desc_l + static_cast<size_t>(i) * desc_bytes;
    int b = kInf, s = kInf, bj = -1;
    auto visit = [&](int j) {
      const double xr = pts_r[2 * j], yr = pts_r[2 * j + 1];
      const double disp = xl - xr;
      if (disp < p.min_disparity || disp > p.max_disparity) return;
      const double e = l0 * xr + l1 * yr + l2;
      if (e * e > lim) return;
      const int d = hamming_distance(dl, desc_r + static_cast<size_t>(j) * desc_bytes, desc_bytes);
      // Rule 3: best = smallest d, ties -> smallest j; second = smallest other d.
      if (d < b || (d == b && j < bj)) {
        s = b;
        b = d;
        bj = j;
      } else if (d < s) {
        s = d;
      }
      // Rule 4: right side best, ties -> smallest i.
      if (d < rbest_d[j] || (d == rbest_d[j] && i < rbest_i[j])) {
        rbest_d[j] = d;
        rbest_i[j] = i;
      }
    };
    const double al1 = std::abs(l1);
    if (al1 > 0.5 * std::sqrt(n2)) {
      // y on the line at both ends of the disparity range, widened by the
      // epipolar tolerance measured along y, plus a 1 px safety margin.
      const double xa = xl - p.max_disparity, xb = xl - p.min_disparity;
      const double ya = -(l0 * xa + l2) / l1, yb = -(l0 * xb + l2) / l1;
      const double dy = p.max_epipolar_px * std::sqrt(n2) / al1 + 1.0;
      const double y0 = std::min(ya, yb) - dy, y1 = std::max(ya, yb) + dy;
      auto k = std::lower_bound(ys.begin(), ys.end(), static_cast<float>(y0)) - ys.begin();
      for (; k < n_r && ys[k] <= y1; ++k) visit(by_y[k]);
    } else {
      for (int j = 0; j < n_r; ++j) visit(j);  // steep epipolar lines: brute force
    }
    if (bj < 0 || b > p.max_hamming) continue;
    if (s != kInf && !(static_cast<double>(b) < p.ratio * static_cast<double>(s))) continue;
    out.push_back({i, bj, b});
  }
  if (p.cross_check) {
    std::vector<MatchCoreResult> kept;
    kept.reserve(out.size());
    for (const auto& m : out)
      if (rbest_i[m.right] == m.left) kept.push_back(m);
    out.swap(kept);
  }
  return out;
}

}  // namespace hapi_frontend
