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

// EqualChunks: the chunks cover 0 .. n-1 in order, depend on n alone, and
// above one chunk come in a multiple of `multiple` of equal size (to one
// item), so that the halves, quarters and eighths a static schedule hands
// to 2, 4 or 8 threads hold the same number of items to within a chunk's
// rounding.
TEST(EqualChunks, CoverInOrderWithEqualSizesAndAMultipleOfTheThreads) {
  for (std::size_t n : {0ul, 1ul, 1000ul, 1024ul, 1025ul, 4096ul, 11000ul, 110000ul, 1234567ul}) {
    const fq::EqualChunks c(n, 1024, 8);
    // Expected count: ceil(n / 1024), and above 1 rounded up to a multiple of 8.
    const std::size_t plain = (n + 1023) / 1024;
    const std::size_t expected = plain <= 1 ? plain : (plain + 7) / 8 * 8;
    ASSERT_EQ(c.count, expected) << n;
    if (c.count == 0) continue;
    EXPECT_EQ(c.begin(0), 0u);
    EXPECT_EQ(c.begin(c.count), n);
    std::size_t smallest = n, largest = 0;
    for (std::size_t k = 0; k < c.count; ++k) {
      const std::size_t size = c.begin(k + 1) - c.begin(k);
      smallest = std::min(smallest, size);
      largest = std::max(largest, size);
    }
    EXPECT_LE(largest - smallest, 1u) << n;
    EXPECT_LE(largest, 1024u) << n;  // never larger than asked
    // Two threads, static schedule: chunks [0, count/2) and [count/2, count).
    if (c.count > 1) {
      const std::size_t first_half = c.begin(c.count / 2), second_half = n - first_half;
      EXPECT_LE(std::max(first_half, second_half) - std::min(first_half, second_half), 1u) << n;
    }
  }
  // The 1e4-body lattice (10 000 elements and 1 000 fixed bases): fixed
  // chunks of 1024 gave one thread 6 chunks (6 144 bodies) and the other 4 856.
  const fq::EqualChunks lattice(11000, 1024, 8);
  EXPECT_EQ(lattice.count, 16u);
  EXPECT_EQ(lattice.begin(8), 5500u);
}
