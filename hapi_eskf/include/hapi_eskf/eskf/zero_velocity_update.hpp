// The zero-velocity pseudo-measurement of a still frame (docs/DESIGN.md
// "Zero-velocity update"): the velocity's mean over the interval since the
// previous frame is 0, with noise still_velocity_sigma, gated at gate_chi2
// on its NIS against the filter's own.
//
// Without it a standing device's velocity is only what the frames' pose
// updates imply, and the IMU-rate output extrapolates its error between
// frames (a vibrating platform: a few mm/s, over a frame interval plus the
// pipeline's latency). A measurement block touches only the first 6 pose
// columns and a landmark slot (covariance_backend.hpp, MeasurementBlock), so
// the update is made exactly with the backend's own calls, as the
// calibration's and the frame error's transitions are:
//   a transition T = S E (Q = 0): E replaces dv by the measured
//   combination J dx (J's dv block is I, so E = I + N with N^2 = 0 and
//   E^-1 = I - N), S exchanges the rows of dp and dv; the update measures
//   the first 3 columns (now J dx) with a zero Jacobian on landmark slot 0
//   (any landmark: its columns take no part); T^-1 = (I - N) S restores
//   the layout, and the correction's pose segment is mapped back by it.
// O(K) per transition and one 3-row update: no backend change.
#pragma once

#include "hapi_eskf/covariance/covariance_backend.hpp"
#include "hapi_eskf/status.hpp"
#include "hapi_eskf/types.hpp"

#include <Eigen/Core>

namespace hapi_eskf {

// What a still frame measures: the camera kept its place over the interval
// since the previous frame, so the velocity's MEAN over that interval is
// zero, not the velocity at the frame's instant. A platform that vibrates
// (EuRoC's MAV: 17 Hz, 0.5 m/s^2) moves at +-5-15 mm/s about a fixed place;
// a zero measured at an instant off by that much would leave the IMU-rate
// output running at it until the next frame (docs/DESIGN.md "Zero-velocity
// update"). The predicted nominal velocity v(t) = v(t_prev) + u(t), with u
// the IMU's integrated acceleration, has the interval mean v_bar; the
// measurement is "mean = 0", v_bar = 0, whose Jacobian meanVelocityJacobian
// gives.
class IntervalVelocity {
 public:
  // One prediction step from (t0, v0) to (t1, v1): trapezoid rule.
  void add(double t0, const Vec3& v0, double t1, const Vec3& v1) {
    if (!(t1 > t0)) return;
    integral_ += 0.5 * (v0 + v1) * (t1 - t0);
    duration_ += t1 - t0;
  }
  void restart() {
    integral_.setZero();
    duration_ = 0.0;
  }
  double duration() const { return duration_; }
  // The mean since restart(); v_now when nothing was predicted (a frame at
  // the previous one's stamp).
  Vec3 meanVelocity(const Vec3& v_now) const { return duration_ > 0.0 ? Vec3(integral_ / duration_) : v_now; }

 private:
  Vec3 integral_ = Vec3::Zero();
  double duration_ = 0.0;
};

// The Jacobian of the interval's mean velocity in the pose block's error
// state (3 x pose_dim). With the inertial model v_bar = v - (u - u_bar),
// where u - u_bar = int (s - t0) / dt a_w(s) ds over the interval of length
// dt and a_w = R (f - b_a) + g; with the errors' effect on a_w
// (-R [a]x dtheta - R db_a + dg, "Inertial prediction") held over the
// interval:
//   d v_bar = dv + dt / 2 (R [a]x dtheta + R db_a - dg),
// so a velocity that ramped over the interval (a gravity or bias error)
// moves gravity and bias as an instantaneous zero would, while vibration
// about a fixed place leaves no offset. Other models integrate no
// acceleration: d v_bar = dv. R_wb: the IMU body's orientation, a: its
// bias-corrected specific force.
Eigen::Matrix<double, 3, Eigen::Dynamic> meanVelocityJacobian(bool inertial, const Mat3& R_wb, const Vec3& a,
                                                              double dt, int pose_dim);

class ZeroVelocityUpdate {
 public:
  // filter_pose_dim: the backend's pose block (the model's plus spare rows).
  ZeroVelocityUpdate(double velocity_sigma, double gate_chi2, int filter_pose_dim);

  // Tests v_hat = 0 (v_hat: IntervalVelocity's mean) against the backend's
  // velocity covariance and, when it
  // passes, updates with it: *dx (stateDim) receives the correction in the
  // state's layout. kOk with status->fused false when gated out or without
  // a landmark to carry the block; a backend fault is returned with C as
  // the transitions left it restored.
  // J: the measured combination of the pose block's errors
  // (meanVelocityJacobian); its dv block must be the identity.
  Status apply(CovarianceBackend* backend, const Vec3& v_hat, const Eigen::Matrix<double, 3, Eigen::Dynamic>& J,
               ZeroVelocityStatus* status, Eigen::VectorXd* dx) const;

 private:
  double variance_, gate_chi2_;
  PoseMat swap_;
};

}  // namespace hapi_eskf
