// Pieces the benchmark programs share: the process's CPU time, the final
// state hash of each scene per thread count, compared at the end of the
// program (results must be bitwise the same for any thread count), the
// scene sizes of the large-scene benchmarks, and the body of main().
#pragma once

#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <map>
#include <string>
#include <utility>

namespace fq::bench {

// CPU seconds of the whole process (all threads): on a shared machine the
// wall time also counts time the process waited for a core.
inline double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

class ThreadHashes {
 public:
  void record(const std::string& scene, int threads, std::uint64_t hash) { hashes_[{scene, threads}] = hash; }
  // One line per scene and thread count above 1 that also ran on 1 thread;
  // returns 1 when any final state differs from the 1-thread one, else 0.
  int compare_with_one_thread() const {
    int status = 0;
    for (const auto& [key, hash] : hashes_) {
      if (key.second == 1) continue;
      const auto one = hashes_.find({key.first, 1});
      if (one == hashes_.end()) continue;
      const bool same = one->second == hash;
      std::printf("%s: final state 1 thread vs %d threads: %s\n", key.first.c_str(), key.second,
                  same ? "identical" : "DIFFERENT");
      if (!same) status = 1;
    }
    return status;
  }

 private:
  std::map<std::pair<std::string, int>, std::uint64_t> hashes_;
};

inline ThreadHashes& thread_hashes() {
  static ThreadHashes hashes;
  return hashes;
}

// Large scenes: 1e3, 1e4 and 1e5 bodies, each on 1 and 2 threads, one timed
// run per repetition (the benchmark sets the time itself).
inline void large_scene_sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "threads"});
  for (const std::int64_t bodies : {1000, 10000, 100000})
    for (const std::int64_t threads : {1, 2}) b->Args({bodies, threads});
  b->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
}

// Runs the benchmarks the command line selects; false for an unknown option.
inline bool run_selected_benchmarks(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return false;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return true;
}

// The body of main(): exit status 1 for an unknown option, else that of the
// 1- vs 2-thread comparison.
inline int run_and_compare_threads(int argc, char** argv) {
  if (!run_selected_benchmarks(argc, argv)) return 1;
  return thread_hashes().compare_with_one_thread();
}

}  // namespace fq::bench
