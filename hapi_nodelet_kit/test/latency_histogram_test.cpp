// LatencyHistogram (latency_histogram.hpp) against exact percentiles.
#include "hapi_nodelet_kit/latency_histogram.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

using hapi_nodelet_kit::LatencyHistogram;

TEST(LatencyHistogram, PercentilesWithinHalfAPercentOfTheSamples) {
  LatencyHistogram h;
  std::mt19937 rng(7);
  std::lognormal_distribution<double> latency(std::log(0.03), 0.4);  // ~30 ms with a tail
  std::vector<double> all;
  for (int i = 0; i < 20000; ++i) {
    all.push_back(latency(rng));
    h.add(all.back());
  }
  std::sort(all.begin(), all.end());
  const LatencyHistogram::Summary s = h.summary();
  EXPECT_EQ(s.count, 20000u);
  EXPECT_EQ(s.negative, 0u);
  EXPECT_NEAR(s.p50, all[all.size() / 2 - 1], 0.006 * all[all.size() / 2 - 1]);
  const double p99 = all[static_cast<std::size_t>(0.99 * all.size()) - 1];
  EXPECT_NEAR(s.p99, p99, 0.006 * p99);
  EXPECT_DOUBLE_EQ(s.max, all.back());
}

TEST(LatencyHistogram, EmptyNegativeAndClear) {
  LatencyHistogram h;
  EXPECT_EQ(h.summary().count, 0u);
  EXPECT_EQ(h.summary().p99, 0.0);
  h.add(-0.002);  // stamp ahead of the clock
  h.add(0.010);
  h.add(std::numeric_limits<double>::quiet_NaN());  // ignored
  LatencyHistogram::Summary s = h.summary();
  EXPECT_EQ(s.count, 2u);
  EXPECT_EQ(s.negative, 1u);
  EXPECT_EQ(s.p50, 0.0);
  EXPECT_NEAR(s.p99, 0.010, 0.0001);
  h.clear();
  EXPECT_EQ(h.summary().count, 0u);
}
