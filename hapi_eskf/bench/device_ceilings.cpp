#include "device_ceilings.hpp"

#ifdef HAPI_ESKF_BENCH_WITH_CUDA
#include "../src/covariance/cuda/blas_traits.hpp"

#include <cublas_v2.h>
#include <cuda_runtime.h>
#include <cusolverDn.h>

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
  if (cudaMemcpy(dev, src, es * tile, cudaMemcpyHostToDevice) != cudaSuccess) return false;
  // The rest by doubling device-to-device copies of what is already there
  // (a 74 GB covariance in well under a second instead of minutes over PCIe).
  for (std::size_t done = tile; done < count;) {
    const std::size_t c = std::min(done, count - done);
    if (cudaMemcpy(static_cast<char*>(dev) + es * done, dev, es * c, cudaMemcpyDeviceToDevice) != cudaSuccess)
      return false;
    done += c;
  }
  return true;
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

namespace {

// The backend's own schedules (blas_traits.hpp) on buffers of this function.
template <typename T>
bool measureRankUpdateT(int n, int k, int reps, RankUpdateTiming* out, std::string* why) {
  const std::size_t es = sizeof(T);
  // Same layout as the backend: leading dimension padded (paddedLd).
  const std::size_t ld = cuda::paddedLd(n);
  T *C = nullptr, *A = nullptr, *A2 = nullptr, *L = nullptr;
  auto release = [&]() {
    cudaFree(C);
    cudaFree(A);
    cudaFree(A2);
    cudaFree(L);
    cudaGetLastError();
  };
  if (cudaMalloc(&C, es * ld * n) != cudaSuccess || cudaMalloc(&A, es * ld * k) != cudaSuccess ||
      cudaMalloc(&A2, es * ld * k) != cudaSuccess || cudaMalloc(&L, es * std::size_t(k) * k) != cudaSuccess) {
    release();
    *why = "n x n, 2 x (n x k) and k x k buffers do not fit";
    return false;
  }
  // Random C and A, as in the filter: the rate can depend on the bits moved
  // and multiplied (power cap); the all-zero-C control below shows how much.
  fillRandom(C, ld * n, es == 4, 4);
  fillRandom(A, ld * k, es == 4, 3);
  // Lower triangular L, diagonal in [1.5, 2.5], small off-diagonal (well
  // conditioned), zeros above as after launchZeroStrictUpper.
  std::vector<T> hl(std::size_t(k) * k, T(0));
  std::uint64_t x = 12345;
  for (int c = 0; c < k; ++c)
    for (int r = c; r < k; ++r) {
      x = x * 6364136223846793005ull + 1442695040888963407ull;
      const double u = static_cast<double>(x >> 11) / 9007199254740992.0;
      hl[r + std::size_t(c) * k] = static_cast<T>(r == c ? 1.5 + u : (u - 0.5) / k);
    }
  cudaMemcpy(L, hl.data(), es * hl.size(), cudaMemcpyHostToDevice);
  cublasHandle_t h;
  cusolverDnHandle_t sol;
  cublasCreate(&h);
  cusolverDnCreate(&sol);
  Events ev;
  const int panel = cuda::defaultPanel(n);
  const int ild = static_cast<int>(ld);
  auto timeIt = [&](auto&& body, int count) {
    std::vector<double> t;
    for (int rep = 0; rep < 1 + count; ++rep) {  // first one is the warm-up
      cudaEventRecord(ev.a);
      body();
      cudaEventRecord(ev.b);
      const double ms = ev.ms();
      if (rep > 0) t.push_back(ms);
    }
    return median(t);
  };
  // Interleaved schedules, so the card is equally hot for each.
  std::vector<double> ts, tg, tr, tu, tz;
  for (int rep = 0; rep < std::max(reps, 1); ++rep) {
    ts.push_back(timeIt([&] { cuda::rankUpdate<T>(h, CudaRankUpdate::kSyrk, n, k, A, ild, C, ld, panel); }, 1));
    tg.push_back(timeIt([&] { cuda::rankUpdate<T>(h, CudaRankUpdate::kPanelGemm, n, k, A, ild, C, ld, panel); }, 1));
    tr.push_back(timeIt([&] { cuda::rankUpdate<T>(h, CudaRankUpdate::kRecursive, n, k, A, ild, C, ld, panel); }, 1));
    tu.push_back(timeIt([&] { cuda::rankUpdate<T>(h, CudaRankUpdate::kRecursive, n, k, A, n, C, n, panel); }, 1));
  }
  // C = 0 last (it destroys the random C; A stays random).
  cudaMemset(C, 0, es * ld * n);
  for (int rep = 0; rep < std::max(reps, 1); ++rep)
    tz.push_back(timeIt([&] { cuda::rankUpdate<T>(h, CudaRankUpdate::kRecursive, n, k, A, ild, C, ld, panel); }, 1));
  out->syrk_ms = median(ts);
  out->gemm_ms = median(tg);
  out->recursive_ms = median(tr);
  out->recursive_unpadded_ms = median(tu);
  out->recursive_zero_c_ms = median(tz);
  out->trsm_ms = timeIt([&] { cuda::Blas<T>::trsmRightLowerT(h, n, k, L, k, A, ild); }, 3);
  std::size_t dev_bytes = 0, host_bytes = 0;
  cuda::trtriBufferSize<T>(sol, k, L, &dev_bytes, &host_bytes);
  void* dwork = nullptr;
  int* info = nullptr;
  cudaMalloc(&dwork, std::max<std::size_t>(dev_bytes, 1));
  cudaMalloc(&info, sizeof(int));
  std::vector<unsigned char> hwork(host_bytes);
  // trtri inverts L in place: alternate between L and its inverse, both
  // well conditioned; the GEMM reads whichever is there (same cost).
  out->inverse_ms = timeIt(
      [&] {
        cuda::trtri<T>(sol, k, L, dwork, dev_bytes, hwork.data(), host_bytes, info);
        cuda::Blas<T>::gemmNT(h, n, k, k, T(1), A, ild, L, k, T(0), A2, ild);
      },
      3);
  cudaFree(dwork);
  cudaFree(info);
  cusolverDnDestroy(sol);
  cublasDestroy(h);
  release();
  out->flops = double(n) * n * k;
  out->bytes = es * (double(n) * n + double(n) * k);  // n^2/2 read + n^2/2 written + A
  out->measured = cudaGetLastError() == cudaSuccess;
  if (!out->measured) *why = "CUDA error while timing the rank update";
  return out->measured;
}

}  // namespace

bool measureRankUpdate(bool fp32, int n, int k, int reps, RankUpdateTiming* out, std::string* why) {
  return fp32 ? measureRankUpdateT<float>(n, k, reps, out, why) : measureRankUpdateT<double>(n, k, reps, out, why);
}

#endif

}  // namespace bench
}  // namespace hapi_eskf
