// The update steps the CPU backends share (docs/DESIGN.md "Update"): the
// checked Cholesky factor of S, and the whole dense update (steps 1-4) of a
// covariance stored by its lower triangle. The dense backend runs it for
// every update, the partitioned one after a flush (partitioned_cpu_backend.cpp).
#pragma once

#include "cpu_linear_algebra.hpp"
#include "hapi_eskf/covariance/covariance_backend.hpp"

#include <vector>

namespace hapi_eskf {
namespace cpu_update {

// S (m x m, symmetrised by the caller) -> lower factor L_S in *Lf. kNonFinite
// for a non-finite S; kNotPositiveDefinite when the factorisation fails or
// the factor is numerically singular (min diag(L_S) <= 1e-12 sqrt(max diag(S)),
// which would blow up the gain).
Status factorInnovationCovariance(CpuLinearAlgebra la, const Eigen::MatrixXd& S, Eigen::MatrixXd* Lf);

// Steps 1-4 on the lower triangle of the top-left n x n corner of *C (pose
// block of P rows): P = C H^T by gathering, S, L_S, A = P L_S^-T, y, dx = A y,
// C <- C - A A^T. C is untouched unless kOk.
Status denseUpdateLower(CpuLinearAlgebra la, Eigen::MatrixXd* C, int n, int P,
                        const std::vector<MeasurementBlock>& blocks, Eigen::VectorXd* dx, double* nis);

}  // namespace cpu_update
}  // namespace hapi_eskf
