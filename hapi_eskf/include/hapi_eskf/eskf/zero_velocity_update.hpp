// The zero-velocity pseudo-measurement of a still frame (docs/DESIGN.md
// "Zero-velocity update"): v = 0 with noise still_velocity_sigma, gated at
// gate_chi2 on its NIS against the filter's own velocity.
//
// Without it a standing device's velocity is only what the frames' pose
// updates imply, and the IMU-rate output extrapolates its error between
// frames (a vibrating platform: a few mm/s, over a frame interval plus the
// pipeline's latency). A measurement block touches only the first 6 pose
// columns and a landmark slot (covariance_backend.hpp, MeasurementBlock), so
// the update is made exactly with the backend's own calls, as the
// calibration's and the frame error's transitions are:
//   a swap transition T (its own inverse, Q = 0) exchanges the rows of dp
//   and dv; the update measures the first 3 columns (now dv) with a zero
//   Jacobian on landmark slot 0 (any landmark: its columns take no part);
//   T swaps back, and the correction's dp and dv segments are exchanged.
// O(K) per transition and one 3-row update: no backend change.
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

namespace hapi_eskf {

class ZeroVelocityUpdate {
 public:
  // filter_pose_dim: the backend's pose block (the model's plus spare rows).
  ZeroVelocityUpdate(double velocity_sigma, double gate_chi2, int filter_pose_dim);

  // Tests v_hat = 0 against the backend's velocity covariance and, when it
  // passes, updates with it: *dx (stateDim) receives the correction in the
  // state's layout. kOk with status->fused false when gated out or without
  // a landmark to carry the block; a backend fault is returned with C as
  // the transitions left it restored.
  Status apply(CovarianceBackend* backend, const Vec3& v_hat, ZeroVelocityStatus* status,
               Eigen::VectorXd* dx) const;

 private:
  double variance_, gate_chi2_;
  PoseMat swap_;
};

}  // namespace hapi_eskf
