// OpenBLAS/LAPACK or Eigen for the CPU backends' large products
// (cpu_linear_algebra.hpp). The BLAS entry points are the Fortran ABI that
// OpenBLAS exports (its own C implementations, no hidden string lengths
// needed), declared here so that no cblas.h/lapacke.h alternative (ATLAS,
// netlib) can be picked up by the include path instead of OpenBLAS's.
#include "cpu_linear_algebra.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cstddef>

namespace hapi_eskf {
namespace cpu_la {

#ifdef HAPI_ESKF_WITH_BLAS
extern "C" {
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* A,
            const int* lda, const double* beta, double* C, const int* ldc);
void dgemm_(const char* ta, const char* tb, const int* m, const int* n, const int* k, const double* alpha,
            const double* A, const int* lda, const double* B, const int* ldb, const double* beta, double* C,
            const int* ldc);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* A, const int* lda, double* B, const int* ldb);
void dpotrf_(const char* uplo, const int* n, double* A, const int* lda, int* info);
void dpotri_(const char* uplo, const int* n, double* A, const int* lda, int* info);
void openblas_set_num_threads(int num_threads);
}
bool blasCompiledIn() { return true; }
#else
bool blasCompiledIn() { return false; }
#endif

void setBlasThreads(int n) {
#ifdef HAPI_ESKF_WITH_BLAS
  if (n > 0) openblas_set_num_threads(n);
#else
  (void)n;
#endif
}

CpuLinearAlgebra effective(CpuLinearAlgebra la) { return blasCompiledIn() ? la : CpuLinearAlgebra::kEigen; }

namespace {
#ifdef HAPI_ESKF_WITH_BLAS
bool useBlas(CpuLinearAlgebra la) { return la == CpuLinearAlgebra::kBlas; }
int ld(const MatrixXd& M) { return M.rows() > 0 ? static_cast<int>(M.rows()) : 1; }
#endif
}  // namespace

void rankUpdateLower(CpuLinearAlgebra la, MatRef C, const MatrixXd& A, double alpha) {
  if (C.rows() == 0 || A.cols() == 0) return;
#ifdef HAPI_ESKF_WITH_BLAS
  if (useBlas(la)) {
    const int n = static_cast<int>(C.rows()), k = static_cast<int>(A.cols()), ldc = static_cast<int>(C.outerStride());
    const double beta = 1.0;
    dsyrk_("L", "N", &n, &k, &alpha, A.data(), &n, &beta, C.data(), &ldc);
    return;
  }
#endif
  (void)la;
  C.selfadjointView<Eigen::Lower>().rankUpdate(A, alpha);
}

void productUpdateLower(CpuLinearAlgebra la, MatRef C, const MatrixXd& A, const MatrixXd& B, double alpha) {
  if (C.rows() == 0 || A.cols() == 0) return;
#ifdef HAPI_ESKF_WITH_BLAS
  if (useBlas(la)) {
    // Panels of kPanel columns: C(j:n, j:j+w) += alpha A(j:n, :) B(j:j+w, :)^T;
    // only the diagonal w x w blocks compute entries above the diagonal
    // (scratch under the storage contract), a w/n share of the flops.
    constexpr int kPanel = 256;
    const int n = static_cast<int>(C.rows()), k = static_cast<int>(A.cols()), ldc = static_cast<int>(C.outerStride());
    const double beta = 1.0;
    for (int j = 0; j < n; j += kPanel) {
      const int w = std::min(kPanel, n - j), h = n - j;
      dgemm_("N", "T", &h, &w, &k, &alpha, A.data() + j, &n, B.data() + j, &n, &beta,
             C.data() + static_cast<std::ptrdiff_t>(j) * ldc + j, &ldc);
    }
    return;
  }
#endif
  (void)la;
  C.triangularView<Eigen::Lower>() += alpha * A * B.transpose();
}

void gemm(CpuLinearAlgebra la, bool trans_a, bool trans_b, double alpha, const MatrixXd& A, const MatrixXd& B,
          double beta, MatrixXd* C) {
  const int m = static_cast<int>(trans_a ? A.cols() : A.rows());
  const int n = static_cast<int>(trans_b ? B.rows() : B.cols());
  const int k = static_cast<int>(trans_a ? A.rows() : A.cols());
  if (C->rows() != m || C->cols() != n) {
    C->setZero(m, n);
    beta = 0.0;
  }
  if (m == 0 || n == 0) return;
  if (k == 0) {
    *C *= beta;
    return;
  }
#ifdef HAPI_ESKF_WITH_BLAS
  if (useBlas(la)) {
    const int ldc = m, lda = ld(A), ldb = ld(B);
    dgemm_(trans_a ? "T" : "N", trans_b ? "T" : "N", &m, &n, &k, &alpha, A.data(), &lda, B.data(), &ldb, &beta,
           C->data(), &ldc);
    return;
  }
#endif
  (void)la;
  MatrixXd prod = trans_a ? (trans_b ? MatrixXd(A.transpose() * B.transpose()) : MatrixXd(A.transpose() * B))
                          : (trans_b ? MatrixXd(A * B.transpose()) : MatrixXd(A * B));
  if (beta == 0.0) *C = alpha * prod;
  else *C = alpha * prod + beta * *C;
}

bool choleskyLower(CpuLinearAlgebra la, MatrixXd* S) {
  const int n = static_cast<int>(S->rows());
  if (n == 0) return true;
#ifdef HAPI_ESKF_WITH_BLAS
  if (useBlas(la)) {
    int info = 0;
    dpotrf_("L", &n, S->data(), &n, &info);
    S->triangularView<Eigen::StrictlyUpper>().setZero();
    return info == 0;
  }
#endif
  (void)la;
  Eigen::LLT<MatrixXd> llt(*S);
  if (llt.info() != Eigen::Success) return false;
  *S = llt.matrixL();
  return true;
}

bool inverseSymmetric(CpuLinearAlgebra la, MatrixXd* S) {
  const int n = static_cast<int>(S->rows());
  if (!choleskyLower(la, S)) return false;
  if (n == 0) return true;
  bool ok = true;
#ifdef HAPI_ESKF_WITH_BLAS
  if (useBlas(la)) {
    int info = 0;
    dpotri_("L", &n, S->data(), &n, &info);
    ok = info == 0;
  } else  // NOLINT(readability/braces): the Eigen path below
#endif
  {
    MatrixXd L_inv = MatrixXd::Identity(n, n);  // S^-1 = L^-T L^-1, lower triangle
    S->triangularView<Eigen::Lower>().solveInPlace(L_inv);
    S->setZero();
    S->selfadjointView<Eigen::Lower>().rankUpdate(L_inv.transpose());
  }
  S->triangularView<Eigen::StrictlyUpper>() = S->transpose();
  return ok && S->allFinite();
}

void solveRightLowerTransposed(CpuLinearAlgebra la, const MatrixXd& L, MatrixXd* X) {
  if (X->size() == 0) return;
#ifdef HAPI_ESKF_WITH_BLAS
  if (useBlas(la)) {
    const int m = static_cast<int>(X->rows()), n = static_cast<int>(X->cols()), lda = ld(L);
    const double one = 1.0;
    dtrsm_("R", "L", "T", "N", &m, &n, &one, L.data(), &lda, X->data(), &m);
    return;
  }
#endif
  (void)la;
  L.triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(*X);
}

void solveLeftLower(CpuLinearAlgebra la, const MatrixXd& L, MatrixXd* X) {
  if (X->size() == 0) return;
#ifdef HAPI_ESKF_WITH_BLAS
  if (useBlas(la)) {
    const int m = static_cast<int>(X->rows()), n = static_cast<int>(X->cols()), lda = ld(L);
    const double one = 1.0;
    dtrsm_("L", "L", "N", "N", &m, &n, &one, L.data(), &lda, X->data(), &m);
    return;
  }
#endif
  (void)la;
  L.triangularView<Eigen::Lower>().solveInPlace(*X);
}

}  // namespace cpu_la
}  // namespace hapi_eskf
