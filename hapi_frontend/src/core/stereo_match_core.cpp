// Reference implementation of the matching contract in stereo_match_core.hpp.
#include "hapi_frontend/stereo_match_core.hpp"

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
  // Per right keypoint: best left distance and index (cross-check, rule 4).
  std::vector<int> rbest_d(n_r, kInf), rbest_i(n_r, -1);
  // Per left keypoint: best/second distance and best index (rule 3).
  std::vector<int> lbest_d(n_l, kInf), lsecond_d(n_l, kInf), lbest_j(n_l, -1);
  for (int i = 0; i < n_l; ++i) {
    const double xl = pts_l[2 * i], yl = pts_l[2 * i + 1];
    const double l0 = F[0] * xl + F[1] * yl + F[2];
    const double l1 = F[3] * xl + F[4] * yl + F[5];
    const double l2 = F[6] * xl + F[7] * yl + F[8];
    const double lim = max_e2 * (l0 * l0 + l1 * l1);
    const uint8_t* dl = desc_l + static_cast<size_t>(i) * desc_bytes;
    int b = kInf, s = kInf, bj = -1;
    for (int j = 0; j < n_r; ++j) {
      const double xr = pts_r[2 * j], yr = pts_r[2 * j + 1];
      const double disp = xl - xr;
      if (disp < p.min_disparity || disp > p.max_disparity) continue;
      const double e = l0 * xr + l1 * yr + l2;
      if (e * e > lim) continue;
      const int d = hamming_distance(dl, desc_r + static_cast<size_t>(j) * desc_bytes, desc_bytes);
      // j ascending + strict '<': the smallest j wins ties for best.
      if (d < b) {
        s = b;
        b = d;
        bj = j;
      } else if (d < s) {
        s = d;
      }
      // i ascending + strict '<': the smallest i wins ties on the right side.
      if (d < rbest_d[j]) {
        rbest_d[j] = d;
        rbest_i[j] = i;
      }
    }
    lbest_d[i] = b;
    lsecond_d[i] = s;
    lbest_j[i] = bj;
  }
  for (int i = 0; i < n_l; ++i) {
    const int j = lbest_j[i];
    if (j < 0 || lbest_d[i] > p.max_hamming) continue;
    if (lsecond_d[i] != kInf && !(static_cast<double>(lbest_d[i]) < p.ratio * static_cast<double>(lsecond_d[i])))
      continue;
    if (p.cross_check && rbest_i[j] != i) continue;
    out.push_back({i, j, lbest_d[i]});
  }
  return out;
}

}  // namespace hapi_frontend
