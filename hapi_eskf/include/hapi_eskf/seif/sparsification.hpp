// The SEIF's sparsification step (docs/DESIGN.md "SEIF"; Thrun et al.,
// Probabilistic Robotics 12.4.3) on a dense gather of the information matrix
// over L = [x, m+, m0]: the pose x (the first P rows), the landmarks that stay
// active m+ (the next keep_rows rows) and the ones whose pose links are
// removed m0 (the remaining rows), passive landmarks conditioned away:
//   Omega~ = Omega - T(m0) + T(x, m0) - T(x),  T(S) = Omega_.S Omega_SS^-1 Omega_S.
// Evaluated without forming T(m0) or T(x, m0): with A = Omega_m0m0,
// B = Omega_m0x, D = Omega_xx, the block inverse of Omega over [x, m0] gives
//   T(x, m0) - T(m0) = V S^-1 V^T,  V = Omega_.x - Omega_.m0 A^-1 B,
//   S = D - B^T A^-1 B,
// so Omega~ = Omega + V S^-1 V^T - Omega_.x D^-1 Omega_x.: one Cholesky
// factor of A with P right-hand sides and two rank-P updates, instead of two
// products through (|m0| + P)-sized inverses with |L| right-hand sides.
// V's m0 rows vanish, hence so do the x-m0 blocks of Omega~ (set to zero
// exactly). Returns false (Omega~ untouched) when A, S or D is not positive
// definite or the result is not finite.
#pragma once

#include <Eigen/Core>

namespace hapi_eskf {
namespace seif {

bool sparsifiedInformation(const Eigen::MatrixXd& omega, int pose_dim, int keep_rows, Eigen::MatrixXd* out);

}  // namespace seif
}  // namespace hapi_eskf
