// LatencyHistogram: the distribution of a latency over a whole run (p50,
// p99, max) in constant memory, for the nodelets' /diagnostics.
// ROS-free; owns its lock (samples come from a worker thread, reads from
// the diagnostics timer).
//
// Bins are logarithmic: bin i holds [1 us * kRatio^i, 1 us * kRatio^(i+1)),
// 1 us .. ~100 s in 1852 bins, and a percentile is reported as its bin's
// geometric centre, so it is within 0.5 % of the true sample. Latencies
// below 1 us (or negative: a stamp ahead of the clock) count in bin 0 and
// separately as `negative()`.
#pragma once

#include <cstdint>
#include <mutex>
#include <vector>

namespace hapi_nodelet_kit {

class LatencyHistogram {
 public:
  static constexpr double kRatio = 1.01;
  static constexpr double kMinSeconds = 1e-6;

  LatencyHistogram();

  void add(double seconds);
  void clear();

  struct Summary {
    std::uint64_t count = 0, negative = 0;
    double p50 = 0, p99 = 0, max = 0;  // [s]; 0 without samples
  };
  Summary summary() const;

 private:
  double quantileLocked(double q) const;

  mutable std::mutex mu_;
  std::vector<std::uint64_t> bins_;
  std::uint64_t count_ = 0, negative_ = 0;
  double max_ = 0;
};

}  // namespace hapi_nodelet_kit
