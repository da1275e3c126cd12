// Quantiles of a finished sample: the p50 / p99 / max of per-frame times that
// the benchmarks and offline tools print. ROS-free and header-only. Two
// conventions are in use, each written once here; figures recorded in docs/
// were taken with them, so each tool keeps its own:
//  * nearest rank (eskf_replay, pipeline_latency): the smallest value with at
//    least a fraction q of the sample at or below it;
//  * rounded position (eskf_bench, compare_backends): the value at the
//    position q (n - 1) of the sorted sample, rounded half up.
// Both give the median's upper neighbour for even n and the maximum at q = 1.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

namespace hapi_nodelet_kit {

// q in [0, 1]; `if_empty` for an empty sample.
inline double quantileNearestRank(std::vector<double> v, double q, double if_empty) {
  if (v.empty()) return if_empty;
  std::sort(v.begin(), v.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(q * v.size()));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

// q in [0, 1]; `if_empty` for an empty sample.
inline double quantileRoundedPosition(std::vector<double> v, double q, double if_empty) {
  if (v.empty()) return if_empty;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

// "p50 / p99 / max" of a sample by nearest rank, `decimals` places each (0 / 0 / 0 when empty): the per-frame
// time columns of pipeline_latency and surface_motion_latency.
inline std::string formatP50P99Max(const std::vector<double>& v, int decimals) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.*f / %.*f / %.*f", decimals, quantileNearestRank(v, 0.5, 0.0), decimals,
                quantileNearestRank(v, 0.99, 0.0), decimals, quantileNearestRank(v, 1.0, 0.0));
  return buf;
}

}  // namespace hapi_nodelet_kit
