// compare_rounds: the summary of a sitting in which two builds ran the
// benchmarks alternately (compare_rounds_core.h; validation/README.md,
// "Comparing two builds"). Prints, per benchmark and counter, each build's
// median and the median over rounds of new / old within a round, with its
// range; then whether every run of both builds gave the same state hash.
//
// Exit status (as the other studies): 0 when the state hashes agree, 2 for
// a usage error, 1 for a log that cannot be read or is not in the format,
// 3 when a state hash differs (a change meant to keep every bit did not).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "compare_rounds_core.h"

namespace {

constexpr const char* kUsage =
    "usage: compare_rounds LOG OLD_BUILD NEW_BUILD [COUNTER ...]\n"
    "  LOG        benchmark output with '## round <R> build <NAME>' before each run\n"
    "             (validation/compare_builds.sh writes it)\n"
    "  OLD_BUILD, NEW_BUILD  the build names used in the markers\n"
    "  COUNTER    counters to compare (default: us_per_step joints_s contacts_s\n"
    "             ns_per_spring_step ns_per_body_step)\n";

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::cout << kUsage;
    return 0;
  }
  if (argc < 4) {
    std::cerr << "compare_rounds: a log and two build names expected\n" << kUsage;
    return 2;
  }
  const std::string log = argv[1], old_build = argv[2], new_build = argv[3];
  std::vector<std::string> counters(argv + 4, argv + argc);
  if (counters.empty())
    counters = {"us_per_step", "joints_s", "contacts_s", "ns_per_spring_step", "ns_per_body_step"};
  std::ifstream in(log);
  if (!in) {
    std::cerr << "compare_rounds: cannot read " << log << "\n";
    return 1;
  }
  fq::bench::Comparison c;
  try {
    c = fq::bench::compare_builds(fq::bench::parse_sitting(in, log), old_build, new_build, counters);
  } catch (const fq::bench::SittingFormatError& e) {
    std::cerr << "compare_rounds: " << e.what() << "\n";
    return 1;
  } catch (const std::invalid_argument& e) {  // a build name without runs
    std::cerr << "compare_rounds: " << log << ": " << e.what() << "\n";
    return 2;
  }
  std::printf("| benchmark | counter | runs %s / %s | median %s | median %s | rounds | %s / %s per round: median (range) |\n",
              old_build.c_str(), new_build.c_str(), old_build.c_str(), new_build.c_str(), new_build.c_str(),
              old_build.c_str());
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const auto& r : c.counters) {
    std::printf("| %s | %s | %d / %d | %.4g | %.4g | %d | ", r.benchmark.c_str(), r.counter.c_str(), r.old_runs,
                r.new_runs, r.old_median, r.new_median, r.paired_rounds);
    if (r.paired_rounds > 0)
      std::printf("%.3f (%.2f-%.2f) |\n", r.ratio_median, r.ratio_min, r.ratio_max);
    else
      std::printf("no round with both |\n");
  }
  for (const auto& name : c.only_in_one) std::printf("\nrun by one build only: %s\n", name.c_str());
  int differing = 0;
  for (const auto& h : c.hashes) {
    if (h.same()) continue;
    ++differing;
    std::printf("\nstate hash differs: %s:", h.benchmark.c_str());
    for (const auto& x : h.old_hashes) std::printf(" %s=%s", old_build.c_str(), x.c_str());
    for (const auto& x : h.new_hashes) std::printf(" %s=%s", new_build.c_str(), x.c_str());
    std::printf("\n");
  }
  std::printf("\nstate hashes: %zu benchmarks, %s\n", c.hashes.size(),
              differing == 0 ? "every run of both builds the same" : "SOME DIFFER (see above)");
  return differing == 0 ? 0 : 3;
}
