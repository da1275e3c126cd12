// NumberRange: the one range type and "out of range" wording of every HAPI
// parameter table (number_range.hpp).
#include "hapi_nodelet_kit/number_range.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using hapi_nodelet_kit::NumberRange;
using hapi_nodelet_kit::outOfRange;

TEST(NumberRange, TextAndEdges) {
  EXPECT_EQ(NumberRange::closed(1, 12).text(), "in [1, 12]");
  EXPECT_EQ(NumberRange::open(0, 1).text(), "in (0, 1)");
  EXPECT_EQ(NumberRange::atLeast(0).text(), ">= 0");
  EXPECT_EQ(NumberRange::above(0).text(), "> 0");
  EXPECT_EQ(NumberRange().text(), "finite");
  EXPECT_TRUE(NumberRange::open(0, 1).contains(0.5));
  EXPECT_FALSE(NumberRange::open(0, 1).contains(0.0));
  EXPECT_FALSE(NumberRange::open(0, 1).contains(1.0));
  EXPECT_TRUE(NumberRange::openClosed(0, 1).contains(1.0));
  EXPECT_FALSE(NumberRange().contains(std::nan("")));
}

TEST(NumberRange, OutOfRangeNamesParameterRangeUnitAndValue) {
  EXPECT_EQ(outOfRange("pyramid_levels", NumberRange::closed(1, 12), "", 13), "pyramid_levels must be in [1, 12], got 13");
  EXPECT_EQ(outOfRange("~time_jump_reset", NumberRange::atLeast(0), "s", -1), "~time_jump_reset must be >= 0 s, got -1");
  EXPECT_EQ(outOfRange("x", NumberRange::any(), "m", std::nan("")), "x must be finite m, got nan");
  EXPECT_EQ(outOfRange("x", NumberRange::closedOpen(0, 0.1), "rad", 0.1), "x must be in [0, 0.1) rad, got 0.1");
  EXPECT_EQ(outOfRange("x", NumberRange::closed(1, 200000), "", 200000), "");
  EXPECT_EQ(outOfRange("x", NumberRange::above(0), "", std::numeric_limits<double>::infinity()), "x must be > 0, got inf");
  EXPECT_FALSE(NumberRange::any().bounded());
  EXPECT_TRUE(NumberRange::atLeast(0).bounded());
}
