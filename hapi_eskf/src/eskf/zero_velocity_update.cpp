// The zero-velocity update through a swap transition (zero_velocity_update.hpp).
#include "hapi_eskf/eskf/zero_velocity_update.hpp"

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

Status ZeroVelocityUpdate::apply(CovarianceBackend* backend, const Vec3& v_hat, ZeroVelocityStatus* status,
                                 Eigen::VectorXd* dx) const {
  status->tested = true;
  status->fused = false;
  const Mat3 S = backend->poseCovariance().block<3, 3>(kIdxV, kIdxV) + variance_ * Mat3::Identity();
  status->innovation = -v_hat;
  status->innovation_variance = S.diagonal();
  const Eigen::LLT<Mat3> llt(S);
  if (llt.info() != Eigen::Success) return Status::kOk;
  status->test_ratio = status->innovation.dot(llt.solve(status->innovation)) / gate_chi2_;
  if (!(status->test_ratio <= 1.0) || backend->numLandmarks() == 0) return Status::kOk;

  const PoseMat no_noise = PoseMat::Zero(swap_.rows(), swap_.cols());
  const Status swapped = backend->predict(swap_, no_noise);
  if (swapped != Status::kOk) return swapped;
  MeasurementBlock b;
  b.slot = 0;
  b.H_pose.leftCols<3>().setIdentity();
  b.H_landmark.setZero();
  b.R = variance_ * Mat3::Identity();
  b.innovation = status->innovation;
  const Status updated = backend->update({b}, dx);
  const Status restored = backend->predict(swap_, no_noise);
  if (restored != Status::kOk) return restored;
  // S not PD or a non-finite result: C is unchanged and the frame goes on
  // without the update, as after a skipped vision update.
  if (updated == Status::kNotPositiveDefinite || updated == Status::kNonFinite) return Status::kOk;
  if (updated != Status::kOk) return updated;
  const Vec3 d_first = dx->segment<3>(kIdxP);
  dx->segment<3>(kIdxP) = dx->segment<3>(kIdxV);
  dx->segment<3>(kIdxV) = d_first;
  status->fused = true;
  return Status::kOk;
}

}  // namespace hapi_eskf
