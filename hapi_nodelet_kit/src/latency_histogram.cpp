// LatencyHistogram (latency_histogram.hpp).
#include "hapi_nodelet_kit/latency_histogram.hpp"

#include <algorithm>
#include <cmath>

namespace hapi_nodelet_kit {

namespace {
// 1 us .. 100 s.
const int kBins = static_cast<int>(std::ceil(std::log(1e8) / std::log(LatencyHistogram::kRatio)));
}  // namespace

LatencyHistogram::LatencyHistogram() : bins_(kBins, 0) {}

void LatencyHistogram::add(double seconds) {
  if (!std::isfinite(seconds)) return;
  std::lock_guard<std::mutex> lk(mu_);
  ++count_;
  if (seconds < 0) ++negative_;
  max_ = std::max(max_, seconds);
  int i = 0;
  if (seconds > kMinSeconds)
    i = std::min(kBins - 1, static_cast<int>(std::log(seconds / kMinSeconds) / std::log(kRatio)));
  ++bins_[i];
}

void LatencyHistogram::clear() {
  std::lock_guard<std::mutex> lk(mu_);
  std::fill(bins_.begin(), bins_.end(), 0);
  count_ = negative_ = 0;
  max_ = 0;
}

double LatencyHistogram::quantileLocked(double q) const {
  // The smallest bin with at least q of the samples at or below it.
  const double target = q * static_cast<double>(count_);
  std::uint64_t seen = 0;
  for (int i = 0; i < kBins; ++i) {
    seen += bins_[i];
    if (static_cast<double>(seen) >= target && seen > 0) {
      if (i == 0) return 0.0;
      return std::min(max_, kMinSeconds * std::pow(kRatio, i + 0.5));
    }
  }
  return max_;
}

LatencyHistogram::Summary LatencyHistogram::summary() const {
  std::lock_guard<std::mutex> lk(mu_);
  Summary s;
  s.count = count_;
  s.negative = negative_;
  if (count_ == 0) return s;
  s.p50 = quantileLocked(0.5);
  s.p99 = quantileLocked(0.99);
  s.max = max_;
  return s;
}

}  // namespace hapi_nodelet_kit
