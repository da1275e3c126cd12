// This machine's CPU linear algebra rates at the update's shapes, measured
// through the backend's own calls (cpu_ceilings.hpp).
#include "cpu_ceilings.hpp"

#include "../src/covariance/cpu_linear_algebra.hpp"

#include <algorithm>
#include <chrono>
#include <random>
#include <vector>

namespace hapi_eskf {
namespace bench {
namespace {

using Clock = std::chrono::steady_clock;
using Eigen::MatrixXd;

MatrixXd randomMatrix(int r, int c, unsigned seed) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatrixXd M(r, c);
  for (Eigen::Index i = 0; i < M.size(); ++i) M.data()[i] = u(g);
  return M;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

double updateFlops(int n, int k) {
  const double N = n, K = k;
  return N * N * K + N * K * K + K * K * K / 3.0;
}

double measureCpuGemm(CpuLinearAlgebra la, int dim, int reps) {
  const MatrixXd A = randomMatrix(dim, dim, 1), B = randomMatrix(dim, dim, 2);
  MatrixXd C = MatrixXd::Zero(dim, dim);
  double best = 1e300;
  for (int r = 0; r < reps + 1; ++r) {
    const auto t0 = Clock::now();
    cpu_la::gemm(la, false, false, 1.0, A, B, 0.0, &C);
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    if (r > 0) best = std::min(best, s);  // the first one warms up threads and caches
  }
  return 2.0 * dim * static_cast<double>(dim) * dim / best / 1e9;
}

CpuRates measureCpuUpdateShapes(CpuLinearAlgebra la, int n, int k, int reps) {
  CpuRates r;
  MatrixXd C = randomMatrix(n, n, 3);
  const MatrixXd A = 1e-3 * randomMatrix(n, k, 4);
  const MatrixXd G = randomMatrix(k, k, 5);
  const MatrixXd S0 = G * G.transpose() + k * MatrixXd::Identity(k, k);
  std::vector<double> syrk, factor;
  for (int i = 0; i < reps + 1; ++i) {
    auto t0 = Clock::now();
    cpu_la::rankUpdateLower(la, cpu_la::MatRef(C.data(), n, n, Eigen::OuterStride<>(n)), A, -1.0);
    const double s1 = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    MatrixXd S = S0, P = A;
    t0 = Clock::now();
    cpu_la::choleskyLower(la, &S);
    cpu_la::solveRightLowerTransposed(la, S, &P);
    const double s2 = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (i == 0) continue;
    syrk.push_back(s1);
    factor.push_back(s2);
  }
  r.syrk_ms = median(syrk);
  r.factor_ms = median(factor);
  const double N = n, K = k;
  r.syrk_gflops = N * N * K / (r.syrk_ms * 1e-3) / 1e9;
  r.factor_gflops = (N * K * K + K * K * K / 3.0) / (r.factor_ms * 1e-3) / 1e9;
  r.gemm_gflops = 0;
  return r;
}

}  // namespace bench
}  // namespace hapi_eskf
