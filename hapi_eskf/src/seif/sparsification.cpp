// The SEIF's sparsification step (sparsification.hpp).
#include "hapi_eskf/seif/sparsification.hpp"

#include <Eigen/Cholesky>

namespace hapi_eskf {
namespace seif {

bool sparsifiedInformation(const Eigen::MatrixXd& omega, int pose_dim, int keep_rows, Eigen::MatrixXd* out) {
  using Eigen::MatrixXd;
  const int n = static_cast<int>(omega.rows()), P = pose_dim, m0 = P + keep_rows, n0 = n - m0;
  if (n0 <= 0) {
    *out = omega;
    return true;
  }
  const Eigen::LLT<MatrixXd> llt_a(omega.block(m0, m0, n0, n0));
  if (llt_a.info() != Eigen::Success) return false;
  const MatrixXd AinvB = llt_a.solve(omega.block(m0, 0, n0, P));  // A^-1 B
  MatrixXd V = omega.leftCols(P);
  V.noalias() -= omega.rightCols(n0) * AinvB;
  const MatrixXd S = omega.topLeftCorner(P, P) - omega.block(m0, 0, n0, P).transpose() * AinvB;
  const Eigen::LLT<MatrixXd> llt_s(0.5 * (S + S.transpose()));
  const Eigen::LLT<MatrixXd> llt_d(omega.topLeftCorner(P, P));
  if (llt_s.info() != Eigen::Success || llt_d.info() != Eigen::Success) return false;
  const MatrixXd Wv = llt_s.matrixL().solve(V.transpose());               // L_S^-1 V^T
  const MatrixXd Wx = llt_d.matrixL().solve(omega.leftCols(P).transpose());  // L_D^-1 Omega_x.
  MatrixXd result = omega;
  result.noalias() += Wv.transpose() * Wv;
  result.noalias() -= Wx.transpose() * Wx;
  result.block(0, m0, P, n0).setZero();
  result.block(m0, 0, n0, P).setZero();
  if (!result.allFinite()) return false;
  *out = std::move(result);
  return true;
}

}  // namespace seif
}  // namespace hapi_eskf
