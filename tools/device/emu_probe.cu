// Probe: does cuBLAS's FP64 fixed-point emulation run on this GPU, how fast
// is it for the filter's rank-600 shape, and how accurate is it?
#include <cublas_v2.h>
#include <cuda_runtime.h>
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <random>
#include <cmath>
#include <algorithm>

#define CK(x) do { cudaError_t e_ = (x); if (e_ != cudaSuccess) { printf("CUDA %s at %d\n", cudaGetErrorString(e_), __LINE__); exit(1);} } while (0)

__global__ void fillK(double* a, size_t n, unsigned long long seed, int ld, int rows, double spread) {
  size_t i = blockIdx.x * (size_t)blockDim.x + threadIdx.x;
  if (i >= n) return;
  unsigned long long x = (i + 1) * 0x9E3779B97F4A7C15ull ^ seed;
  x ^= x >> 33; x *= 0xff51afd7ed558ccdull; x ^= x >> 33; x *= 0xc4ceb9fe1a85ec53ull; x ^= x >> 33;
  double u = (x >> 11) * (1.0 / 9007199254740992.0) - 0.5;
  int r = (int)(i % ld);
  // row scale: 10^(spread * (r mod 97)/97 - spread/2)
  double s = pow(10.0, spread * ((r % 97) / 97.0) - spread / 2);
  a[i] = u * s;
}
__global__ void diffK(const double* a, const double* b, size_t n, double* out) {
  __shared__ double s1[256], s2[256];
  double d = 0, r = 0;
  for (size_t i = blockIdx.x * (size_t)blockDim.x + threadIdx.x; i < n; i += gridDim.x * (size_t)blockDim.x) {
    double e = a[i] - b[i]; d += e * e; r += b[i] * b[i];
  }
  s1[threadIdx.x] = d; s2[threadIdx.x] = r; __syncthreads();
  for (int o = 128; o > 0; o >>= 1) { if (threadIdx.x < o) { s1[threadIdx.x] += s1[threadIdx.x + o]; s2[threadIdx.x] += s2[threadIdx.x + o]; } __syncthreads(); }
  if (threadIdx.x == 0) { atomicAdd(out, s1[0]); atomicAdd(out + 1, s2[0]); }
}

int main() {
  cudaDeviceProp p; CK(cudaGetDeviceProperties(&p, 0));
  int ver = 0; cublasHandle_t h; cublasCreate(&h); cublasGetVersion(h, &ver);
  printf("device %s sm_%d%d, cuBLAS %d\n", p.name, p.major, p.minor, ver);
  const int M = 24576, N = 24576, K = 600;
  double *A, *C, *C0, *Cref, *acc; int* bits;
  CK(cudaMalloc(&A, sizeof(double) * (size_t)M * K));
  CK(cudaMalloc(&C, sizeof(double) * (size_t)M * N));
  CK(cudaMalloc(&C0, sizeof(double) * (size_t)M * N));
  CK(cudaMalloc(&Cref, sizeof(double) * (size_t)M * N));
  CK(cudaMalloc(&acc, 2 * sizeof(double)));
  CK(cudaMallocManaged(&bits, sizeof(int)));
  cudaEvent_t e0, e1; cudaEventCreate(&e0); cudaEventCreate(&e1);
  for (double spread : {0.0, 6.0}) {
    fillK<<<(M * (size_t)K + 255) / 256, 256>>>(A, (size_t)M * K, 7, M, M, spread);
    fillK<<<(M * (size_t)N + 255) / 256, 256>>>(C0, (size_t)M * N, 11, M, M, spread);
    CK(cudaDeviceSynchronize());
    const double minus1 = -1, one = 1;
    auto run = [&](const char* name, cublasComputeType_t ct, int reps) -> double {
      std::vector<float> ts;
      for (int r = 0; r < reps + 1; ++r) {
        CK(cudaMemcpy(C, C0, sizeof(double) * (size_t)M * N, cudaMemcpyDeviceToDevice));
        cudaEventRecord(e0);
        cublasStatus_t s = cublasGemmEx(h, CUBLAS_OP_N, CUBLAS_OP_T, M, N, K, &minus1, A, CUDA_R_64F, M, A, CUDA_R_64F, M,
                                        &one, C, CUDA_R_64F, M, ct, CUBLAS_GEMM_DEFAULT);
        cudaEventRecord(e1);
        CK(cudaDeviceSynchronize());
        if (s != CUBLAS_STATUS_SUCCESS) { printf("  %s: status %s\n", name, cublasGetStatusName(s)); return -1; }
        float ms; cudaEventElapsedTime(&ms, e0, e1); if (r) ts.push_back(ms);
      }
      std::sort(ts.begin(), ts.end());
      return ts[ts.size() / 2];
    };
    double t_nat = run("native", CUBLAS_COMPUTE_64F, 5);
    CK(cudaMemcpy(Cref, C, sizeof(double) * (size_t)M * N, cudaMemcpyDeviceToDevice));
    double fl = 2.0 * M * N * K;
    printf("spread 1e%.0f: native DGEMM %.3f ms %.1f TFLOP/s\n", spread, t_nat, fl / t_nat / 1e9);
    cublasSetFixedPointEmulationMantissaBitCountPointer(h, bits);
    for (int strat : {1, 2}) {
      cublasSetEmulationStrategy(h, (cublasEmulationStrategy_t)strat);
      for (int mb : {0, 32, 40, 48, 56, 64}) {
        if (mb == 0) cublasSetFixedPointEmulationMantissaControl(h, CUDA_EMULATION_MANTISSA_CONTROL_DYNAMIC);
        else { cublasSetFixedPointEmulationMantissaControl(h, CUDA_EMULATION_MANTISSA_CONTROL_FIXED); cublasSetFixedPointEmulationMaxMantissaBitCount(h, mb); }
        *bits = -7;
        double t = run("emu", CUBLAS_COMPUTE_64F_EMULATED_FIXEDPOINT, 3);
        CK(cudaMemset(acc, 0, 16));
        // error of the update (C - C0 part): compare C with Cref
        diffK<<<1024, 256>>>(C, Cref, (size_t)M * N, acc);
        double h2[2]; CK(cudaMemcpy(h2, acc, 16, cudaMemcpyDeviceToHost));
        // also norm of update itself: approximated by ||Cref - C0||
        CK(cudaMemset(acc, 0, 16));
        diffK<<<1024, 256>>>(Cref, C0, (size_t)M * N, acc);
        double u2[2]; CK(cudaMemcpy(u2, acc, 16, cudaMemcpyDeviceToHost));
        printf("  strategy %d mantissa %s%d: %.3f ms (%.2fx native), bits used %d, |C-Cnat|/|AAt| %.2e\n", strat,
               mb ? "fixed " : "dynamic ", mb, t, t_nat / t, *bits, std::sqrt(h2[0] / u2[0]));
      }
    }
    cublasSetEmulationStrategy(h, CUBLAS_EMULATION_STRATEGY_DEFAULT);
  }
  // math-mode route: DGEMM with CUBLAS_FP64_EMULATED_FIXEDPOINT_MATH
  return 0;
}
