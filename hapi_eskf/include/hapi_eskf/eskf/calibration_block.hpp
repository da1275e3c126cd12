// The online calibration's frame transitions (docs/DESIGN.md "Online
// calibration"): with the camera-IMU extrinsic and time offset in the pose
// block (CalibrationLayout), the camera pose a frame sees depends on more
// than the first 6 columns, which are all a measurement block may touch
// (covariance_backend.hpp, MeasurementBlock::H_pose). So, for one frame:
//   open():  a linear, invertible transition T of the model's rows replaces
//            [dp, dtheta] by the camera's pose error
//              e_c = J_body [dp, dtheta] + J_ext [dtheta_bc, dp_bc] + J_t dt_d
//            (the top 6 rows of MotionModel::cameraStateJacobian); the
//            measurement and new-landmark Jacobians then take the identity
//            as the camera Jacobian (cameraJacobian());
//   close(): T^-1 restores the body's rows.
// Both are pose-block transitions with Q = 0 (CovarianceBackend::predict,
// which carries the landmark cross-covariances along): no backend change.
// open() runs before the frame error's (frame_error_block.hpp), whose
// spare rows then copy e_c, and close() after its close.
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/eskf/frame_error_block.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

namespace hapi_eskf {

class CalibrationBlock {
 public:
  explicit CalibrationBlock(const MotionModel& model) : enabled_(model.calibration().any()) {}

  bool enabled() const { return enabled_; }
  bool isOpen() const { return open_; }

  // The transition T (model-sized) at x and its inverse.
  static PoseMat cameraErrorTransition(const MotionModel& model, const NominalState& x);
  static PoseMat inverseTransition(const PoseMat& T);

  // open() is a no-op when disabled; close() undoes an open() and is a
  // no-op otherwise. `frame_error` embeds T in the filter's pose block.
  Status open(CovarianceBackend* backend, const FrameErrorBlock& frame_error, const MotionModel& model,
              const NominalState& x);
  Status close(CovarianceBackend* backend, const FrameErrorBlock& frame_error);
  // The backend was reset.
  void discard() { open_ = false; }

  // The camera Jacobian of the first 6 columns while open (the identity),
  // else the model's at x.
  Mat6 cameraJacobian(const MotionModel& model, const NominalState& x) const {
    return open_ ? Mat6::Identity() : model.cameraJacobian(x);
  }
  // A model-sized correction in the open frame's rows, in the state's
  // (T^-1 dx); dx itself when not open.
  Eigen::VectorXd stateCorrection(const Eigen::VectorXd& dx) const;

 private:
  bool enabled_;
  bool open_ = false;
  PoseMat T_inv_;
};

// The calibration as estimated, for /diagnostics and the tools: the
// rotation and translation relative to the configured prior (the
// extrinsic of PoseBlockState) and the time offset, with 1-sigma values
// from the pose block's covariance. `valid`: the state estimates them.
struct CalibrationEstimate {
  bool extrinsic_valid = false, time_offset_valid = false;
  Vec3 rotation_change = Vec3::Zero();  // Log(R_bc,prior^T R_bc) [rad]
  Vec3 rotation_sigma = Vec3::Zero();   // [rad], per axis of dtheta_bc
  Vec3 p_bc = Vec3::Zero(), p_bc_sigma = Vec3::Zero();  // [m]
  double time_offset = 0.0, time_offset_sigma = 0.0;    // [s]
};
CalibrationEstimate calibrationEstimate(const CalibrationLayout& layout, const PoseBlockState& s);

}  // namespace hapi_eskf
