// The CPU backends' dense products and factorisations, on OpenBLAS/LAPACK
// (DSYRK, DGEMM, DPOTRF, DTRSM) or on Eigen alone, chosen per call
// (setting cpu_linear_algebra), so one binary can compare both (tests, bench).
// Matrices are column-major; a "lower" operand has only its lower triangle
// read or written, as in the backends' storage contract. Small blocks (3 x 3,
// 9 x 9, gathers) stay in Eigen in the callers.
#pragma once

#include "hapi_eskf/settings.hpp"

#include <Eigen/Core>

namespace hapi_eskf {
namespace cpu_la {

using Eigen::MatrixXd;
// A column-major block of a larger buffer (the capacity-sized C).
using MatRef = Eigen::Map<MatrixXd, 0, Eigen::OuterStride<>>;

// True when hapi_eskf was built with OpenBLAS (HAPI_ESKF_WITH_BLAS); without
// it every function runs the Eigen path whatever `la` says.
bool blasCompiledIn();
// Sets OpenBLAS's thread count for the process (n > 0; no-op without BLAS).
void setBlasThreads(int n);
// The path a call with `la` takes in this build.
CpuLinearAlgebra effective(CpuLinearAlgebra la);

// lower(C) += alpha A A^T (C n x n, A n x k).
void rankUpdateLower(CpuLinearAlgebra la, MatRef C, const MatrixXd& A, double alpha);
// lower(C) += alpha A B^T (C n x n, A and B n x k, A B^T symmetric: only
// its lower triangle is formed; column panels of DGEMM on the BLAS path,
// Eigen's triangular product otherwise). Half the flops of a
// DSYR2K on (A, B).
void productUpdateLower(CpuLinearAlgebra la, MatRef C, const MatrixXd& A, const MatrixXd& B, double alpha);
// C = alpha A B + beta C, with op(X) = X^T where the flag says so.
void gemm(CpuLinearAlgebra la, bool trans_a, bool trans_b, double alpha, const MatrixXd& A, const MatrixXd& B,
          double beta, MatrixXd* C);
// Lower Cholesky factor of the symmetric S in place (the upper triangle is
// zeroed); false when S is not positive definite (a non-positive pivot).
bool choleskyLower(CpuLinearAlgebra la, MatrixXd* S);
// S <- S^-1 for a symmetric positive definite S (its lower triangle read;
// the whole inverse written): DPOTRF + DPOTRI (n^3 flops) or Eigen's LLT and
// a solve of the identity. False when S is not positive definite.
bool inverseSymmetric(CpuLinearAlgebra la, MatrixXd* S);
// X <- X L^-T (triangular solve from the right, L lower, X m x k).
void solveRightLowerTransposed(CpuLinearAlgebra la, const MatrixXd& L, MatrixXd* X);
// X <- L^-1 X (triangular solve from the left, L lower).
void solveLeftLower(CpuLinearAlgebra la, const MatrixXd& L, MatrixXd* X);

}  // namespace cpu_la
}  // namespace hapi_eskf
