// The fusion filter's state (docs/DESIGN.md "Surface motion", fusion): e, the
// skin's velocity at the pixel's point that the device's odometry does not
// explain, in the imaging camera's frame, a first-order Gauss-Markov process
//   e(t + dt) = exp(-dt / tau) R_{t+dt,t} e(t) + w,  Var w = q^2 tau / 2 (1 - exp(-2 dt / tau)) I
// (R the camera's rotation over dt, q the acceleration density), updated by
// linearised image-flow measurements with a chi-square gate. A measurement
// of an earlier instant updates the step there and the later steps are
// predicted again (no lag for the flow's latency). Every step is kept
// (bounded by time) for the fixed-interval smoother (rts_smoother.hpp).
#pragma once

#include "hapi_eskf/surface_motion/surface_motion_settings.hpp"
#include "hapi_eskf/types.hpp"

#include <deque>

namespace hapi_eskf {
namespace surface_motion {

using Mat23 = Eigen::Matrix<double, 2, 3>;

// One step of the filter: the prediction to t from the previous step (F) and
// the state after the updates at t.
struct FilterStep {
  double t = 0;
  Mat3 F = Mat3::Identity(), Q = Mat3::Zero();
  bool updated = false;
  Vec3 e_pred = Vec3::Zero(), e = Vec3::Zero();
  Mat3 P_pred = Mat3::Zero(), P = Mat3::Zero();
};

struct UpdateResult {
  bool fused = false;
  bool gated = false;      // NIS beyond the gate (not fused)
  bool restarted = false;  // max_consecutive_gated reached: e restarted from its prior, then fused
  double nis = 0;
};

class RelativeVelocityFilter {
 public:
  explicit RelativeVelocityFilter(const SurfaceMotionSettings& s);

  bool started() const { return !steps_.empty(); }
  double time() const { return steps_.back().t; }
  const Vec3& e() const { return steps_.back().e; }
  const Mat3& covariance() const { return steps_.back().P; }
  const std::deque<FilterStep>& steps() const { return steps_; }

  // e = 0 with its prior at t (history cleared).
  void start(double t);
  // To t > time(); R_new_old rotates the old camera frame's vectors into the new one.
  void predict(double t, const Mat3& R_new_old);
  // The process noise a prediction over dt adds (also the lag term of a late measurement).
  Mat3 processNoise(double dt) const;
  // The step a measurement of instant t updates: the last at or before t,
  // but not before an updated step (the measurements come in order).
  std::size_t stepFor(double t) const;
  // Measurement z = h(e_k) + noise linearised at step k's e: innovation nu,
  // H = dh/de, R its noise. Gated when nu^T S^-1 nu > flow_gate. Steps after
  // k are predicted again from the updated step.
  UpdateResult update(std::size_t k, const Eigen::Vector2d& nu, const Mat23& H, const Eigen::Matrix2d& R);

 private:
  void trim();
  void repropagateFrom(std::size_t k);

  SurfaceMotionSettings s_;
  std::deque<FilterStep> steps_;
  int consecutive_gated_ = 0;
};

}  // namespace surface_motion
}  // namespace hapi_eskf
