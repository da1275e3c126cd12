// The IMU's in-situ noise density (imu_noise_estimator.hpp).
#include "hapi_eskf/eskf/imu_noise_estimator.hpp"

#include <cmath>

namespace hapi_eskf {
namespace {

// Variance of the third difference of white noise, in units of the sample
// variance: 1 + 3^2 + 3^2 + 1 (the binomial coefficients squared).
constexpr double kThirdDifferenceGain = 20.0;

}  // namespace

void ImuNoiseEstimator::add(const ImuSample& sample) {
  if (!std::isfinite(sample.stamp) || !sample.gyro.allFinite() || !sample.accel.allFinite()) return;
  if (!samples_.empty() && sample.stamp == samples_.back().stamp) return;  // a repeated sample
  if (!samples_.empty() && sample.stamp < samples_.back().stamp) samples_.clear();
  samples_.push_back(sample);
  while (samples_.size() > 1 && samples_.back().stamp - samples_.front().stamp > window_) samples_.pop_front();
}

ImuNoiseDensity ImuNoiseEstimator::estimate() const {
  ImuNoiseDensity out;
  const std::size_t n = samples_.size();
  if (n < static_cast<std::size_t>(kMinDifferences) + 3) return out;
  const double mean_dt = (samples_.back().stamp - samples_.front().stamp) / static_cast<double>(n - 1);
  const auto regular = [&](std::size_t i) {
    const double dt = samples_[i].stamp - samples_[i - 1].stamp;
    return dt >= 0.5 * mean_dt && dt <= 1.5 * mean_dt;
  };
  Vec3 sum_g = Vec3::Zero(), sum_a = Vec3::Zero();
  double sum_dt = 0.0;
  int used = 0;
  for (std::size_t i = 3; i < n; ++i) {
    if (!regular(i) || !regular(i - 1) || !regular(i - 2)) continue;
    const ImuSample &a = samples_[i], &b = samples_[i - 1], &c = samples_[i - 2], &d = samples_[i - 3];
    sum_g += (a.gyro - 3.0 * b.gyro + 3.0 * c.gyro - d.gyro).cwiseAbs2();
    sum_a += (a.accel - 3.0 * b.accel + 3.0 * c.accel - d.accel).cwiseAbs2();
    sum_dt += a.stamp - d.stamp;
    ++used;
  }
  if (used < kMinDifferences) return out;
  // density^2 = sigma^2 dt with sigma^2 = E[d^2] / 20 and dt the mean interval.
  const double dt = sum_dt / (3.0 * used);
  const double scale = dt / (kThirdDifferenceGain * used);
  out.gyro = (sum_g * scale).cwiseSqrt();
  out.accel = (sum_a * scale).cwiseSqrt();
  return out;
}

}  // namespace hapi_eskf
