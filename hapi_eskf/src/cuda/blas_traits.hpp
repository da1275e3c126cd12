// Precision-generic thin wrappers over the cuBLAS / cuSOLVER calls the backend
// uses (FP64 default, FP32 option: settings.hpp Precision).
#pragma once

#include <cublas_v2.h>
#include <cusolverDn.h>

namespace hapi_eskf {
namespace cuda {

template <typename T>
struct Blas;

template <>
struct Blas<double> {
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
};

template <>
struct Blas<float> {
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

// C <- C - A A^T on the lower triangle of the leading n x n block: either one
// cuBLAS SYRK, or column panels of width `panel` each updated by one GEMM
// (C[j:, j:j+b] -= A[j:, :] A[j:j+b, :]^T; the few upper entries of each
// diagonal panel are scratch under the storage contract). The GEMM path runs
// cuBLAS's best kernels; the bench measures both (docs/BENCHMARKS.md).
enum class RankUpdate { kSyrk, kPanelGemm };

template <typename T>
cublasStatus_t rankUpdate(cublasHandle_t h, RankUpdate how, int n, int k, const T* A, int lda, T* C,
                          std::size_t ldc, int panel) {
  if (n <= 0 || k <= 0) return CUBLAS_STATUS_SUCCESS;
  if (how == RankUpdate::kSyrk) return Blas<T>::syrk(h, n, k, T(-1), A, lda, T(1), C, static_cast<int>(ldc));
  for (int j = 0; j < n; j += panel) {
    const int b = n - j < panel ? n - j : panel;
    const cublasStatus_t s = Blas<T>::gemmNT(h, n - j, b, k, T(-1), A + j, lda, A + j, lda, T(1),
                                             C + j + static_cast<std::size_t>(j) * ldc, static_cast<int>(ldc));
    if (s != CUBLAS_STATUS_SUCCESS) return s;
  }
  return CUBLAS_STATUS_SUCCESS;
}

// Panel width: a few percent of extra flops on the diagonal panels against
// GEMMs large enough to run at full rate.
inline int defaultPanel(int n) {
  int p = ((n / 24 + 255) / 256) * 256;
  return p < 512 ? 512 : (p > 4096 ? 4096 : p);
}

}  // namespace cuda
}  // namespace hapi_eskf
