// Internal: launchers of the stereo matching kernels (stereo_match_kernels.cu),
// the GPU form of the contract in stereo_match_core.hpp.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>

namespace hapi_frontend {
namespace match_cuda {

struct MatchGeometry {
  double F[9];
  double max_e2;  // max_epipolar_px^2
  double min_disparity, max_disparity;
  double ratio;
  int max_hamming;
  int cross_check;
};

// Descriptors are stored as rows of `words` 32-bit words (zero padded), so
// any desc_bytes works and the padding adds nothing to the XOR popcount.
// col_best[j] <- min over candidate i of (d << 32 | i)  (rule 4: smallest d, then smallest i)
void launchColumnBest(const uint32_t* desc_l, const float* pts_l, int n_l, const uint32_t* desc_r, const float* pts_r,
                      int n_r, int words, const MatchGeometry& g, unsigned long long* col_best, cudaStream_t s);
// Per left i: best/second (rule 3), max Hamming, ratio and cross-check; writes
// out_j[i] = matched right index or -1 and out_d[i] = its distance.
void launchRowDecide(const uint32_t* desc_l, const float* pts_l, int n_l, const uint32_t* desc_r, const float* pts_r,
                     int n_r, int words, const MatchGeometry& g, const unsigned long long* col_best, int* out_j,
                     int* out_d, cudaStream_t s);

}  // namespace match_cuda
}  // namespace hapi_frontend
