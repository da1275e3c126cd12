// Measured ceilings of the CUDA device (same run as the filter timings): FP64
// (or FP32) GEMM rate, device-to-device copy bandwidth, and the isolated
// C <- C - A A^T step for a given n and rank (SYRK and panelled GEMM), so the
// benchmark can state how far that step is from its floor
// max(flops / peak, bytes / bandwidth) (docs/DESIGN.md "Update" step 4).
#pragma once

#include <string>

namespace hapi_eskf {
namespace bench {

struct Ceilings {
  bool measured = false;
  std::string device;       // name, memory
  double gemm_tflops = 0;   // best of several large square GEMMs on random operands
  double copy_gbps = 0;     // (read + write) bytes / s of a large D2D copy
};

struct RankUpdateTiming {
  bool measured = false;
  // C <- C - A A^T, random A, median of the repetitions, per schedule
  // (src/covariance/cuda/blas_traits.hpp rankUpdate): SYRK, panelled GEMM, recursive.
  double syrk_ms = 0, gemm_ms = 0, recursive_ms = 0;
  // Controls of the recursive schedule, interleaved with the above: leading
  // dimension n instead of the padded one, and an all-zero C (power: the
  // rate depends on the bits moved).
  double recursive_unpadded_ms = 0, recursive_zero_c_ms = 0;
  // Update step 3 with the same shape, A <- P L^-T: TRSM in place, and the
  // trtri + GEMM of Solve::kInverse (src/covariance/cuda/cuda_backend.cpp).
  double trsm_ms = 0, inverse_ms = 0;
  double flops = 0;                 // n^2 k (one triangle, multiply-add = 2 flops)
  double bytes = 0;                 // lower triangle read + written once, A read once
};

// false (and *why) without CUDA or device.
bool measureCeilings(bool fp32, Ceilings* out, std::string* why);
// Also times both ways of update step 3 with the same shape.
// Allocates its own n x n and n x k buffers (call while no backend is alive
// when n is large); false if they do not fit.
// reps: timed repetitions of each variant (after one warm-up); more of them
// show the rate the GEMM sustains once the card is hot.
bool measureRankUpdate(bool fp32, int n, int k, int reps, RankUpdateTiming* out, std::string* why);

}  // namespace bench
}  // namespace hapi_eskf
