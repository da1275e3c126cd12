// IMU-rate pose output between filter frames (prediction at the IMU rate).
//
// Why a copy: the filter predicts with the gyro only when the next frame is
// processed, because it cannot go back in time and a frame always arrives
// AFTER the IMU samples of its own time span (front-end latency). Predicting
// the filter itself ahead with every sample would make the next, older frame
// unusable. So the worker keeps this copy of the pose and its 12x12
// covariance, re-based on the filter after every frame and stepped with every
// newer gyro sample, and publishes odometry/TF from it at the IMU rate.
//
// Exactness: the step is the filter's own code path (gyro_prediction.hpp,
// which Eskf::predictWithGyro runs too: w replaced by the gyro for the step,
// then the constant-velocity model, docs/DESIGN.md "Gyro prediction"), and the pose block
// of the filter covariance evolves as C_pp <- F C_pp F^T + Q
// (predictPoseCovariance, as in the CPU backend), independently of the
// landmark blocks. After the same samples this copy therefore equals the
// filter's pose and pose covariance (checked in
// test/ros/pose_propagator_test.cpp).
#pragma once

#include "hapi_eskf/settings.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

namespace hapi_eskf {
namespace ros_glue {

class PosePropagator {
 public:
  explicit PosePropagator(const EskfSettings& settings) : settings_(settings) {}

  // Start from the filter's state at `stamp` (after a processed frame).
  void rebase(const PoseState& pose, const Mat12& covariance, double stamp);
  // Forget the state (filter reset): step() fails until the next rebase().
  void invalidate() { valid_ = false; }
  bool valid() const { return valid_; }

  // One gyro step to `stamp` (camera-frame rate [rad/s], noise density
  // [rad/s/sqrt(Hz)]). The checks of Eskf::predictWithGyro: kNotInitialised
  // before rebase(), kNonFinite, kInvalidArgument for a stamp before time()
  // or sigma <= 0; the state is unchanged on error.
  Status step(double stamp, const Vec3& gyro_camera, double sigma_gyro);

  const PoseState& pose() const { return pose_; }
  const Mat12& covariance() const { return C_; }
  double time() const { return time_; }

 private:
  EskfSettings settings_;
  bool valid_ = false;
  PoseState pose_;
  Mat12 C_ = Mat12::Zero();
  double time_ = 0.0;
};

}  // namespace ros_glue
}  // namespace hapi_eskf
