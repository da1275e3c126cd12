// StampGuard: accept newer stamps, reject small steps back and repeats,
// reset on a jump back beyond ~time_jump_reset; the parameter's range.
#include "hapi_nodelet_kit/stamp_guard.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

using hapi_nodelet_kit::StampGuard;
using hapi_nodelet_kit::StampVerdict;
using hapi_nodelet_kit::TimeJumpResetParam;

namespace {
constexpr std::int64_t kSec = 1000000000;
}

TEST(StampGuard, ForwardAcceptedSmallStepBackRejectedBigStepBackResets) {
  StampGuard g(1.0);
  auto c = g.check(100 * kSec);
  EXPECT_EQ(c.verdict, StampVerdict::kAccept);
  EXPECT_FALSE(c.had_previous);
  EXPECT_EQ(g.check(100 * kSec + 1).verdict, StampVerdict::kAccept);  // 1 ns later
  // Repeated stamp: a step back of 0 s.
  c = g.check(100 * kSec + 1);
  EXPECT_EQ(c.verdict, StampVerdict::kReject);
  EXPECT_EQ(c.back_ns, 0);
  // Back by exactly the threshold: still out of order.
  c = g.check(99 * kSec + 1);
  EXPECT_EQ(c.verdict, StampVerdict::kReject);
  EXPECT_EQ(c.previous_ns, 100 * kSec + 1);
  EXPECT_DOUBLE_EQ(c.backSec(), 1.0);
  // A rejection does not move the guard: 1 ns beyond the threshold resets.
  c = g.check(99 * kSec);
  EXPECT_EQ(c.verdict, StampVerdict::kReset);
  EXPECT_TRUE(c.had_previous);
  EXPECT_EQ(c.back_ns, kSec + 1);
  // The new timeline is the reference from now on.
  EXPECT_EQ(g.check(99 * kSec + 5).verdict, StampVerdict::kAccept);
  EXPECT_EQ(g.check(99 * kSec + 4).verdict, StampVerdict::kReject);
  // A forward jump is never a reset.
  EXPECT_EQ(g.check(5000 * kSec).verdict, StampVerdict::kAccept);
}

TEST(StampGuard, ZeroThresholdResetsOnEveryStepBackButRejectsRepeats) {
  StampGuard g(0.0);
  g.check(10 * kSec);
  EXPECT_EQ(g.check(10 * kSec).verdict, StampVerdict::kReject);
  EXPECT_EQ(g.check(10 * kSec - 1).verdict, StampVerdict::kReset);
}

TEST(StampGuard, ClearForgetsTheLastStamp) {
  StampGuard g(1.0);
  g.check(10 * kSec);
  g.clear();
  const auto c = g.check(5 * kSec);
  EXPECT_EQ(c.verdict, StampVerdict::kAccept);
  EXPECT_FALSE(c.had_previous);
}

TEST(StampGuard, ZeroStampIsAnOrdinaryFirstStamp) {
  StampGuard g(1.0);
  EXPECT_EQ(g.check(0).verdict, StampVerdict::kAccept);
  EXPECT_EQ(g.check(0).verdict, StampVerdict::kReject);
}

TEST(TimeJumpResetParam, RangeIsFiniteAndNonNegative) {
  EXPECT_STREQ(TimeJumpResetParam::kName, "time_jump_reset");
  EXPECT_EQ(TimeJumpResetParam::check(TimeJumpResetParam::kDefault), "");
  EXPECT_EQ(TimeJumpResetParam::check(0.0), "");
  EXPECT_EQ(TimeJumpResetParam::check(1e12), "");  // saturates: never a jump
  for (double bad : {-0.1, std::nan(""), std::numeric_limits<double>::infinity()}) {
    const std::string why = TimeJumpResetParam::check(bad);
    EXPECT_NE(why.find("~time_jump_reset must be >= 0 s"), std::string::npos) << why;
    EXPECT_THROW(StampGuard{bad}, std::invalid_argument);
  }
  StampGuard never(1e12);
  never.check(1000 * kSec);
  EXPECT_EQ(never.check(0).verdict, StampVerdict::kReject);
}
