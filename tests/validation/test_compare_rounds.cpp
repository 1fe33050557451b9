// The summary of a two-build sitting (validation/compare_rounds_core.h).
// Expected values are worked out by hand from the small logs below, whose
// numbers are chosen so that each statistic has one right answer: medians
// of odd and even counts, ratios taken within a round (not the ratio of the
// medians), rounds missing for one build, suffixed counter values, and
// state hashes that agree or not.
#include <gtest/gtest.h>

#include <sstream>

#include "compare_rounds_core.h"

namespace {

using fq::bench::compare_builds;
using fq::bench::parse_sitting;

fq::bench::Sitting sitting_of(const std::string& text) {
  std::istringstream in(text);
  return parse_sitting(in, "log.txt");
}

// Round 1 is slow for both builds (a busy host), round 2 fast, round 3
// in between. Within rounds new / old is 0.8, 0.8 and 0.75 (median 0.8),
// while the ratio of the two medians is 9 / 12 = 0.75: a summary that
// divided medians would not give the within-round figure.
const char* const kThreeRounds =
    "# header line, ignored\n"
    "## round 1 build old frames\n"
    "BM_Frame/B/no_output/threads:1/iterations:1/manual_time  5.6 s  5.6 s  1 joints_s=2 state_hash=85.5037T "
    "us_per_step=20\n"
    "## round 1 build new frames\n"
    "BM_Frame/B/no_output/threads:1/iterations:1/manual_time  4.5 s  4.5 s  1 joints_s=1.6 state_hash=85.5037T "
    "us_per_step=16\n"
    "## round 2 build old frames\n"
    "BM_Frame/B/no_output/threads:1/iterations:1/manual_time  3 s  3 s  1 joints_s=1 state_hash=85.5037T "
    "us_per_step=10\n"
    "## round 2 build new frames\n"
    "BM_Frame/B/no_output/threads:1/iterations:1/manual_time  2.4 s  2.4 s  1 joints_s=0.8 state_hash=85.5037T "
    "us_per_step=8\n"
    "## round 3 build old frames\n"
    "BM_Frame/B/no_output/threads:1/iterations:1/manual_time  3.6 s  3.6 s  1 joints_s=1.25 state_hash=85.5037T "
    "us_per_step=12\n"
    "## round 3 build new frames\n"
    "BM_Frame/B/no_output/threads:1/iterations:1/manual_time  2.9 s  2.9 s  1 joints_s=1 state_hash=85.5037T "
    "us_per_step=9\n";

TEST(CompareRounds, CounterValuesWithSuffixesArePowersOfAThousand) {
  EXPECT_DOUBLE_EQ(fq::bench::parse_counter_value("4.56k"), 4560.0);
  EXPECT_DOUBLE_EQ(fq::bench::parse_counter_value("1.5M"), 1.5e6);
  EXPECT_DOUBLE_EQ(fq::bench::parse_counter_value("2G"), 2e9);
  EXPECT_DOUBLE_EQ(fq::bench::parse_counter_value("85.5037T"), 85.5037e12);
  EXPECT_DOUBLE_EQ(fq::bench::parse_counter_value("12"), 12.0);
  EXPECT_THROW(fq::bench::parse_counter_value("k"), std::invalid_argument);
  EXPECT_THROW(fq::bench::parse_counter_value("12x"), std::invalid_argument);
  EXPECT_THROW(fq::bench::parse_counter_value(""), std::invalid_argument);
}

TEST(CompareRounds, MedianOfOddAndEvenCounts) {
  EXPECT_DOUBLE_EQ(fq::bench::median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(fq::bench::median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_DOUBLE_EQ(fq::bench::median({7.0}), 7.0);
  EXPECT_THROW(fq::bench::median({}), std::invalid_argument);
}

TEST(CompareRounds, RatiosAreTakenWithinEachRound) {
  const auto c = compare_builds(sitting_of(kThreeRounds), "old", "new", {"us_per_step", "joints_s", "absent"});
  ASSERT_EQ(c.counters.size(), 2u);  // "absent" is reported by no run
  const auto& us = c.counters[0];
  EXPECT_EQ(us.counter, "us_per_step");
  EXPECT_EQ(us.old_runs, 3);
  EXPECT_EQ(us.new_runs, 3);
  EXPECT_DOUBLE_EQ(us.old_median, 12.0);  // of 20, 10, 12
  EXPECT_DOUBLE_EQ(us.new_median, 9.0);   // of 16, 8, 9
  EXPECT_EQ(us.paired_rounds, 3);
  EXPECT_NEAR(us.ratio_median, 0.8, 1e-15);  // 16/20, 8/10, 9/12
  EXPECT_NEAR(us.ratio_min, 0.75, 1e-15);
  EXPECT_NEAR(us.ratio_max, 0.8, 1e-15);
  const auto& joints = c.counters[1];
  EXPECT_EQ(joints.counter, "joints_s");
  EXPECT_DOUBLE_EQ(joints.old_median, 1.25);  // of 2, 1, 1.25
  EXPECT_DOUBLE_EQ(joints.new_median, 1.0);   // of 1.6, 0.8, 1
  EXPECT_NEAR(joints.ratio_median, 0.8, 1e-15);  // 0.8, 0.8, 0.8
  ASSERT_EQ(c.hashes.size(), 1u);
  EXPECT_TRUE(c.hashes[0].same());
  EXPECT_TRUE(c.only_in_one.empty());
}

TEST(CompareRounds, RoundsWithOneBuildOnlyCountInItsMedianButGiveNoRatio) {
  // Round 2 of new is missing (a failed run) and round 4 has new alone:
  // old's median stays that of 20, 10, 12; new's is that of 16, 9, 100;
  // the ratios come from rounds 1 and 3 only (0.8 and 0.75).
  std::string text = kThreeRounds;
  const auto cut = text.find("## round 2 build new");
  const auto end = text.find("## round 3 build old");
  text.erase(cut, end - cut);
  text +=
      "## round 4 build new frames\n"
      "BM_Frame/B/no_output/threads:1/iterations:1/manual_time  1 s  1 s  1 state_hash=85.5037T us_per_step=100\n";
  const auto c = compare_builds(sitting_of(text), "old", "new", {"us_per_step"});
  ASSERT_EQ(c.counters.size(), 1u);
  EXPECT_EQ(c.counters[0].old_runs, 3);
  EXPECT_EQ(c.counters[0].new_runs, 3);              // rounds 1, 3, 4
  EXPECT_DOUBLE_EQ(c.counters[0].new_median, 16.0);  // of 16, 9, 100
  EXPECT_EQ(c.counters[0].paired_rounds, 2);
  EXPECT_NEAR(c.counters[0].ratio_median, 0.775, 1e-15);
}

TEST(CompareRounds, ADifferentStateHashInAnyRunIsReported) {
  std::string text = kThreeRounds;
  const auto at = text.rfind("state_hash=85.5037T");  // round 3 of new
  text.replace(at, std::string("state_hash=85.5037T").size(), "state_hash=85.5038T");
  const auto c = compare_builds(sitting_of(text), "old", "new", {"us_per_step"});
  ASSERT_EQ(c.hashes.size(), 1u);
  EXPECT_FALSE(c.hashes[0].same());
  EXPECT_EQ(c.hashes[0].new_hashes.size(), 2u);
  // Two runs of one build that disagree are as bad as builds that disagree.
  std::string within_old = kThreeRounds;
  within_old.replace(within_old.find("state_hash=85.5037T"), 19, "state_hash=11.1111T");
  EXPECT_FALSE(compare_builds(sitting_of(within_old), "old", "new", {"us_per_step"}).hashes[0].same());
  // Both builds changing the same way between rounds (round 3 of each with
  // another hash) give equal sets of hashes, and still runs that disagree.
  std::string both = kThreeRounds;
  for (int k = 0; k < 2; ++k) both.replace(both.rfind("state_hash=85.5037T"), 19, "state_hash=22.2222T");
  const auto twice = compare_builds(sitting_of(both), "old", "new", {"us_per_step"}).hashes[0];
  EXPECT_EQ(twice.old_hashes, twice.new_hashes);
  EXPECT_FALSE(twice.same());
}

// The hash in the benchmarks' label is compared in full: two states whose
// counter prints alike (85.5037T, six digits of 48 bits) but whose whole
// hashes differ are reported (validation probe: the counter alone let
// them pass).
TEST(CompareRounds, TheWholeHashInTheLabelIsCompared) {
  std::string text = kThreeRounds;
  for (std::size_t at = text.find("state_hash=85.5037T "); at != std::string::npos;
       at = text.find("state_hash=85.5037T ", at + 1))
    text.insert(at + 20, "state_hash_hex=00004dc4a1b2c3d4 ");
  const auto same = compare_builds(sitting_of(text), "old", "new", {"us_per_step"});
  ASSERT_EQ(same.hashes.size(), 1u);
  EXPECT_TRUE(same.hashes[0].same());
  EXPECT_EQ(*same.hashes[0].old_hashes.begin(), "00004dc4a1b2c3d4");
  text.replace(text.rfind("state_hash_hex=00004dc4a1b2c3d4"), 31, "state_hash_hex=00004dc4a1b2c3d5");
  const auto differ = compare_builds(sitting_of(text), "old", "new", {"us_per_step"});
  EXPECT_FALSE(differ.hashes[0].same());
}

TEST(CompareRounds, BenchmarksOfOneBuildOnlyAreListed) {
  std::string text = kThreeRounds;
  text +=
      "## round 1 build new joints\n"
      "BM_JointLattice/bodies:1000/threads:1/iterations:1/manual_time 330 ms 346 ms 1 ns_per_spring_step=8.6\n";
  const auto c = compare_builds(sitting_of(text), "old", "new", {"ns_per_spring_step"});
  ASSERT_EQ(c.only_in_one.size(), 1u);
  EXPECT_NE(c.only_in_one[0].find("BM_JointLattice/bodies:1000"), std::string::npos);
  EXPECT_NE(c.only_in_one[0].find("only new"), std::string::npos);
  EXPECT_TRUE(c.counters.empty());
}

TEST(CompareRounds, MalformedLogsNameTheLine) {
  auto message_of = [](const std::string& text) {
    try {
      sitting_of(text);
    } catch (const fq::bench::SittingFormatError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message_of("BM_x 1 s 1 s 1 a=1\n"), "log.txt:1: a benchmark line before the first '## round' marker");
  EXPECT_EQ(message_of("# x\n## round one build old\n"), "log.txt:2: expected '## round <number> build <name>'");
  EXPECT_EQ(message_of("## round 1 build old\nBM_x 1 s a=1 b=2q\n"),
            "log.txt:2: counter b: '2q' is not a number");
  EXPECT_EQ(message_of("## round 1 build old\nBM_x a=1\nBM_x a=2\n"),
            "log.txt:3: a second line for BM_x in round 1 of build old");
  EXPECT_THROW(compare_builds(sitting_of(kThreeRounds), "old", "nieuw", {"us_per_step"}), std::invalid_argument);
}

}  // namespace
