// The vision error shared by all measurements of one frame (docs/DESIGN.md
// "Frame-shared vision error"): the stereo front end's points of a frame
// are not independent (rectification, the keypoints' common sub-pixel
// bias, rolling exposure), they err together like a small extra camera
// motion n ~ N(0, Sigma_f), 6-dof [dp, dtheta] in the camera frame. A
// filter that takes them as independent learns the rotation from every
// frame anew and grows overconfident.
//
// Modelled exactly with the backend's own calls: the pose block carries 6
// spare rows after the motion model's P (the backend's pose block is
// P + 6). For one frame:
//   open():  spare <- [dp, dtheta] (a copy of the pose error), then
//            [dp, dtheta] += n: the first 6 columns, which every
//            measurement and new landmark touches, are now the pose the
//            frame sees;
//   (association, update and new landmarks run unchanged on them)
//   close(): [dp, dtheta] <- spare (the pose itself, with its correlations
//            as the update left them), spare <- an uncorrelated identity.
// Both are O(K) pose-block transitions (CovarianceBackend::predict), so
// the exact joint update with the nuisance n costs no change of either
// backend. Between frames the spare rows are uncorrelated with everything:
// the first P rows are the model's pose block as without them.
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

namespace hapi_eskf {

// Whether the ES-EKF models the frame-shared vision error: with a model that
// predicts from an IMU (gyro, inertial), whose tight frame-to-frame link
// would otherwise take the frames' shared errors as information, and any
// frame_* sigma > 0. constant_velocity's angular-velocity random walk absorbs
// them (consistent without, conservative with it: docs/ACCURACY.md
// "Consistency"). Not over the SEIF's storage: its information-form motion
// update inverts the transition, and the frame error's (a copy, a restore)
// are singular. Sigma_f itself: MeasurementSettings::frameErrorCameraCovariance.
bool frameErrorModelled(const EskfSettings& s);

// The backend's pose block for the settings: the motion model's
// (poseDim(s)), plus kFrameErrorDim spare rows when the
// settings model a frame error.
int filterPoseDim(const EskfSettings& s);

class FrameErrorBlock {
 public:
  FrameErrorBlock(int model_dim, const EskfSettings& s);

  bool enabled() const { return enabled_; }
  int filterDim() const { return enabled_ ? model_dim_ + kFrameErrorDim : model_dim_; }

  // A model-sized transition or noise (F, Q) or covariance, embedded in the
  // filter's pose block: identity (transition) or zero (noise) on the spare
  // rows; a covariance gets the identity there.
  PoseMat transition(const PoseMat& F) const;
  PoseMat noise(const PoseMat& Q) const;
  PoseMat covariance(const PoseMat& C) const;
  // The model's block of the filter's pose covariance.
  PoseMat modelBlock(const PoseMat& C) const { return C.topLeftCorner(model_dim_, model_dim_); }

  // Sigma_f in the state's [dp, dtheta]: J^-1 Sigma_cam J^-T, with J the
  // motion model's camera Jacobian (MotionModel::cameraJacobian).
  Mat6 stateCovariance(const Mat6& camera_jacobian) const;

  // The frame's two transitions (see above). open() is a no-op when
  // disabled; close() undoes an open() and is a no-op otherwise.
  Status open(CovarianceBackend* backend, const Mat6& camera_jacobian);
  Status close(CovarianceBackend* backend);
  bool isOpen() const { return open_; }
  // The backend was reset: its spare rows are the identity again.
  void discard() { open_ = false; }

  // From an update's correction (the filter's layout) while open: the
  // model's pose correction (length P; [dp, dtheta] from the spare rows)
  // and the correction of the pose the frame saw (first P rows). Disabled:
  // both are dx.head(P).
  Eigen::VectorXd poseCorrection(const Eigen::VectorXd& dx) const;
  Eigen::VectorXd framePoseCorrection(const Eigen::VectorXd& dx) const { return dx.head(model_dim_); }

 private:
  // M (model-sized) in the top-left corner, `spare_diagonal` times the
  // identity on the spare rows.
  PoseMat embed(const PoseMat& M, double spare_diagonal) const;

  int model_dim_;
  bool enabled_;
  Mat6 sigma_camera_;
  bool open_ = false;
};

}  // namespace hapi_eskf
