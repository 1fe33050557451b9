// The 1/n form of a drift ratio (apps/drift_fraction.h). Expected values
// are the reciprocals worked by hand: 1/120 rad is the ratio building codes
// often allow for a storey, 1/30 rad the damage limit of the frames.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "drift_fraction.h"

using fq_app::drift_one_in_n;

TEST(DriftFraction, ARatioReadsAsOneOverItsRoundedReciprocal) {
  EXPECT_EQ(drift_one_in_n(1.0 / 120.0), "1/120");
  EXPECT_EQ(drift_one_in_n(0.0333), "1/30");    // 30.03
  EXPECT_EQ(drift_one_in_n(0.0038), "1/263");   // 263.16
  EXPECT_EQ(drift_one_in_n(0.5), "1/2");
  EXPECT_EQ(drift_one_in_n(1e-9), "1/1000000000");
  EXPECT_EQ(drift_one_in_n(1.0 / 262.5), "1/263");  // a half rounds away from zero
}

// Below a nanoradian there is no 1/n: a still frame's round-off drift of
// 2.8e-22 rad printed "1/-9223372036854775808" (the reciprocal overflowed
// the rounding's integer).
TEST(DriftFraction, NoFormForATinyZeroOrMeaninglessRatio) {
  EXPECT_EQ(drift_one_in_n(2.81524e-22), "");
  EXPECT_EQ(drift_one_in_n(0.99e-9), "");
  EXPECT_EQ(drift_one_in_n(0.0), "");
  EXPECT_EQ(drift_one_in_n(-0.01), "");
  EXPECT_EQ(drift_one_in_n(std::numeric_limits<double>::quiet_NaN()), "");
  EXPECT_EQ(drift_one_in_n(std::numeric_limits<double>::infinity()), "");
}

// Beside the verdict limits, 1/n keeps the ratio's side of each: the input
// probe's storey at 0.032884 rad, standing below the 1/30 damage limit,
// read "1/30"; 1/0.032884 = 30.41, so one decimal tells it apart. A ratio
// just past the limit (0.03334, n = 29.994) reads as on it with none or one
// decimal ("1/30", "1/30.0") and past it with two ("1/29.99"). A ratio on
// the limit itself is shown as the limit.
TEST(DriftFraction, OneOverNStaysOnTheRatiosSideOfEachVerdictLimit) {
  const std::vector<double> limits{1.0 / 30.0, 0.1};
  EXPECT_EQ(drift_one_in_n(0.032884, limits), "1/30.4");
  EXPECT_EQ(drift_one_in_n(0.032884), "1/30");
  EXPECT_EQ(drift_one_in_n(0.03334, limits), "1/29.99");
  EXPECT_EQ(drift_one_in_n(1.0 / 30.0, limits), "1/30");
  EXPECT_EQ(drift_one_in_n(0.0999999, limits), "1/10.00001");
  EXPECT_EQ(drift_one_in_n(0.1, limits), "1/10");
  // Far from the limits nothing changes.
  EXPECT_EQ(drift_one_in_n(1.0 / 120.0, limits), "1/120");
  EXPECT_EQ(drift_one_in_n(0.0038, limits), "1/263");
}
