// The IMU-rate copy of the filter state (pose_propagator.hpp).
#include "hapi_eskf/eskf/pose_propagator.hpp"

#include "hapi_eskf/backend/pose_kinematics.hpp"
#include "hapi_eskf/so3.hpp"

#include <cmath>

namespace hapi_eskf {

void PosePropagator::rebase(const SlamBackend& filter, bool scene_moving) {
  PoseBlockState s;
  if (!filter.poseBlockState(&s)) {
    model_.reset();
    have_previous_ = false;
    return;
  }
  model_ = makeMotionModel(settings_, s.extrinsic);
  x_ = s.x;
  C_ = s.C;
  time_ = s.time;
  const PoseState camera = model_->camera(x_);
  const Mat12 camera_C = hapi_eskf::cameraCovariance(*model_, x_, C_);
  relative_ = false;
  const double dt = time_ - previous_time_;
  // A filter that estimates the surface's motion reports the camera
  // relative to the surface itself; the IMU-rate copy steps it as usual.
  if (scene_moving && !model_->sceneMotion().any() && have_previous_ && dt > 0.0) {
    // Twist of the camera relative to the surface over the last frame
    // interval, in the camera frame (the filter's own v, w convention).
    // Its covariance treats the two poses as independent (an upper bound:
    // they are positively correlated through the map).
    const Mat3 R0 = previous_.q.toRotationMatrix(), R1 = camera.q.toRotationMatrix();
    frame_camera_ = camera;
    frame_camera_.v = R1.transpose() * (camera.p - previous_.p) / dt;
    frame_camera_.w = logSO3(R0.transpose() * R1) / dt;
    frame_C_ = camera_C;
    frame_C_.block<6, 6>(kIdxV, kIdxV).setZero();
    frame_C_.block<6, 6>(kIdxV, kIdxP).setZero();
    frame_C_.block<6, 6>(kIdxP, kIdxV).setZero();
    frame_C_.block<3, 3>(kIdxV, kIdxV) =
        R1.transpose() * (camera_C.block<3, 3>(kIdxP, kIdxP) + previous_C_.block<3, 3>(kIdxP, kIdxP)) * R1 /
        (dt * dt);
    frame_C_.block<3, 3>(kIdxW, kIdxW) =
        (camera_C.block<3, 3>(kIdxTheta, kIdxTheta) + previous_C_.block<3, 3>(kIdxTheta, kIdxTheta)) / (dt * dt);
    frame_time_ = time_;
    relative_ = true;
  }
  // Surface-relative mode takes its twist from two measured frames.
  velocity_measured_ = relative_ || s.velocity_measured;
  have_previous_ = true;
  previous_ = camera;
  previous_C_ = camera_C;
  previous_time_ = time_;
}

// The filter's step (motion_model.hpp predictStep), applied to the pose
// block's covariance only; in surface-relative mode only the clock moves
// (pose() extrapolates from the frame).
Status PosePropagator::step(const ImuSample& sample) {
  if (!model_) return Status::kNotInitialised;
  if (relative_) {
    if (!std::isfinite(sample.stamp) || !sample.gyro.allFinite() || !sample.accel.allFinite())
      return Status::kNonFinite;
    if (sample.stamp < time_) return Status::kInvalidArgument;
    time_ = sample.stamp;
    return Status::kOk;
  }
  // The filter's clock rule (Eskf::addImu): the estimated offset's clock;
  // a sample moved before the output's time is dropped.
  const ImuSample moved = model_->onEstimatedClock(sample, x_);
  if (sample.stamp >= time_ && moved.stamp < time_) return Status::kOk;
  return predictStep(*model_, &x_, &time_, moved.stamp, &moved, [this](const PoseMat& F, const PoseMat& Q) {
    C_ = predictPoseCovariance(C_, F, Q);
    return Status::kOk;
  });
}

PoseState PosePropagator::pose() const {
  if (!model_) return PoseState();
  if (!relative_) return model_->camera(x_);
  // Constant camera-frame twist from the frame: p += R v tau, R <- R Exp(w tau)
  // (first order in tau for the position, as the constant-velocity model).
  const double tau = time_ - frame_time_;
  PoseState c = frame_camera_;
  c.p += frame_camera_.q * (frame_camera_.v * tau);
  c.q = (frame_camera_.q * quatExp(frame_camera_.w * tau)).normalized();
  return c;
}

Mat12 PosePropagator::cameraCovariance() const {
  if (!model_) return Mat12::Zero();
  if (!relative_) return hapi_eskf::cameraCovariance(*model_, x_, C_);
  // The extrapolation adds the twist's uncertainty over tau (its correlation
  // with the frame pose neglected, as in the twist itself).
  const double tau = time_ - frame_time_;
  Mat12 C = frame_C_;
  const Mat3 R = frame_camera_.q.toRotationMatrix();
  C.block<3, 3>(kIdxP, kIdxP) += R * frame_C_.block<3, 3>(kIdxV, kIdxV) * R.transpose() * (tau * tau);
  C.block<3, 3>(kIdxTheta, kIdxTheta) += frame_C_.block<3, 3>(kIdxW, kIdxW) * (tau * tau);
  return C;
}

}  // namespace hapi_eskf
