// OpenCV- and Eigen-free stereo matching core: brute-force Hamming search of
// every left descriptor against the right descriptors that pass the epipolar
// and disparity constraints, Lowe ratio test, absolute Hamming bound and
// cross-check. The CPU StereoMatcher calls it directly; the CUDA matcher
// (src/cuda) must reproduce its output exactly, so every rule that decides a
// match is spelled out here and kept free of floating-point ambiguity.
//
// Exact semantics (the contract the GPU matcher mirrors):
//  1. Geometry, per pair (i, j), in double precision, evaluated exactly in the
//     order written below WITHOUT fused multiply-add contraction (the CPU
//     library is built with -ffp-contract=off; CUDA code must use
//     __dmul_rn/__dadd_rn or -fmad=false for these lines):
//       l = F * [xl_i, yl_i, 1]^T                 (l0, l1, l2)
//       e = |l0*xr_j + l1*yr_j + l2|,  n2 = l0*l0 + l1*l1
//       candidate  <=>  e*e <= max_epipolar_px^2 * n2
//                  and  min_disparity <= xl_i - xr_j <= max_disparity
//       with l0 = F0*x + F1*y + F2 (left to right), likewise l1, l2; the
//     squared test needs no sqrt/division, so both paths agree bit for bit.
//  2. Hamming distance d(i, j) over desc_bytes bytes (popcount of XOR).
//  3. Left side: over the candidates j of i, best = smallest d, ties broken by
//     the SMALLEST j; second = smallest d among the other candidates (may equal
//     best). Accept when best <= max_hamming and (no second candidate or
//     best < ratio * second, evaluated as double(best) < ratio * double(second)).
//     Equal best and second distances therefore never pass (ambiguous match),
//     so the left-side tie rule never shows in the output; the right-side
//     one (rule 4) does.
//  4. Cross-check (optional): over all left candidates i of right j (geometry
//     only, no ratio test), the best left = smallest d, ties -> SMALLEST i.
//     Keep (i, j) only if that best left is i.
//  Rules 3 and 4 do not depend on the order in which candidates are visited
//  (the CPU visits a y band of right keypoints, a GPU may visit all of them).
//  5. Output sorted by left index ascending (at most one match per left and,
//     with cross-check, per right).
#pragma once

#include <cstdint>
#include <vector>

namespace hapi_frontend {

struct MatchCoreParams {
  double max_epipolar_px = 2.0;
  double min_disparity = 0.5;
  double max_disparity = 256.0;
  double ratio = 0.8;
  int max_hamming = 64;
  bool cross_check = true;
};

struct MatchCoreResult {
  int left = -1, right = -1, distance = 0;
};

// desc_l: n_l * desc_bytes bytes (row i = left keypoint i); pts_l: 2 * n_l
// floats (x0, y0, x1, y1, ...) undistorted pixels; same for the right side.
// F: row-major 3x3 with l_right = F * [x_l, y_l, 1]^T.
std::vector<MatchCoreResult> stereo_match_core(const uint8_t* desc_l, const float* pts_l, int n_l,
                                               const uint8_t* desc_r, const float* pts_r, int n_r, int desc_bytes,
                                               const double F[9], const MatchCoreParams& p);

// Hamming distance of two byte strings (shared helper, also used by tests).
int hamming_distance(const uint8_t* a, const uint8_t* b, int bytes);

}  // namespace hapi_frontend
