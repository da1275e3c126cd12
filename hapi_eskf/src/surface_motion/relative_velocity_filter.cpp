#include "hapi_eskf/surface_motion/relative_velocity_filter.hpp"

#include <Eigen/Cholesky>

#include <cmath>

namespace hapi_eskf {
namespace surface_motion {

RelativeVelocityFilter::RelativeVelocityFilter(const SurfaceMotionSettings& s) : s_(s) {}

void RelativeVelocityFilter::start(double t) {
  steps_.clear();
  FilterStep st;
  st.t = t;
  const double s0 = s_.initial_sigma_relative_velocity;
  st.P_pred = st.P = s0 * s0 * Mat3::Identity();
  steps_.push_back(st);
  consecutive_gated_ = 0;
}

Mat3 RelativeVelocityFilter::processNoise(double dt) const {
  const double tau = s_.relative_velocity_time_constant, q = s_.relative_acceleration_density;
  return (0.5 * q * q * tau * -std::expm1(-2 * dt / tau)) * Mat3::Identity();
}

void RelativeVelocityFilter::predict(double t, const Mat3& R_new_old) {
  const FilterStep& prev = steps_.back();
  const double dt = t - prev.t;
  FilterStep st;
  st.t = t;
  st.F = std::exp(-dt / s_.relative_velocity_time_constant) * R_new_old;
  st.Q = processNoise(dt);
  st.e_pred = st.e = st.F * prev.e;
  st.P_pred = st.F * prev.P * st.F.transpose() + st.Q;
  st.P_pred = 0.5 * (st.P_pred + st.P_pred.transpose()).eval();
  st.P = st.P_pred;
  steps_.push_back(st);
  trim();
}

std::size_t RelativeVelocityFilter::stepFor(double t) const {
  std::size_t k = steps_.size() - 1;
  while (k > 0 && steps_[k].t > t && !steps_[k].updated) --k;
  return k;
}

void RelativeVelocityFilter::repropagateFrom(std::size_t k) {
  for (std::size_t j = k + 1; j < steps_.size(); ++j) {
    FilterStep& st = steps_[j];
    st.e_pred = st.e = st.F * steps_[j - 1].e;
    st.P_pred = st.F * steps_[j - 1].P * st.F.transpose() + st.Q;
    st.P_pred = 0.5 * (st.P_pred + st.P_pred.transpose()).eval();
    st.P = st.P_pred;
  }
}

UpdateResult RelativeVelocityFilter::update(std::size_t k, const Eigen::Vector2d& nu, const Mat23& H,
                                            const Eigen::Matrix2d& R) {
  FilterStep& st = steps_[k];
  UpdateResult out;
  Eigen::Matrix2d S = H * st.P * H.transpose() + R;
  Eigen::LLT<Eigen::Matrix2d> llt(S);
  if (llt.info() != Eigen::Success) return out;
  out.nis = nu.dot(llt.solve(nu));
  if (!(out.nis <= s_.flow_gate)) {
    if (++consecutive_gated_ < s_.max_consecutive_gated) {
      out.gated = true;
      return out;
    }
    // The skin moved in a way the model did not expect (a jump, a restart of
    // the flow): e restarts from its prior, the measurement decides.
    const double s0 = s_.initial_sigma_relative_velocity;
    st.P = s0 * s0 * Mat3::Identity();
    S = H * st.P * H.transpose() + R;
    llt.compute(S);
    out.restarted = true;
  }
  consecutive_gated_ = 0;
  const Eigen::Matrix<double, 3, 2> K = st.P * H.transpose() * llt.solve(Eigen::Matrix2d::Identity());
  st.e += K * nu;
  // Joseph form: stays symmetric positive definite.
  const Mat3 IKH = Mat3::Identity() - K * H;
  st.P = IKH * st.P * IKH.transpose() + K * R * K.transpose();
  st.P = 0.5 * (st.P + st.P.transpose()).eval();
  st.updated = true;
  repropagateFrom(k);
  out.fused = true;
  return out;
}

void RelativeVelocityFilter::trim() {
  while (steps_.size() > 2 && steps_.back().t - steps_.front().t > s_.history_length) steps_.pop_front();
}

}  // namespace surface_motion
}  // namespace hapi_eskf
