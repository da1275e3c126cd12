// The online calibration's frame transitions (calibration_block.hpp).
#include "hapi_eskf/eskf/calibration_block.hpp"

#include "hapi_eskf/so3.hpp"

#include <algorithm>
#include <cmath>

namespace hapi_eskf {

PoseMat CalibrationBlock::cameraErrorTransition(const MotionModel& model, const NominalState& x) {
  const int P = model.poseDim();
  PoseMat T = PoseMat::Identity(P, P);
  T.topRows(6) = model.cameraStateJacobian(x).topRows<6>();
  return T;
}

// T = [[J, B], [0, I]] with J = T's top-left 6 x 6: T^-1 = [[J^-1, -J^-1 B], [0, I]].
PoseMat CalibrationBlock::inverseTransition(const PoseMat& T) {
  const int P = static_cast<int>(T.rows());
  const Mat6 J_inv = T.topLeftCorner<6, 6>().inverse();
  PoseMat T_inv = PoseMat::Identity(P, P);
  T_inv.topLeftCorner<6, 6>() = J_inv;
  T_inv.topRightCorner(6, P - 6) = -J_inv * T.topRightCorner(6, P - 6);
  return T_inv;
}

Status CalibrationBlock::open(CovarianceBackend* backend, const FrameErrorBlock& frame_error,
                              const MotionModel& model, const NominalState& x) {
  if (!enabled_ || open_) return Status::kOk;
  const PoseMat T = cameraErrorTransition(model, x);
  if (!T.allFinite()) return Status::kNonFinite;
  const int n = frame_error.filterDim();
  const Status st = backend->predict(frame_error.transition(T), PoseMat::Zero(n, n));
  if (st != Status::kOk) return st;
  T_inv_ = inverseTransition(T);
  open_ = true;
  return Status::kOk;
}

Status CalibrationBlock::close(CovarianceBackend* backend, const FrameErrorBlock& frame_error) {
  if (!open_) return Status::kOk;
  const int n = frame_error.filterDim();
  const Status st = backend->predict(frame_error.transition(T_inv_), PoseMat::Zero(n, n));
  if (st == Status::kOk) open_ = false;
  return st;
}

Eigen::VectorXd CalibrationBlock::stateCorrection(const Eigen::VectorXd& dx) const {
  if (!open_) return dx;
  return T_inv_ * dx;
}

CalibrationEstimate calibrationEstimate(const CalibrationLayout& layout, const PoseBlockState& s) {
  CalibrationEstimate e;
  auto sigma = [&](int row) { return std::sqrt(std::max(0.0, s.C(row, row))); };
  if (layout.extrinsic >= 0 && s.C.rows() >= layout.extrinsic + kCalibExtrinsicDim) {
    e.extrinsic_valid = true;
    e.rotation_change = logSO3(s.extrinsic.R_imu_cam.transpose() * s.x.R_bc);
    e.p_bc = s.x.p_bc;
    for (int i = 0; i < 3; ++i) {
      e.rotation_sigma[i] = sigma(layout.extrinsic + i);
      e.p_bc_sigma[i] = sigma(layout.extrinsic + 3 + i);
    }
  }
  if (layout.time_offset >= 0 && s.C.rows() > layout.time_offset) {
    e.time_offset_valid = true;
    e.time_offset = s.x.t_d;
    e.time_offset_sigma = sigma(layout.time_offset);
  }
  return e;
}

}  // namespace hapi_eskf
