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

ImuModel::ImuModel(const ImuSpec& spec, double rate_hz, uint32_t seed, bool noise, bool saturate)
    : spec_(spec), rate_(rate_hz), noise_(noise), saturate_(saturate), rng_(mixSeed(seed, 0xFFFFFF04u, 13)) {
  if (noise_)
    for (int i = 0; i < 3; ++i) {
      bg_[i] = spec_.gyro_turn_on_sigma * rng_.normal();
      ba_[i] = spec_.accel_turn_on_sigma * rng_.normal();
    }
}

Eigen::Vector3d ImuModel::specificForce(const MotionSample& imu) {
  // f = R^T (a - g) with g = (0, 0, -9.81): at rest the accelerometer reads +9.81 along the inertial up.
  return imu.q.conjugate() * (imu.a + Eigen::Vector3d(0, 0, kGravity));
}

ImuReading ImuModel::measure(const MotionSample& imu) {
  ImuReading r;
  r.gyro = imu.omega;
  r.accel = specificForce(imu);
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
  if (saturate_)
    for (int i = 0; i < 3; ++i) {
      r.gyro[i] = std::clamp(r.gyro[i], -spec_.gyro_range, spec_.gyro_range);
      r.accel[i] = std::clamp(r.accel[i], -spec_.accel_range, spec_.accel_range);
    }
  return r;
}

}  // namespace hapi_sim
