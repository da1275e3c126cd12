// Precision-generic thin wrappers over the cuBLAS / cuSOLVER calls the backend
// uses (FP64 default, FP32 option: settings.hpp Precision).
#pragma once

#include "hapi_eskf/settings.hpp"

#include <cublas_v2.h>
#include <cusolverDn.h>

#include <cstddef>
#include <string>

namespace hapi_eskf {
namespace cuda {

template <typename T>
struct Blas;

template <>
struct Blas<double> {
  static constexpr cudaDataType kType = CUDA_R_64F;
  static cublasStatus_t syrk(cublasHandle_t h, int n, int k, double alpha, const double* A, int lda, double beta,
                             double* C, int ldc) {
    return cublasDsyrk(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_N, n, k, &alpha, A, lda, &beta, C, ldc);
  }
  static cublasStatus_t gemmNT(cublasHandle_t h, int m, int n, int k, double alpha, const double* A, int lda,
                               const double* B, int ldb, double beta, double* C, int ldc) {
    return cublasDgemm(h, CUBLAS_OP_N, CUBLAS_OP_T, m, n, k, &alpha, A, lda, B, ldb, &beta, C, ldc);
  }
  // B <- B L^-T (L lower, n x n), B is m x n.
  static cublasStatus_t trsmRightLowerT(cublasHandle_t h, int m, int n, const double* L, int ldl, double* B,
                                        int ldb) {
    const double one = 1.0;
    return cublasDtrsm(h, CUBLAS_SIDE_RIGHT, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_T, CUBLAS_DIAG_NON_UNIT, m, n, &one,
                       L, ldl, B, ldb);
  }
  static cublasStatus_t trsvLower(cublasHandle_t h, int n, const double* L, int ldl, double* x) {
    return cublasDtrsv(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_N, CUBLAS_DIAG_NON_UNIT, n, L, ldl, x, 1);
  }
  static cublasStatus_t gemv(cublasHandle_t h, int m, int n, const double* A, int lda, const double* x, double* y) {
    const double one = 1.0, zero = 0.0;
    return cublasDgemv(h, CUBLAS_OP_N, m, n, &one, A, lda, x, 1, &zero, y, 1);
  }
  static cusolverStatus_t potrfBufferSize(cusolverDnHandle_t h, int n, double* A, int lda, int* lwork) {
    return cusolverDnDpotrf_bufferSize(h, CUBLAS_FILL_MODE_LOWER, n, A, lda, lwork);
  }
  static cusolverStatus_t potrf(cusolverDnHandle_t h, int n, double* A, int lda, double* work, int lwork,
                                int* info) {
    return cusolverDnDpotrf(h, CUBLAS_FILL_MODE_LOWER, n, A, lda, work, lwork, info);
  }
  // FP64 only: the products of the partitioned backend (partitioned_cuda_backend.cpp).
  // C = alpha op(A) op(B) + beta C.
  static cublasStatus_t gemm(cublasHandle_t h, bool trans_a, bool trans_b, int m, int n, int k, double alpha,
                             const double* A, int lda, const double* B, int ldb, double beta, double* C, int ldc) {
    return cublasDgemm(h, trans_a ? CUBLAS_OP_T : CUBLAS_OP_N, trans_b ? CUBLAS_OP_T : CUBLAS_OP_N, m, n, k, &alpha,
                       A, lda, B, ldb, &beta, C, ldc);
  }
  // C = alpha B S + beta C, S symmetric n x n read from its lower triangle, B m x n.
  static cublasStatus_t symmRight(cublasHandle_t h, int m, int n, double alpha, const double* S, int lds,
                                  const double* B, int ldb, double beta, double* C, int ldc) {
    return cublasDsymm(h, CUBLAS_SIDE_RIGHT, CUBLAS_FILL_MODE_LOWER, m, n, &alpha, S, lds, B, ldb, &beta, C, ldc);
  }
  // C = alpha S B + beta C, S symmetric m x m read from its lower triangle, B m x n.
  static cublasStatus_t symmLeft(cublasHandle_t h, int m, int n, double alpha, const double* S, int lds,
                                 const double* B, int ldb, double beta, double* C, int ldc) {
    return cublasDsymm(h, CUBLAS_SIDE_LEFT, CUBLAS_FILL_MODE_LOWER, m, n, &alpha, S, lds, B, ldb, &beta, C, ldc);
  }
  // lower(C) = alpha A^T A + beta C, A k x n.
  static cublasStatus_t syrkT(cublasHandle_t h, int n, int k, double alpha, const double* A, int lda, double beta,
                              double* C, int ldc) {
    return cublasDsyrk(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_T, n, k, &alpha, A, lda, &beta, C, ldc);
  }
  // lower(C) = alpha A B^T + beta C where A B^T is symmetric (A, B n x k).
  static cublasStatus_t syrkx(cublasHandle_t h, int n, int k, double alpha, const double* A, int lda,
                              const double* B, int ldb, double beta, double* C, int ldc) {
    return cublasDsyrkx(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_N, n, k, &alpha, A, lda, B, ldb, &beta, C, ldc);
  }
  // B <- L^-1 B (L lower m x m, B m x n).
  static cublasStatus_t trsmLeftLower(cublasHandle_t h, int m, int n, const double* L, int ldl, double* B, int ldb) {
    const double one = 1.0;
    return cublasDtrsm(h, CUBLAS_SIDE_LEFT, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_N, CUBLAS_DIAG_NON_UNIT, m, n, &one, L,
                       ldl, B, ldb);
  }
  // y = A^T x (A m x n).
  static cublasStatus_t gemvT(cublasHandle_t h, int m, int n, const double* A, int lda, const double* x, double* y) {
    const double one = 1.0, zero = 0.0;
    return cublasDgemv(h, CUBLAS_OP_T, m, n, &one, A, lda, x, 1, &zero, y, 1);
  }
  // C_i = A_i B_i^T for `count` blocks at fixed strides (A_i m x k, B_i n x k).
  static cublasStatus_t gemmNTBatched(cublasHandle_t h, int m, int n, int k, const double* A, int lda,
                                      long long stride_a, const double* B, int ldb, long long stride_b, double* C,
                                      int ldc, long long stride_c, int count) {
    const double one = 1.0, zero = 0.0;
    return cublasDgemmStridedBatched(h, CUBLAS_OP_N, CUBLAS_OP_T, m, n, k, &one, A, lda, stride_a, B, ldb, stride_b,
                                     &zero, C, ldc, stride_c, count);
  }
};

template <>
struct Blas<float> {
  static constexpr cudaDataType kType = CUDA_R_32F;
  static cublasStatus_t syrk(cublasHandle_t h, int n, int k, float alpha, const float* A, int lda, float beta,
                             float* C, int ldc) {
    return cublasSsyrk(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_N, n, k, &alpha, A, lda, &beta, C, ldc);
  }
  static cublasStatus_t gemmNT(cublasHandle_t h, int m, int n, int k, float alpha, const float* A, int lda,
                               const float* B, int ldb, float beta, float* C, int ldc) {
    return cublasSgemm(h, CUBLAS_OP_N, CUBLAS_OP_T, m, n, k, &alpha, A, lda, B, ldb, &beta, C, ldc);
  }
  static cublasStatus_t trsmRightLowerT(cublasHandle_t h, int m, int n, const float* L, int ldl, float* B, int ldb) {
    const float one = 1.0f;
    return cublasStrsm(h, CUBLAS_SIDE_RIGHT, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_T, CUBLAS_DIAG_NON_UNIT, m, n, &one,
                       L, ldl, B, ldb);
  }
  static cublasStatus_t trsvLower(cublasHandle_t h, int n, const float* L, int ldl, float* x) {
    return cublasStrsv(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_OP_N, CUBLAS_DIAG_NON_UNIT, n, L, ldl, x, 1);
  }
  static cublasStatus_t gemv(cublasHandle_t h, int m, int n, const float* A, int lda, const float* x, float* y) {
    const float one = 1.0f, zero = 0.0f;
    return cublasSgemv(h, CUBLAS_OP_N, m, n, &one, A, lda, x, 1, &zero, y, 1);
  }
  static cusolverStatus_t potrfBufferSize(cusolverDnHandle_t h, int n, float* A, int lda, int* lwork) {
    return cusolverDnSpotrf_bufferSize(h, CUBLAS_FILL_MODE_LOWER, n, A, lda, lwork);
  }
  static cusolverStatus_t potrf(cusolverDnHandle_t h, int n, float* A, int lda, float* work, int lwork, int* info) {
    return cusolverDnSpotrf(h, CUBLAS_FILL_MODE_LOWER, n, A, lda, work, lwork, info);
  }
};

// In-place inverse of a lower-triangular L (n x n, leading dim n): cuSOLVER's
// trtri, precision from Blas<T>::kType. Buffers are the caller's (sizes from
// trtriBufferSize). The strictly upper triangle is left as it was.
template <typename T>
cusolverStatus_t trtriBufferSize(cusolverDnHandle_t h, int n, T* L, std::size_t* device_bytes,
                                 std::size_t* host_bytes) {
  return cusolverDnXtrtri_bufferSize(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_DIAG_NON_UNIT, n, Blas<T>::kType, L, n,
                                     device_bytes, host_bytes);
}
template <typename T>
cusolverStatus_t trtri(cusolverDnHandle_t h, int n, T* L, void* device_work, std::size_t device_bytes,
                       void* host_work, std::size_t host_bytes, int* info) {
  return cusolverDnXtrtri(h, CUBLAS_FILL_MODE_LOWER, CUBLAS_DIAG_NON_UNIT, n, Blas<T>::kType, L, n, device_work,
                          device_bytes, host_work, host_bytes, info);
}

// C <- C - A A^T on the lower triangle of the leading n x n block, three
// schedules of the same n^2 k flops (EskfSettings::cuda_rank_update; the bench
// times each on the device, docs/BENCHMARKS.md):
//  * kSyrk: one cuBLAS SYRK;
//  * kPanelGemm: column panels of width `panel`, one GEMM each
//    (C[j:, j:j+b] -= A[j:, :] A[j:j+b, :]^T; the few upper entries of each
//    diagonal panel are scratch under the storage contract);
//  * kRecursive: the triangle halved recursively: the square lower-left block
//    of each level is ONE GEMM (few, large, square GEMMs: cuBLAS's best rate
//    for k = 3L is on square shapes), the two diagonal halves recurse, down to
//    diagonal blocks of at most `panel` rows, done by SYRK. No wasted flops.
// kAuto takes autoRankUpdate(n).

template <typename T>
cublasStatus_t rankUpdateRecursive(cublasHandle_t h, int n, int k, const T* A, int lda, T* C, std::size_t ldc,
                                   int leaf) {
  if (n <= leaf) return Blas<T>::syrk(h, n, k, T(-1), A, lda, T(1), C, static_cast<int>(ldc));
  int h1 = ((n / 2 + 127) / 128) * 128;  // split on a 128-row grid (whole GEMM tiles)
  if (h1 >= n) h1 = n / 2;
  cublasStatus_t s = Blas<T>::gemmNT(h, n - h1, h1, k, T(-1), A + h1, lda, A, lda, T(1), C + h1, static_cast<int>(ldc));
  if (s != CUBLAS_STATUS_SUCCESS) return s;
  s = rankUpdateRecursive<T>(h, h1, k, A, lda, C, ldc, leaf);
  if (s != CUBLAS_STATUS_SUCCESS) return s;
  return rankUpdateRecursive<T>(h, n - h1, k, A + h1, lda, C + h1 + static_cast<std::size_t>(h1) * ldc, ldc, leaf);
}

inline CudaRankUpdate autoRankUpdate(int n);

template <typename T>
cublasStatus_t rankUpdate(cublasHandle_t h, CudaRankUpdate how, int n, int k, const T* A, int lda, T* C,
                          std::size_t ldc, int panel) {
  if (n <= 0 || k <= 0) return CUBLAS_STATUS_SUCCESS;
  if (how == CudaRankUpdate::kAuto) how = autoRankUpdate(n);
  if (how == CudaRankUpdate::kSyrk) return Blas<T>::syrk(h, n, k, T(-1), A, lda, T(1), C, static_cast<int>(ldc));
  if (how == CudaRankUpdate::kRecursive) return rankUpdateRecursive<T>(h, n, k, A, lda, C, ldc, panel);
  for (int j = 0; j < n; j += panel) {
    const int b = n - j < panel ? n - j : panel;
    const cublasStatus_t s = Blas<T>::gemmNT(h, n - j, b, k, T(-1), A + j, lda, A + j, lda, T(1),
                                             C + j + static_cast<std::size_t>(j) * ldc, static_cast<int>(ldc));
    if (s != CUBLAS_STATUS_SUCCESS) return s;
  }
  return CUBLAS_STATUS_SUCCESS;
}

// Panel width (kPanelGemm) / largest diagonal leaf (kRecursive): a few percent
// of extra flops on the diagonal panels against GEMMs large enough to run at
// full rate.
inline int defaultPanel(int n) {
  int p = ((n / 24 + 255) / 256) * 256;
  return p < 512 ? 512 : (p > 4096 ? 4096 : p);
}

// Schedule and solve chosen by size (the kAuto settings), from
// the H100 runs of docs/BENCHMARKS.md: one SYRK is fastest while launches
// dominate (K <= 2000), the panelled GEMM around K = 4000, the recursive
// schedule from K = 8000 up (isolated at K = 32000: 111.7 ms vs 117.5 SYRK,
// 121.4 panelled); TRSM beats trtri + GEMM below n ~ 20000 (K = 4000: 0.56 vs
// 0.78 ms) and loses above (K = 32000: 3.9 vs 2.3 ms). In the filter at
// K = 32000 this choice takes 131.0 ms per iteration against 142.2 for the
// previous fixed panelled GEMM + TRSM (alternated A/B, same call).
inline CudaRankUpdate autoRankUpdate(int n) {
  return n < 8192 ? CudaRankUpdate::kSyrk : (n < 16384 ? CudaRankUpdate::kPanelGemm : CudaRankUpdate::kRecursive);
}
inline bool autoSolveByInverse(int n) { return n >= 20000; }

// Leading dimension of C and the n x 3m workspaces for n rows: a multiple of
// 32 elements, so every column starts on a 256-byte boundary (whole memory
// sectors and aligned GEMM tiles; ld = 96012 put column starts at 4 different
// offsets within 128 bytes).
inline std::size_t paddedLd(int n) { return (static_cast<std::size_t>(n) + 31) / 32 * 32; }

}  // namespace cuda
}  // namespace hapi_eskf
