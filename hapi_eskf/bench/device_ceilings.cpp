#include "device_ceilings.hpp"

#ifdef HAPI_ESKF_BENCH_WITH_CUDA
#include <cublas_v2.h>
#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>
#include <vector>
#endif

namespace hapi_eskf {
namespace bench {

#ifndef HAPI_ESKF_BENCH_WITH_CUDA

bool measureCeilings(bool, Ceilings*, std::string* why) {
  *why = "built without CUDA";
  return false;
}
bool measureRankUpdate(bool, int, int, int, RankUpdateTiming*, std::string* why) {
  *why = "built without CUDA";
  return false;
}

#else

namespace {

struct Events {
  cudaEvent_t a = nullptr, b = nullptr;
  Events() {
    cudaEventCreate(&a);
    cudaEventCreate(&b);
  }
  ~Events() {
    cudaEventDestroy(a);
    cudaEventDestroy(b);
  }
  double ms() {
    cudaEventSynchronize(b);
    float t = 0;
    cudaEventElapsedTime(&t, a, b);
    return t;
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

cublasStatus_t gemm(cublasHandle_t h, bool fp32, cublasOperation_t tb, int m, int n, int k, const void* A, int lda,
                    const void* B, int ldb, void* C, long long ldc, double alpha, double beta) {
  if (fp32) {
    const float a = static_cast<float>(alpha), b = static_cast<float>(beta);
    return cublasSgemm(h, CUBLAS_OP_N, tb, m, n, k, &a, static_cast<const float*>(A), lda,
                       static_cast<const float*>(B), ldb, &b, static_cast<float*>(C), static_cast<int>(ldc));
  }
  return cublasDgemm(h, CUBLAS_OP_N, tb, m, n, k, &alpha, static_cast<const double*>(A), lda,
                     static_cast<const double*>(B), ldb, &beta, static_cast<double*>(C), static_cast<int>(ldc));
}

// Uniform [-1, 1] operands: tensor-core throughput (and the clock under the
// power cap) depends on the data, so zeros would overstate the peak and
// understate the filter's own GEMM time. A host tile of random numbers is
// copied over the device buffer.
bool fillRandom(void* dev, std::size_t count, bool fp32, unsigned seed) {
  const std::size_t tile = std::min<std::size_t>(count, std::size_t(1) << 22);
  std::vector<double> hd(fp32 ? 0 : tile);
  std::vector<float> hf(fp32 ? tile : 0);
  std::uint64_t x = 0x9E3779B97F4A7C15ull ^ seed;
  for (std::size_t i = 0; i < tile; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    const double u = static_cast<double>(x >> 11) * (2.0 / 9007199254740992.0) - 1.0;
    if (fp32) hf[i] = static_cast<float>(u);
    else hd[i] = u;
  }
  const std::size_t es = fp32 ? 4 : 8;
  const void* src = fp32 ? static_cast<const void*>(hf.data()) : static_cast<const void*>(hd.data());
  for (std::size_t off = 0; off < count; off += tile) {
    const std::size_t c = std::min(tile, count - off);
    if (cudaMemcpy(static_cast<char*>(dev) + es * off, src, es * c, cudaMemcpyHostToDevice) != cudaSuccess)
      return false;
  }
  return true;
}

// Same panel width rule as the backend (src/cuda/blas_traits.hpp defaultPanel).
int panelFor(int n) {
  int p = ((n / 24 + 255) / 256) * 256;
  return p < 512 ? 512 : (p > 4096 ? 4096 : p);
}

}  // namespace

bool measureCeilings(bool fp32, Ceilings* out, std::string* why) {
  int count = 0;
  if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0) {
    *why = "no CUDA device";
    cudaGetLastError();
    return false;
  }
  cudaDeviceProp p{};
  cudaGetDeviceProperties(&p, 0);
  out->device = std::string(p.name) + ", " + std::to_string(p.totalGlobalMem >> 20) + " MiB, " +
                std::to_string(p.multiProcessorCount) + " SMs";
  const std::size_t es = fp32 ? 4 : 8;
  const int N = 8192;
  void *A = nullptr, *B = nullptr, *C = nullptr;
  if (cudaMalloc(&A, es * N * N) != cudaSuccess || cudaMalloc(&B, es * N * N) != cudaSuccess ||
      cudaMalloc(&C, es * N * N) != cudaSuccess) {
    *why = "cannot allocate GEMM ceiling buffers";
    cudaFree(A);
    cudaFree(B);
    return false;
  }
  fillRandom(A, std::size_t(N) * N, fp32, 1);
  fillRandom(B, std::size_t(N) * N, fp32, 2);
  cudaMemset(C, 0, es * N * N);
  cublasHandle_t h;
  cublasCreate(&h);
  Events ev;
  double best = 0;
  for (int rep = 0; rep < 6; ++rep) {
    cudaEventRecord(ev.a);
    gemm(h, fp32, CUBLAS_OP_N, N, N, N, A, N, B, N, C, N, 1.0, 0.0);
    cudaEventRecord(ev.b);
    const double ms = ev.ms();
    if (rep > 0) best = std::max(best, 2.0 * N * double(N) * N / (ms * 1e-3) / 1e12);
  }
  out->gemm_tflops = best;
  // D2D copy of 2 GiB (A+B region reused as source/target halves).
  const std::size_t bytes = std::min<std::size_t>(es * N * N, std::size_t(1) << 31);
  double bw = 0;
  for (int rep = 0; rep < 6; ++rep) {
    cudaEventRecord(ev.a);
    cudaMemcpyAsync(B, A, bytes, cudaMemcpyDeviceToDevice);
    cudaEventRecord(ev.b);
    const double ms = ev.ms();
    if (rep > 0) bw = std::max(bw, 2.0 * bytes / (ms * 1e-3) / 1e9);
  }
  out->copy_gbps = bw;
  cublasDestroy(h);
  cudaFree(A);
  cudaFree(B);
  cudaFree(C);
  out->measured = cudaGetLastError() == cudaSuccess;
  if (!out->measured) *why = "CUDA error while measuring ceilings";
  return out->measured;
}

bool measureRankUpdate(bool fp32, int n, int k, int reps, RankUpdateTiming* out, std::string* why) {
  const std::size_t es = fp32 ? 4 : 8;
  void *C = nullptr, *A = nullptr;
  if (cudaMalloc(&C, es * std::size_t(n) * n) != cudaSuccess) {
    cudaGetLastError();
    *why = "n x n buffer does not fit";
    return false;
  }
  if (cudaMalloc(&A, es * std::size_t(n) * k) != cudaSuccess) {
    cudaGetLastError();
    cudaFree(C);
    *why = "n x k buffer does not fit";
    return false;
  }
  // C's values hardly matter (it is only accumulated into); A's do.
  cudaMemset(C, 0, es * std::size_t(n) * n);
  void* L = nullptr;
  if (cudaMalloc(&L, es * std::size_t(k) * k) != cudaSuccess) {
    cudaGetLastError();
    cudaFree(C);
    cudaFree(A);
    *why = "k x k buffer does not fit";
    return false;
  }
  {
    // Lower triangular, diagonal in [1.5, 2.5], small off-diagonal: well conditioned.
    std::vector<double> hl(std::size_t(k) * k, 0.0);
    std::uint64_t x = 12345;
    for (int c = 0; c < k; ++c)
      for (int r = c; r < k; ++r) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        const double u = static_cast<double>(x >> 11) / 9007199254740992.0;
        hl[r + std::size_t(c) * k] = r == c ? 1.5 + u : (u - 0.5) / k;
      }
    std::vector<float> hf(fp32 ? hl.size() : 0);
    for (std::size_t i = 0; i < hf.size(); ++i) hf[i] = static_cast<float>(hl[i]);
    cudaMemcpy(L, fp32 ? static_cast<const void*>(hf.data()) : static_cast<const void*>(hl.data()), es * hl.size(),
               cudaMemcpyHostToDevice);
  }
  cublasHandle_t h;
  cublasCreate(&h);
  Events ev;
  std::vector<double> ts, tg, tz, tt;
  const int panel = panelFor(n);
  auto panelGemm = [&]() {
    for (int j = 0; j < n; j += panel) {
      const int w = std::min(panel, n - j);
      const char* Aj = static_cast<const char*>(A) + es * j;
      char* Cj = static_cast<char*>(C) + es * (j + std::size_t(j) * n);
      gemm(h, fp32, CUBLAS_OP_T, n - j, w, k, Aj, n, Aj, n, Cj, n, -1.0, 1.0);
    }
  };
  // Zero operands first (for the comparison), then random ones.
  cudaMemset(A, 0, es * std::size_t(n) * k);
  for (int rep = 0; rep < 3; ++rep) {
    cudaEventRecord(ev.a);
    panelGemm();
    cudaEventRecord(ev.b);
    const double t = ev.ms();
    if (rep > 0) tz.push_back(t);
  }
  fillRandom(A, std::size_t(n) * k, fp32, 3);
  for (int rep = 0; rep < 1 + std::max(reps, 1); ++rep) {
    cudaEventRecord(ev.a);
    if (fp32) {
      const float a = -1.f, b = 1.f;
      cublasSsyrk(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_N, n, k, &a, static_cast<float*>(A), n, &b,
                  static_cast<float*>(C), n);
    } else {
      const double a = -1.0, b = 1.0;
      cublasDsyrk(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_N, n, k, &a, static_cast<double*>(A), n, &b,
                  static_cast<double*>(C), n);
    }
    cudaEventRecord(ev.b);
    const double t1 = ev.ms();
    cudaEventRecord(ev.a);
    panelGemm();
    cudaEventRecord(ev.b);
    const double t2 = ev.ms();
    if (rep > 0) {
      ts.push_back(t1);
      tg.push_back(t2);
    }
  }
  for (int rep = 0; rep < 4; ++rep) {
    cudaEventRecord(ev.a);
    if (fp32) {
      const float one = 1.f;
      cublasStrsm(h, CUBLAS_SIDE_RIGHT, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_T, CUBLAS_DIAG_NON_UNIT, n, k, &one,
                  static_cast<const float*>(L), k, static_cast<float*>(A), n);
    } else {
      const double one = 1.0;
      cublasDtrsm(h, CUBLAS_SIDE_RIGHT, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_T, CUBLAS_DIAG_NON_UNIT, n, k, &one,
                  static_cast<const double*>(L), k, static_cast<double*>(A), n);
    }
    cudaEventRecord(ev.b);
    const double t = ev.ms();
    if (rep > 0) tt.push_back(t);
  }
  cublasDestroy(h);
  cudaFree(C);
  cudaFree(A);
  cudaFree(L);
  out->syrk_ms = median(ts);
  out->gemm_ms = median(tg);
  out->gemm_zero_ms = median(tz);
  out->trsm_ms = median(tt);
  out->flops = double(n) * n * k;
  out->bytes = es * (double(n) * n + double(n) * k);  // n^2/2 read + n^2/2 written + A
  out->measured = cudaGetLastError() == cudaSuccess;
  if (!out->measured) *why = "CUDA error while timing the rank update";
  return out->measured;
}

#endif

}  // namespace bench
}  // namespace hapi_eskf
