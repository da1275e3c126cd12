// Photometric effects: the camera's gain over time and the sensor noise.
#include <algorithm>
#include <cmath>

#include "hapi_sim/image_formation.hpp"

namespace hapi_sim {

ExposureModel::ExposureModel(uint32_t seed, bool enabled) : enabled_(enabled) {
  GaussianRng rng(mixSeed(seed, 0xFFFFFF03u, 11));
  drift_period_ = 11.0 + 6.0 * rng.uniform01();
  drift_phase_ = 2 * M_PI * rng.uniform01();
  // Steps up to one hour (the longest data set the tools accept).
  for (double t = 3.0 + 3.0 * rng.uniform01(); t < 3700.0; t += 3.0 + 3.0 * rng.uniform01()) {
    step_times_.push_back(t);
    step_levels_.push_back(0.8 + 0.4 * rng.uniform01());
  }
}

double ExposureModel::gain(double t) const {
  if (!enabled_) return 1.0;
  const size_t k = static_cast<size_t>(std::upper_bound(step_times_.begin(), step_times_.end(), t) - step_times_.begin());
  const double level = k == 0 ? 1.0 : step_levels_[k - 1];
  return level * (1.0 + 0.1 * std::sin(2 * M_PI * t / drift_period_ + drift_phase_));
}

cv::Mat SensorNoise::expose(const cv::Mat& radiance, double gain, uint32_t seed) const {
  cv::Mat out(radiance.rows, radiance.cols, CV_8UC1);
  GaussianRng rng(seed);
  for (int v = 0; v < radiance.rows; ++v) {
    const float* in = radiance.ptr<float>(v);
    uint8_t* o = out.ptr<uint8_t>(v);
    for (int u = 0; u < radiance.cols; ++u) {
      double g = std::max(0.0, gain * in[u]);
      if (enabled) g += std::sqrt(g / electrons_per_grey + read_noise * read_noise) * rng.normal();
      o[u] = static_cast<uint8_t>(std::clamp(std::lround(g), 0L, 255L));
    }
  }
  return out;
}

}  // namespace hapi_sim
