// The zero-velocity update through a transition (zero_velocity_update.hpp).
#include "hapi_eskf/eskf/zero_velocity_update.hpp"

#include "hapi_eskf/so3.hpp"

#include <Eigen/Cholesky>

#include <vector>

namespace hapi_eskf {

ZeroVelocityUpdate::ZeroVelocityUpdate(double velocity_sigma, double gate_chi2, int filter_pose_dim)
    : variance_(velocity_sigma * velocity_sigma), gate_chi2_(gate_chi2),
      swap_(PoseMat::Identity(filter_pose_dim, filter_pose_dim)) {
  swap_.block<3, 3>(kIdxP, kIdxP).setZero();
  swap_.block<3, 3>(kIdxV, kIdxV).setZero();
  swap_.block<3, 3>(kIdxP, kIdxV).setIdentity();
  swap_.block<3, 3>(kIdxV, kIdxP).setIdentity();
}

Eigen::Matrix<double, 3, Eigen::Dynamic> meanVelocityJacobian(bool inertial, const Mat3& R_wb, const Vec3& a,
                                                              double dt, int pose_dim) {
  Eigen::Matrix<double, 3, Eigen::Dynamic> J = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, pose_dim);
  J.block<3, 3>(0, kIdxV).setIdentity();
  if (!inertial) return J;
  J.block<3, 3>(0, kIdxTheta) = 0.5 * dt * R_wb * skew(a);
  J.block<3, 3>(0, kIdxBa) = 0.5 * dt * R_wb;
  J.block<3, 3>(0, kIdxG) = -0.5 * dt * Mat3::Identity();
  return J;
}

Status ZeroVelocityUpdate::apply(CovarianceBackend* backend, const Vec3& v_hat,
                                 const Eigen::Matrix<double, 3, Eigen::Dynamic>& J, ZeroVelocityStatus* status,
                                 Eigen::VectorXd* dx) const {
  status->tested = true;
  status->fused = false;
  const int P = static_cast<int>(swap_.rows());
  if (J.cols() > P) return Status::kInvalidArgument;
  // E = I + N: the dv rows become J (N: J off its dv block).
  PoseMat N = PoseMat::Zero(P, P);
  N.block(kIdxV, 0, 3, J.cols()) = J;
  N.block<3, 3>(kIdxV, kIdxV).setZero();
  const PoseMat I = PoseMat::Identity(P, P);
  const PoseMat T = swap_ * (I + N), T_inverse = (I - N) * swap_;
  const PoseMat C = backend->poseCovariance();
  const Mat3 S = J * C.topLeftCorner(J.cols(), J.cols()) * J.transpose() + variance_ * Mat3::Identity();
  status->innovation = -v_hat;
  status->innovation_variance = S.diagonal();
  const Eigen::LLT<Mat3> llt(S);
  if (llt.info() != Eigen::Success) return Status::kOk;
  status->test_ratio = status->innovation.dot(llt.solve(status->innovation)) / gate_chi2_;
  if (!(status->test_ratio <= 1.0) || backend->numLandmarks() == 0) return Status::kOk;

  const PoseMat no_noise = PoseMat::Zero(P, P);
  const Status swapped = backend->predict(T, no_noise);
  if (swapped != Status::kOk) return swapped;
  MeasurementBlock b;
  b.slot = 0;
  b.H_pose.leftCols<3>().setIdentity();
  b.H_landmark.setZero();
  b.R = variance_ * Mat3::Identity();
  b.innovation = status->innovation;
  const Status updated = backend->update({b}, dx);
  const Status restored = backend->predict(T_inverse, no_noise);
  if (restored != Status::kOk) return restored;
  // S not PD or a non-finite result: C is unchanged and the frame goes on
  // without the update, as after a skipped vision update.
  if (updated == Status::kNotPositiveDefinite || updated == Status::kNonFinite) return Status::kOk;
  if (updated != Status::kOk) return updated;
  dx->head(P) = (T_inverse * dx->head(P)).eval();
  status->fused = true;
  return Status::kOk;
}

}  // namespace hapi_eskf
