// Measured rates of this machine's CPU linear algebra in the benchmark's own
// run (OpenBLAS and Eigen through src/covariance/cpu_linear_algebra.hpp, the code
// the CPU backend calls): a square DGEMM and, per pool size, the update's own
// shapes: DSYRK (n x n += n x 3L) and DPOTRF + DTRSM of S (3L x 3L, n x 3L).
// The backend's update rate is then stated against them (same run, ratios).
#pragma once

#include "hapi_eskf/settings.hpp"

namespace hapi_eskf {
namespace bench {

struct CpuRates {
  double gemm_gflops = 0;  // square DGEMM, 2 flops per multiply-add
  double syrk_ms = 0;      // n x n lower += n x k k x n
  double factor_ms = 0;    // DPOTRF of k x k + DTRSM of n x k from the right
  double syrk_gflops = 0, factor_gflops = 0;
};

// Square DGEMM of size `dim`, best of `reps`.
double measureCpuGemm(CpuLinearAlgebra la, int dim, int reps);
// The update's rank update and factorisation shapes (n, k), medians of `reps`.
CpuRates measureCpuUpdateShapes(CpuLinearAlgebra la, int n, int k, int reps);
// Flops of the backend update's large steps at (n, k): SYRK n^2 k, TRSM n k^2,
// POTRF k^3 / 3 (2 flops per multiply-add).
double updateFlops(int n, int k);

}  // namespace bench
}  // namespace hapi_eskf
