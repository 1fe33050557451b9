// Two builds compared in one sitting (validation/README.md, "Comparing two
// builds"): the summary behind compare_rounds and compare_builds.sh, shared
// with its test (tests/validation/test_compare_rounds.cpp).
//
// Input: the console output of the benchmarks, run round by round with the
// builds alternating, each run preceded by a marker line
//   ## round <R> build <NAME> [anything]
// and reporting lines that start with "BM_" and carry counters key=value
// (Google Benchmark's console format; a value may end in k, M, G or T,
// powers of 1000). Other lines are ignored.
//
// Why ratios within a round: on a shared host other tenants slow single
// runs by up to a factor 1.5 (docs/performance_history.md, 2026-11-26), and they do
// so for minutes, not for one run. Two runs next to each other meet about
// the same load, so new / old within a round scatters less than either
// build's own runs; the median over rounds of that ratio is the figure to
// quote, with its range beside it to show what the host did.
//
// Bitwise identity: every benchmark reports `state_hash`; a change meant to
// keep the results must give the same hash in every run of both builds.
#pragma once

#include <istream>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace fq::bench {

// One benchmark line: its name and counters (values in plain units).
struct BenchLine {
  std::string name;
  std::map<std::string, double> counters;
  std::string state_hash;  // as printed ("" when absent)
};

// Runs keyed by (build, benchmark name), in round order.
struct Sitting {
  // build -> benchmark -> round -> line
  std::map<std::string, std::map<std::string, std::map<int, BenchLine>>> runs;
};

// Thrown for input that is not the format above, with its line number.
struct SittingFormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Parses a log (`source` names it in errors). A "BM_" line before any
// marker, a marker without a round number or build name, a counter whose
// value is not a number, or a second line for the same build, benchmark
// and round is an error.
Sitting parse_sitting(std::istream& in, const std::string& source);

// "4.56k" -> 4560, "12" -> 12; throws std::invalid_argument otherwise.
double parse_counter_value(const std::string& text);

// Median of a non-empty sample (mean of the two middle values for an even
// count); throws std::invalid_argument for an empty one.
double median(std::vector<double> values);

struct CounterComparison {
  std::string benchmark;
  std::string counter;
  int old_runs = 0, new_runs = 0;
  double old_median = 0.0, new_median = 0.0;
  int paired_rounds = 0;          // rounds with a run of both builds
  double ratio_median = 0.0;      // median over those rounds of new / old
  double ratio_min = 0.0, ratio_max = 0.0;
};

struct HashCheck {
  std::string benchmark;
  std::set<std::string> old_hashes, new_hashes;
  bool same() const { return old_hashes == new_hashes && old_hashes.size() == 1; }
};

struct Comparison {
  std::vector<CounterComparison> counters;  // benchmark order, then counter order as asked
  std::vector<HashCheck> hashes;            // benchmarks with a state hash in both builds
  std::vector<std::string> only_in_one;     // benchmarks run by one build only
};

// Compares build `new_build` against `old_build` on the named counters
// (those a benchmark does not report are skipped for it). Throws
// std::invalid_argument when either build has no runs.
Comparison compare_builds(const Sitting& sitting, const std::string& old_build, const std::string& new_build,
                          const std::vector<std::string>& counters);

}  // namespace fq::bench
