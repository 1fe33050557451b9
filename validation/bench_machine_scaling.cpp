// Benchmark (not a test): what 2 threads can gain on THIS machine, for
// loops that are perfectly parallel -- the ceiling against which the
// engine's parallel efficiency (bench_joints, bench_contact_pile) is read.
//
// Three kernels, each a fixed amount of work split evenly between the
// threads (strong scaling, no shared writes, one barrier at the end):
//   latency     one dependent chain of multiply-adds per thread (waits on
//               the latency of each operation; leaves the core's execution
//               ports mostly idle)
//   throughput  sixteen independent chains per thread (keeps the
//               floating-point ports busy, as the joint and contact loops
//               do: about 3 instructions per cycle)
//   memory      triad a[i] = b[i] + s c[i] over 3 x 128 MiB (bound by the
//               memory bandwidth the guest gets)
//   cache       the same triad over 3 x 4 MiB, 128 passes: larger than the
//               L2 caches, within the shared L3; the working set of the
//               1e4-body scenes (10-20 MB) streams like this
//   region      20 000 parallel regions with about a microsecond of work
//               per thread each: what entering and leaving one costs under
//               the OMP_WAIT_POLICY in force (the engine enters 10-20 per
//               step of a large scene). Not a scaling kernel: its line at
//               the end gives the cost per region on 2 threads.
// Two threads on two real cores give a speed-up near 2 for all three.
// Two hardware threads of ONE core (a host may map vCPUs that way; the
// guest cannot tell) give near 2 for `latency` but far less for
// `throughput`, whose ports the threads share. Memory-bound loops show how
// much bandwidth the second core adds.
//
// Run: OMP_WAIT_POLICY=passive build_rel/validation/bench_machine_scaling
//        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// The last lines give the speed-up of 2 threads over 1 from the median times.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bench_support.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace {

constexpr long kLatencySteps = 200'000'000;     // multiply-adds per run, all threads together
constexpr long kThroughputSteps = 100'000'000;  // per chain, 16 chains
constexpr std::size_t kTriadLength = std::size_t(16) << 20;       // doubles per array (128 MiB)
constexpr std::size_t kCacheTriadLength = std::size_t(512) << 10;  // doubles per array (4 MiB)

// Every (kernel, threads) run's wall seconds, for the speed-up lines at exit.
std::map<std::pair<std::string, int>, std::vector<double>>& run_times() {
  static std::map<std::pair<std::string, int>, std::vector<double>> times;
  return times;
}

template <class Body>
double timed_parallel(int threads, Body body) {
  const auto t0 = std::chrono::steady_clock::now();
#if defined(_OPENMP)
#pragma omp parallel num_threads(threads)
  body(omp_get_thread_num(), omp_get_num_threads());
#else
  (void)threads;
  body(0, 1);
#endif
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void BM_Latency(benchmark::State& state) {
  const int threads = int(state.range(0));
  for (auto _ : state) {
    std::vector<double> out(std::size_t(threads) * 8, 0.0);  // one cache line per thread
    const double s = timed_parallel(threads, [&](int t, int nt) {
      double x = 1.0 + 1e-3 * t;
      for (long k = 0; k < kLatencySteps / nt; ++k) x = x * 0.999999 + 1e-6;
      out[std::size_t(t) * 8] = x;
    });
    benchmark::DoNotOptimize(out.data());
    state.SetIterationTime(s);
    run_times()[{"latency", threads}].push_back(s);
  }
}

void BM_Throughput(benchmark::State& state) {
  const int threads = int(state.range(0));
  for (auto _ : state) {
    std::vector<double> out(std::size_t(threads) * 8, 0.0);
    const double s = timed_parallel(threads, [&](int t, int nt) {
      double x[16];
      for (int c = 0; c < 16; ++c) x[c] = 1.0 + 1e-3 * (t * 16 + c);
      for (long k = 0; k < kThroughputSteps / nt; ++k)
        for (int c = 0; c < 16; ++c) x[c] = x[c] * 0.999999 + 1e-6;
      double sum = 0.0;
      for (int c = 0; c < 16; ++c) sum += x[c];
      out[std::size_t(t) * 8] = sum;
    });
    benchmark::DoNotOptimize(out.data());
    state.SetIterationTime(s);
    run_times()[{"throughput", threads}].push_back(s);
  }
}

// a[i] = b[i] + s c[i] over `length` doubles per array, `passes` times,
// each thread on its own contiguous share (first touched by it).
void triad(benchmark::State& state, std::size_t length, int passes, const char* kernel) {
  const int threads = int(state.range(0));
  std::vector<double> a(length), b(length), c(length);
  timed_parallel(threads, [&](int t, int nt) {
    const std::size_t lo = length * std::size_t(t) / std::size_t(nt);
    const std::size_t hi = length * std::size_t(t + 1) / std::size_t(nt);
    for (std::size_t i = lo; i < hi; ++i) a[i] = 0.0, b[i] = 1.0, c[i] = 2.0;
  });
  for (auto _ : state) {
    const double s = timed_parallel(threads, [&](int t, int nt) {
      const std::size_t lo = length * std::size_t(t) / std::size_t(nt);
      const std::size_t hi = length * std::size_t(t + 1) / std::size_t(nt);
      for (int pass = 0; pass < passes; ++pass)
        for (std::size_t i = lo; i < hi; ++i) a[i] = b[i] + 0.5 * c[i];
    });
    benchmark::DoNotOptimize(a.data());
    state.SetIterationTime(s);
    state.counters["GB_per_s"] = double(passes) * 3.0 * 8.0 * double(length) / s * 1e-9;
    run_times()[{kernel, threads}].push_back(s);
  }
}

void BM_Memory(benchmark::State& state) { triad(state, kTriadLength, 4, "memory"); }
void BM_Cache(benchmark::State& state) { triad(state, kCacheTriadLength, 128, "cache"); }

constexpr int kRegions = 20'000;

void BM_Region(benchmark::State& state) {
  const int threads = int(state.range(0));
  for (auto _ : state) {
    std::vector<double> out(std::size_t(threads) * 8, 1.0);
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < kRegions; ++r)
      timed_parallel(threads, [&](int t, int) {
        double x = out[std::size_t(t) * 8];
        for (int k = 0; k < 1000; ++k) x = x * 0.999999 + 1e-6;
        out[std::size_t(t) * 8] = x;
      });
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    benchmark::DoNotOptimize(out.data());
    state.SetIterationTime(s);
    state.counters["us_per_region"] = 1e6 * s / kRegions;
    run_times()[{"region", threads}].push_back(s);
  }
}

BENCHMARK(BM_Latency)->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Throughput)->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Memory)->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Cache)->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Region)->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(1);

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  if (!fq::bench::run_selected_benchmarks(argc, argv)) return 1;
  for (const char* kernel : {"latency", "throughput", "memory", "cache"}) {
    const auto one = run_times().find({kernel, 1}), two = run_times().find({kernel, 2});
    if (one == run_times().end() || two == run_times().end()) continue;
    const double s1 = median(one->second), s2 = median(two->second);
    std::printf("%s: median %.3f s on 1 thread, %.3f s on 2 threads: speed-up %.2f (efficiency %.0f %%)\n", kernel,
                s1, s2, s1 / s2, 50.0 * s1 / s2);
  }
  const auto regions = run_times().find({"region", 2});
  if (regions != run_times().end()) {
    const char* policy = std::getenv("OMP_WAIT_POLICY");
    std::printf("region: a parallel region with ~1 us of work per thread takes %.1f us on 2 threads (median; OMP_WAIT_POLICY=%s)\n",
                1e6 * median(regions->second) / kRegions, policy && *policy ? policy : "unset, libgomp's default");
  }
  return 0;
}
