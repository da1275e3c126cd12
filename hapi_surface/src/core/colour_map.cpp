#include "hapi_surface/colour_map.hpp"

#include <algorithm>
#include <cmath>

namespace hapi_surface {
namespace {

// Jet: blue -> cyan -> yellow -> red, each channel a clamped tent.
std::array<Rgb8, 256> makeJet() {
  std::array<Rgb8, 256> lut{};
  for (int i = 0; i < 256; ++i) {
    const double x = i / 255.0;
    auto ch = [&](double centre) {
      const double v = std::clamp(1.5 - std::abs(4.0 * x - centre), 0.0, 1.0);
      return static_cast<std::uint8_t>(std::lround(255.0 * v));
    };
    lut[i] = {ch(3.0), ch(2.0), ch(1.0)};
  }
  return lut;
}

}  // namespace

Rgb8 jetColour(float value, float lo, float hi) {
  static const std::array<Rgb8, 256> kLut = makeJet();
  if (!std::isfinite(value)) return {128, 128, 128};
  const float span = hi - lo;
  const float x = span > 0.f ? (value - lo) / span : 0.5f;
  const int i = static_cast<int>(std::lround(255.f * std::clamp(x, 0.f, 1.f)));
  return kLut[i];
}

bool valueRange(const std::vector<float>& values, float* lo, float* hi) {
  std::vector<float> v;
  v.reserve(values.size());
  for (float x : values)
    if (std::isfinite(x)) v.push_back(x);
  if (v.empty()) return false;
  auto quantile = [&](double q) {
    const std::size_t k = static_cast<std::size_t>(q * (v.size() - 1));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[k];
  };
  *lo = quantile(0.01);
  *hi = quantile(0.99);
  return true;
}

}  // namespace hapi_surface
