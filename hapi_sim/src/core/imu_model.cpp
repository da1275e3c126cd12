// ImuModel: the ADIS16448 noise model and the ideal inertial readings.
#include <algorithm>
#include <cmath>

#include "hapi_sim/imu_model.hpp"

namespace hapi_sim {

ImuSpec ImuSpec::adis16448() {
  ImuSpec s;
  s.part = "ADIS16448";
  // White noise and random walks: the values EuRoC publishes for this part
  // in every mav0/imu0/sensor.yaml. They match the datasheet's angular random
  // walk 0.66 deg/sqrt(h) = 0.66 * (pi/180) / 60 = 1.92e-4 rad/s/sqrt(Hz) and
  // velocity random walk 0.11 m/s/sqrt(h) = 0.11 / 60 = 1.83e-3 m/s^2/sqrt(Hz);
  // the random walks are EuRoC's (inflated over the datasheet's in-run bias
  // stability of 14.5 deg/h and 0.25 mg to cover temperature drift).
  s.gyro_noise_density = 1.6968e-04;
  s.gyro_random_walk = 1.9393e-05;
  s.accel_noise_density = 2.0000e-3;
  s.accel_random_walk = 3.0000e-3;
  // Turn-on bias after factory calibration: 0.2 deg/s and 2 mg per axis
  // (chosen; the datasheet bounds the initial bias error more loosely).
  s.gyro_turn_on_sigma = 0.2 * M_PI / 180.0;
  s.accel_turn_on_sigma = 2e-3 * kGravity;
  // Ranges: +-1000 deg/s and +-18 g.
  s.gyro_range = 1000.0 * M_PI / 180.0;
  s.accel_range = 18.0 * kGravity;
  return s;
}

namespace {

// Uniform in [-bound, bound].
double symmetric(GaussianRng* rng, double bound) { return bound * (2.0 * rng->uniform01() - 1.0); }

// I + per-axis scale errors on the diagonal + cross-axis terms (small-angle
// misalignment of non-orthogonal sensing axes) off it.
Eigen::Matrix3d sensingMatrix(GaussianRng* rng, double scale_bound, double misalignment_bound) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  for (int i = 0; i < 3; ++i) M(i, i) += symmetric(rng, scale_bound);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) M(i, j) = symmetric(rng, misalignment_bound);
  return M;
}

}  // namespace

ImuModel::ImuModel(const ImuSpec& spec, double rate_hz, uint32_t seed, bool noise, bool saturate,
                   const ImuImperfections& imperfections)
    : spec_(spec), rate_(rate_hz), noise_(noise), saturate_(saturate), rng_(mixSeed(seed, 0xFFFFFF04u, 13)),
      imp_(imperfections), imperfect_(noise && imperfections.any()), imp_rng_(mixSeed(seed, 0xFFFFFF05u, 17)) {
  if (noise_)
    for (int i = 0; i < 3; ++i) {
      bg_[i] = spec_.gyro_turn_on_sigma * rng_.normal();
      ba_[i] = spec_.accel_turn_on_sigma * rng_.normal();
    }
  if (imperfect_) drawImperfections();
}

void ImuModel::drawImperfections() {
  // A mounted part's turn-on bias replaces the factory-calibrated one.
  for (int i = 0; i < 3; ++i) {
    if (imp_.gyro_turn_on_bound > 0) bg_[i] = symmetric(&imp_rng_, imp_.gyro_turn_on_bound);
    if (imp_.accel_turn_on_bound > 0) ba_[i] = symmetric(&imp_rng_, imp_.accel_turn_on_bound);
  }
  Mg_ = sensingMatrix(&imp_rng_, imp_.gyro_scale_bound, imp_.gyro_misalignment_bound);
  Ma_ = sensingMatrix(&imp_rng_, imp_.accel_scale_bound, imp_.accel_misalignment_bound);
  for (size_t k = 0; k < imp_.tones.size(); ++k) {
    Eigen::Matrix<double, 6, 1> ph;
    for (int i = 0; i < 6; ++i) ph[i] = 2.0 * M_PI * imp_rng_.uniform01();
    phases_.push_back(ph);
  }
}

void ImuModel::addVibration(ImuReading* r) {
  const double t = static_cast<double>(n_) / rate_;
  for (size_t k = 0; k < imp_.tones.size(); ++k) {
    const VibrationTone& v = imp_.tones[k];
    const double w = 2.0 * M_PI * v.frequency_hz * t;
    for (int i = 0; i < 3; ++i) {
      r->gyro[i] += v.gyro_amplitude[i] * std::sin(w + phases_[k][i]);
      r->accel[i] += v.accel_amplitude[i] * std::sin(w + phases_[k][3 + i]);
    }
  }
  const double s = std::sqrt(rate_);
  for (int i = 0; i < 3; ++i) r->gyro[i] += imp_.gyro_broadband_density[i] * s * imp_rng_.normal();
  for (int i = 0; i < 3; ++i) r->accel[i] += imp_.accel_broadband_density[i] * s * imp_rng_.normal();
}

Eigen::Vector3d ImuModel::specificForce(const MotionSample& imu) {
  // f = R^T (a - g) with g = (0, 0, -9.81): at rest the accelerometer reads +9.81 along the inertial up.
  return imu.q.conjugate() * (imu.a + Eigen::Vector3d(0, 0, kGravity));
}

ImuReading ImuModel::measure(const MotionSample& imu) {
  ImuReading r;
  r.gyro = imu.omega;
  r.accel = specificForce(imu);
  if (imperfect_) {
    r.gyro = Mg_ * r.gyro;
    r.accel = Ma_ * r.accel;
  }
  r.gyro_bias = bg_;
  r.accel_bias = ba_;
  if (noise_) {
    const double sg = gyroSigma(), sa = accelSigma();
    for (int i = 0; i < 3; ++i) r.gyro[i] += bg_[i] + sg * rng_.normal();
    for (int i = 0; i < 3; ++i) r.accel[i] += ba_[i] + sa * rng_.normal();
    const double sdt = 1.0 / std::sqrt(rate_);
    for (int i = 0; i < 3; ++i) bg_[i] += spec_.gyro_random_walk * sdt * rng_.normal();
    for (int i = 0; i < 3; ++i) ba_[i] += spec_.accel_random_walk * sdt * rng_.normal();
  }
  if (imperfect_) addVibration(&r);
  ++n_;
  if (saturate_)
    for (int i = 0; i < 3; ++i) {
      r.gyro[i] = std::clamp(r.gyro[i], -spec_.gyro_range, spec_.gyro_range);
      r.accel[i] = std::clamp(r.accel[i], -spec_.accel_range, spec_.accel_range);
    }
  return r;
}

}  // namespace hapi_sim
