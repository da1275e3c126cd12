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
//
// Surface-relative mode (docs/DESIGN.md "Scene motion"): after a frame in
// which the scanned surface moved while the device was still
// (IterationReport::scene_moving), the IMU measures the device, not the
// camera's motion relative to the surface, which is what the output stands
// for (the filter's pose there follows the map). Until the next frame the
// copy then extrapolates the last frame-to-frame camera motion (twist from
// the two latest filter poses) instead of integrating the IMU, so pose and
// twist stay relative to the surface, at the IMU rate but with the frames'
// bandwidth.
//
// Unmeasured velocity: until a frame has measured the filter's velocity
// (PoseBlockState::velocity_measured: after a moving start or an outage,
// the velocity is a guess of rest), publishable() is false: the copy still
// steps, but a dead-reckoned pose would be off by the velocity error times
// the time since the frame, so the outputs wait for the next frame.
#pragma once

#include "hapi_eskf/backend/slam_backend.hpp"
#include "hapi_eskf/eskf/motion_model.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <memory>

namespace hapi_eskf {

class PosePropagator {
 public:
  explicit PosePropagator(const EskfSettings& settings) : settings_(settings) {}

  // Start from the back end's pose-block state (after a processed frame);
  // a back end without one (SlamBackend::poseBlockState) leaves the copy
  // invalid. scene_moving: that frame's IterationReport::scene_moving
  // (surface-relative mode above).
  void rebase(const SlamBackend& filter, bool scene_moving = false);
  // Forget the state (filter reset): step() fails until the next rebase().
  void invalidate() {
    model_.reset();
    have_previous_ = false;
  }
  bool surfaceRelative() const { return relative_; }
  bool valid() const { return model_ != nullptr; }
  // Valid, and its velocity measured (see "Unmeasured velocity" above).
  bool publishable() const { return model_ != nullptr && velocity_measured_; }

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
  bool velocity_measured_ = false;
  // The previous frame's camera pose and covariance (surface-relative twist).
  bool have_previous_ = false;
  PoseState previous_;
  Mat12 previous_C_ = Mat12::Zero();
  double previous_time_ = 0.0;
  // Surface-relative mode: the frame's camera and its covariance with the
  // frame-to-frame twist, extrapolated from frame_time_.
  bool relative_ = false;
  PoseState frame_camera_;
  Mat12 frame_C_ = Mat12::Zero();
  double frame_time_ = 0.0;
};

}  // namespace hapi_eskf
