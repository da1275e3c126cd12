// The frame-shared vision error's transitions (frame_error_block.hpp).
#include "hapi_eskf/eskf/frame_error_block.hpp"

#include "hapi_eskf/eskf/motion_model.hpp"

namespace hapi_eskf {

bool frameErrorModelled(const EskfSettings& s) {
  return s.backend_algorithm != BackendAlgorithm::kSeif && s.motion_model != MotionModelKind::kConstantVelocity &&
         s.anyFrameError();
}

int filterPoseDim(const EskfSettings& s) {
  const int model_dim = poseDim(s);
  return frameErrorModelled(s) ? model_dim + kFrameErrorDim : model_dim;
}

FrameErrorBlock::FrameErrorBlock(int model_dim, const EskfSettings& s)
    : model_dim_(model_dim), enabled_(frameErrorModelled(s)), sigma_camera_(s.frameErrorCameraCovariance()) {}

PoseMat FrameErrorBlock::embed(const PoseMat& M, double spare_diagonal) const {
  if (!enabled_) return M;
  PoseMat out = spare_diagonal * PoseMat::Identity(filterDim(), filterDim());
  out.topLeftCorner(model_dim_, model_dim_) = M;
  return out;
}

PoseMat FrameErrorBlock::transition(const PoseMat& F) const { return embed(F, 1.0); }
PoseMat FrameErrorBlock::noise(const PoseMat& Q) const { return embed(Q, 0.0); }
PoseMat FrameErrorBlock::covariance(const PoseMat& C) const { return embed(C, 1.0); }

Mat6 FrameErrorBlock::stateCovariance(const Mat6& camera_jacobian) const {
  const Mat6 J_inv = camera_jacobian.inverse();
  const Mat6 S = J_inv * sigma_camera_ * J_inv.transpose();
  return 0.5 * (S + S.transpose());
}

Status FrameErrorBlock::open(CovarianceBackend* backend, const Mat6& camera_jacobian) {
  if (!enabled_ || open_) return Status::kOk;
  const int n = filterDim(), s = model_dim_;
  PoseMat F = PoseMat::Identity(n, n), Q = PoseMat::Zero(n, n);
  // spare <- [dp, dtheta]; [dp, dtheta] <- [dp, dtheta] + n.
  F.block(s, s, kFrameErrorDim, kFrameErrorDim).setZero();
  F.block(s, 0, kFrameErrorDim, kFrameErrorDim).setIdentity();
  Q.topLeftCorner(kFrameErrorDim, kFrameErrorDim) = stateCovariance(camera_jacobian);
  const Status st = backend->predict(F, Q);
  if (st == Status::kOk) open_ = true;
  return st;
}

Status FrameErrorBlock::close(CovarianceBackend* backend) {
  if (!open_) return Status::kOk;
  const int n = filterDim(), s = model_dim_;
  PoseMat F = PoseMat::Identity(n, n), Q = PoseMat::Zero(n, n);
  // [dp, dtheta] <- spare; spare <- 0 + an uncorrelated identity.
  F.topLeftCorner(kFrameErrorDim, kFrameErrorDim).setZero();
  F.block(0, s, kFrameErrorDim, kFrameErrorDim).setIdentity();
  F.block(s, s, kFrameErrorDim, kFrameErrorDim).setZero();
  Q.block(s, s, kFrameErrorDim, kFrameErrorDim).setIdentity();
  const Status st = backend->predict(F, Q);
  if (st == Status::kOk) open_ = false;
  return st;
}

Eigen::VectorXd FrameErrorBlock::poseCorrection(const Eigen::VectorXd& dx) const {
  Eigen::VectorXd d = dx.head(model_dim_);
  if (open_) d.head(kFrameErrorDim) = dx.segment(model_dim_, kFrameErrorDim);
  return d;
}

}  // namespace hapi_eskf
