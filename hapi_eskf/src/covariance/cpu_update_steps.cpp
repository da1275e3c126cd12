// The update steps shared by the CPU backends (cpu_update_steps.hpp,
// docs/DESIGN.md "Update").
#include "cpu_update_steps.hpp"

#include "lower_triangle.hpp"

#include <algorithm>
#include <cmath>

namespace hapi_eskf {
namespace cpu_update {

using Eigen::MatrixXd;
using Eigen::VectorXd;

Status factorInnovationCovariance(CpuLinearAlgebra la, const MatrixXd& S, MatrixXd* Lf) {
  if (!S.allFinite()) return Status::kNonFinite;
  *Lf = S;
  if (!cpu_la::choleskyLower(la, Lf)) return Status::kNotPositiveDefinite;
  if (!(Lf->diagonal().minCoeff() > 1e-12 * std::sqrt(std::max(1e-300, S.diagonal().maxCoeff()))))
    return Status::kNotPositiveDefinite;
  return Status::kOk;
}

Status denseUpdateLower(CpuLinearAlgebra la, MatrixXd* C, int n, int Pdim, const std::vector<MeasurementBlock>& blocks,
                        VectorXd* dx, double* nis) {
  const int L = static_cast<int>(blocks.size());
  const int m = 3 * L;
  // 1. P = C H^T by gathering: the 6 pose columns once, then 3 landmark
  //    columns per measurement (full columns rebuilt from the lower triangle).
  MatrixXd Cx6(n, 6);
  lower_triangle::gatherColumns(*C, 0, 6, n, Cx6);
  MatrixXd P(n, m);
  MatrixXd G3(n, 3);
  for (int j = 0; j < L; ++j) {
    const auto& b = blocks[j];
    lower_triangle::gatherColumns(*C, landmarkRow(b.slot, Pdim), 3, n, G3);
    P.middleCols<3>(3 * j).noalias() = Cx6 * b.H_pose.transpose();
    P.middleCols<3>(3 * j).noalias() += G3 * b.H_landmark.transpose();
  }
  // 2. S = H P + R (only the rows of P that H touches), symmetrised, factorised.
  MatrixXd S(m, m);
  VectorXd z(m);
  for (int i = 0; i < L; ++i) {
    const auto& b = blocks[i];
    const int r = landmarkRow(b.slot, Pdim);
    S.middleRows<3>(3 * i).noalias() = b.H_pose * P.topRows<6>();
    S.middleRows<3>(3 * i).noalias() += b.H_landmark * P.middleRows<3>(r);
    z.segment<3>(3 * i) = b.innovation;
  }
  for (int i = 0; i < L; ++i) S.block<3, 3>(3 * i, 3 * i) += blocks[i].R;
  S = (0.5 * (S + S.transpose())).eval();
  MatrixXd Lf;
  const Status st = factorInnovationCovariance(la, S, &Lf);
  if (st != Status::kOk) return st;
  // 3. A = P L^-T (triangular solve from the right), y = L^-1 z, dx = A y.
  cpu_la::solveRightLowerTransposed(la, Lf, &P);
  const VectorXd y = Lf.triangularView<Eigen::Lower>().solve(z);
  VectorXd dxn = P * y;
  if (!dxn.allFinite()) return Status::kNonFinite;
  // 4. C <- C - A A^T on the lower triangle only (SYRK).
  cpu_la::rankUpdateLower(la, cpu_la::MatRef(C->data(), n, n, Eigen::OuterStride<>(C->rows())), P, -1.0);
  *dx = std::move(dxn);
  if (nis) *nis = y.squaredNorm();
  return Status::kOk;
}

}  // namespace cpu_update
}  // namespace hapi_eskf
