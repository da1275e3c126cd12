// The slot plan of a removal (removal_plan.hpp), pinned with hand-worked
// cases: every backend, the filter's host mirror and the benchmark follow it.
#include "hapi_eskf/backend/removal_plan.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <string>

namespace hapi_eskf {
namespace {

std::vector<std::pair<int, int>> pairs(const std::vector<SlotMove>& m) {
  std::vector<std::pair<int, int>> out;
  for (const SlotMove& x : m) out.emplace_back(x.from, x.to);
  return out;
}

TEST(RemovalPlan, HandWorkedCases) {
  using P = std::vector<std::pair<int, int>>;
  // 8 landmarks, remove {1, 4, 5, 6}: new end 4, hole 1, mover 7.
  EXPECT_EQ(pairs(tailFillMoves(8, {6, 1, 4, 5})), (P{{7, 1}}));
  EXPECT_EQ(oldSlotOfNew(8, {6, 1, 4, 5}), (std::vector<int>{0, 7, 2, 3}));
  // Removing only tail slots moves nothing.
  EXPECT_TRUE(tailFillMoves(10, {9, 8}).empty());
  EXPECT_EQ(oldSlotOfNew(10, {9, 8}), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  // A leading run: the last three fill the first three holes, in order.
  EXPECT_EQ(pairs(tailFillMoves(6, {0, 1, 2})), (P{{3, 0}, {4, 1}, {5, 2}}));
  // Mixed: new end 5; holes 0, 3; movers 5, 7 (6 is removed itself).
  EXPECT_EQ(pairs(tailFillMoves(8, {0, 3, 6})), (P{{5, 0}, {7, 3}}));
  EXPECT_EQ(oldSlotOfNew(8, {0, 3, 6}), (std::vector<int>{5, 1, 2, 7, 4}));
  // Everything.
  EXPECT_TRUE(oldSlotOfNew(3, {2, 0, 1}).empty());
  EXPECT_TRUE(tailFillMoves(5, {}).empty());
}

// Property check on random removals: the kept landmarks, each exactly once,
// the ones below the new end unmoved, and only tail landmarks moved.
TEST(RemovalPlan, RandomRemovalsKeepEveryLandmarkOnce) {
  std::mt19937 gen(5);
  for (int trial = 0; trial < 500; ++trial) {
    const int K = std::uniform_int_distribution<int>(1, 60)(gen);
    std::vector<int> all(K);
    std::iota(all.begin(), all.end(), 0);
    std::shuffle(all.begin(), all.end(), gen);
    const int r = std::uniform_int_distribution<int>(0, K)(gen);
    const std::vector<int> removed(all.begin(), all.begin() + r);
    const std::vector<int> old = oldSlotOfNew(K, removed);
    ASSERT_EQ(static_cast<int>(old.size()), K - r);
    std::vector<int> seen(old);
    std::sort(seen.begin(), seen.end());
    std::vector<int> kept(all.begin() + r, all.end());
    std::sort(kept.begin(), kept.end());
    EXPECT_EQ(seen, kept) << "trial " << trial;
    for (int k = 0; k < K - r; ++k)
      if (std::find(removed.begin(), removed.end(), k) == removed.end()) EXPECT_EQ(old[k], k);
    for (const SlotMove& m : tailFillMoves(K, removed)) EXPECT_GE(m.from, K - r);
    // applyRemoval moves a host array the same way.
    std::vector<std::string> names(K);
    for (int k = 0; k < K; ++k) names[k] = "lm" + std::to_string(k);
    applyRemoval(tailFillMoves(K, removed), K - r, &names);
    for (int k = 0; k < K - r; ++k) EXPECT_EQ(names[k], "lm" + std::to_string(old[k]));
  }
}

}  // namespace
}  // namespace hapi_eskf
