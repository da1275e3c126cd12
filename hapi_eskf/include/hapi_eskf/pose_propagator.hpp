// IMU-rate pose output between filter frames (prediction at the IMU rate),
// used by the nodelet and by eskf_replay.
//
// Why a copy: the filter predicts with the IMU only when the next frame is
// processed, because it cannot go back in time and a frame always arrives
// AFTER the IMU samples of its own time span (front-end latency). Predicting
// the filter itself ahead with every sample would make the next, older frame
// unusable. So the worker keeps this copy of the nominal pose-block state
// and its covariance, re-based on the filter after every frame and stepped
// with every newer IMU sample, and publishes odometry/TF from it at the IMU
// rate.
//
// Exactness: the step is the filter's own code path (motion_model.hpp
// predictStep with the filter's MotionModel), and the pose block of the
// filter covariance evolves as C_pp <- F C_pp F^T + Q (predictPoseCovariance,
// as in the CPU backend), independently of the landmark blocks. After the
// same samples this copy therefore equals the filter's pose and pose
// covariance (checked in test/test_pose_propagator.cpp).
#pragma once

#include "hapi_eskf/slam_backend.hpp"
#include "hapi_eskf/motion_model.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>

namespace hapi_eskf {

class PosePropagator {
 public:
  explicit PosePropagator(const EskfSettings& settings) : settings_(settings) {}

  // Start from the back end's pose-block state (after a processed frame);
  // a back end without one (SlamBackend::poseBlockState) leaves the copy
  // invalid.
  void rebase(const SlamBackend& filter);
  // Forget the state (filter reset): step() fails until the next rebase().
  void invalidate() { model_.reset(); }
  bool valid() const { return model_ != nullptr; }

  // One IMU step to the sample's stamp (predictStep's checks:
  // kNotInitialised before rebase(), kNonFinite, kInvalidArgument for a
  // stamp before time()); the state is unchanged on error.
  Status step(const ImuSample& sample);

  // The camera: pose, camera-frame velocities, and their covariance
  // [dp, dtheta, dv, dw] (12 x 12, MotionModel::cameraStateJacobian).
  PoseState pose() const;
  Mat12 cameraCovariance() const;
  const PoseMat& covariance() const { return C_; }  // the pose block's (P x P)
  double time() const { return time_; }

 private:
  EskfSettings settings_;
  std::unique_ptr<MotionModel> model_;
  NominalState x_;
  PoseMat C_;
  double time_ = 0.0;
};

}  // namespace hapi_eskf
