// split_by_cost and parallel_for_parts (dem_core/parallel_for.h): the runs
// cover every index once, in order, and their costs are equal shares of the
// total up to one index's cost (the finest a contiguous cut can do).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "dem_core/parallel_for.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace {

// The runs are contiguous, ordered and cover 0 .. n-1.
void expect_cover(const std::vector<std::int64_t>& first, std::int64_t n, int parts) {
  ASSERT_EQ(first.size(), std::size_t(parts) + 1);
  EXPECT_EQ(first.front(), 0);
  EXPECT_EQ(first.back(), n);
  for (int p = 0; p < parts; ++p) EXPECT_LE(first[std::size_t(p)], first[std::size_t(p) + 1]);
}

double run_cost(const std::vector<double>& cost, const std::vector<std::int64_t>& first, int p) {
  return std::accumulate(cost.begin() + first[std::size_t(p)], cost.begin() + first[std::size_t(p) + 1], 0.0);
}

TEST(SplitByCost, EqualCostsGiveEqualCounts) {
  const std::vector<double> cost(100, 3.0);
  std::vector<std::int64_t> first;
  fq::split_by_cost(cost.data(), 100, 2, first);
  expect_cover(first, 100, 2);
  EXPECT_EQ(first[1], 50);
  fq::split_by_cost(cost.data(), 100, 4, first);
  expect_cover(first, 100, 4);
  EXPECT_EQ(first[1], 25);
  EXPECT_EQ(first[2], 50);
  EXPECT_EQ(first[3], 75);
}

TEST(SplitByCost, ClusteredCostsGiveEqualSharesNotEqualCounts) {
  // A pile's narrow phase: the first tenth of the chunks holds the touching
  // pairs and costs 50 times as much per chunk as the rest.
  std::vector<double> cost(400, 1.0);
  for (int i = 0; i < 40; ++i) cost[std::size_t(i)] = 50.0;
  const double total = std::accumulate(cost.begin(), cost.end(), 0.0);
  const double largest = *std::max_element(cost.begin(), cost.end());
  for (int parts : {2, 3, 8}) {
    std::vector<std::int64_t> first;
    fq::split_by_cost(cost.data(), 400, parts, first);
    expect_cover(first, 400, parts);
    for (int p = 0; p < parts; ++p)
      EXPECT_NEAR(run_cost(cost, first, p), total / parts, largest) << parts << " parts, run " << p;
  }
  // Equal halves by count would give the first thread 2160 of 2360
  // (the 40 heavy chunks, 2000, and 160 light ones).
  std::vector<std::int64_t> first;
  fq::split_by_cost(cost.data(), 400, 2, first);
  EXPECT_LT(first[1], 40);
}

TEST(SplitByCost, NoKnownCostGivesEqualCountsAndMorePartsThanIndicesGiveEmptyRuns) {
  const std::vector<double> zero(10, 0.0);
  std::vector<std::int64_t> first;
  fq::split_by_cost(zero.data(), 10, 2, first);
  expect_cover(first, 10, 2);
  EXPECT_EQ(first[1], 5);
  const std::vector<double> three(3, 1.0);
  fq::split_by_cost(three.data(), 3, 5, first);
  expect_cover(first, 3, 5);
  fq::split_by_cost(three.data(), 0, 2, first);
  expect_cover(first, 0, 2);
}

TEST(ParallelForParts, EveryIndexRunsOnceOnOneAndTwoThreads) {
  std::vector<double> cost(1000, 1.0);
  for (int i = 0; i < 100; ++i) cost[std::size_t(i)] = 20.0;
  for (int threads : {1, 2}) {
#if defined(_OPENMP)
    omp_set_num_threads(threads);
#endif
    std::vector<std::int64_t> first;
    fq::split_by_cost(cost.data(), 1000, std::max(1, std::min(fq::worker_count(), 2)), first);
    std::vector<int> visits(1000, 0);
    fq::parallel_for_parts(first, true, [&](std::int64_t i) { ++visits[std::size_t(i)]; });
    for (std::size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i], 1) << "index " << i << ", " << threads << " threads";
  }
}

}  // namespace
