// Pieces the benchmark programs share: the process's CPU time and each
// thread's, the final
// state hash of each scene per thread count, compared at the end of the
// program (results must be bitwise the same for any thread count), the
// scene sizes of the large-scene benchmarks, and the body of main().
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <map>
#include <string>
#include <utility>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

#include "dem_core/lane_isa.h"
namespace fq::bench {

// CPU seconds of the whole process (all threads): on a shared machine the
// wall time also counts time the process waited for a core.
inline double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// CPU seconds each of `threads` OpenMP threads has run so far (index =
// thread number; 0 is the main thread). libgomp keeps the same threads from
// one parallel region to the next, so two readings around the timed steps
// give each thread's busy time; with OMP_WAIT_POLICY=passive a thread that
// waits at a barrier sleeps and adds nothing. The busiest thread's time is
// then about what the run takes on free cores: it holds the serial parts
// (thread 0) and any imbalance, but not the time the host gave the cores to
// other jobs, which on a shared machine makes the wall time of two threads
// vary by tens of percent from one minute to the next.
inline std::vector<double> thread_cpu_s(int threads) {
  std::vector<double> t(std::size_t(threads > 0 ? threads : 1), 0.0);
  auto read = [](double& out) {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    out = double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  };
#if defined(_OPENMP)
#pragma omp parallel num_threads(threads)
  {
    const int i = omp_get_thread_num();
    if (i < int(t.size())) read(t[std::size_t(i)]);
  }
#else
  read(t[0]);
#endif
  return t;
}

// Largest per-thread difference of two thread_cpu_s readings (s).
inline double busiest_thread_s(const std::vector<double>& before, const std::vector<double>& after) {
  double most = 0.0;
  for (std::size_t i = 0; i < before.size() && i < after.size(); ++i) most = std::max(most, after[i] - before[i]);
  return most;
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

// The final state's hash in full, as the benchmark's label
// ("state_hash_hex=0123456789abcdef" at the end of its line): the
// state_hash counter is printed by Google Benchmark to about six digits
// (274.77T), too few for compare_rounds to tell two states apart (a
// validation probe). compare_rounds reads this one where it is present.
inline void label_state_hash(benchmark::State& state, std::uint64_t hash) {
  char text[40];
  std::snprintf(text, sizeof text, "state_hash_hex=%016llx", static_cast<unsigned long long>(hash));
  state.SetLabel(text);
}

// Large scenes: 1e3, 1e4 and 1e5 bodies, each on 1 and 2 threads, one timed
// run per repetition (the benchmark sets the time itself).
inline void large_scene_sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "threads"});
  for (const std::int64_t bodies : {1000, 10000, 100000})
    for (const std::int64_t threads : {1, 2}) b->Args({bodies, threads});
  b->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
}

// The help text of a program's own options (before Google Benchmark's), or
// null; printed by --help ahead of Google Benchmark's flags.
inline const char*& own_options_help() {
  static const char* text = nullptr;
  return text;
}

inline void print_help() {
  if (const char* own = own_options_help()) std::fputs(own, stdout);
  benchmark::PrintDefaultHelp();
}

// Runs the benchmarks the command line selects; false for an unknown option.
// `own_options`: the help text of the program's own options, listed by
// --help before Google Benchmark's (which --help alone would print).
inline bool run_selected_benchmarks(int argc, char** argv, const char* own_options = nullptr) {
  own_options_help() = own_options;
  benchmark::Initialize(&argc, argv, print_help);
  // The SIMD form of the lane kernels every figure was measured with
  // (FRAMEQUAKE_SIMD=sse2 or avx2 to choose; dem_core/lane_isa.h).
  benchmark::AddCustomContext("simd_form", fq::lane_isa_name(fq::active_lane_isa()));
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return false;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return true;
}

// The body of main(): exit status 1 for an unknown option, else that of the
// 1- vs 2-thread comparison.
inline int run_and_compare_threads(int argc, char** argv, const char* own_options = nullptr) {
  if (!run_selected_benchmarks(argc, argv, own_options)) return 1;
  return thread_hashes().compare_with_one_thread();
}

}  // namespace fq::bench
