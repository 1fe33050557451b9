// Benchmark (not a test): wall time of the seed-001 frames A, B and C
// (cases/frame_*.yaml) under their 20 record seconds of the Kobe NS record
// at dt = 1e-5 s (time scale 0.3162: 6.324 s simulated, 632 400 steps).
//
// Two variants per frame:
//   BM_Frame/<X>/no_output    the simulation alone (no observers): the
//                             engine's cost, what the speed target is about
//   BM_Frame/<X>/with_output  the whole `framequake run` (VTK frame every
//                             0.01 s, history row every 1 ms, events,
//                             summary) into a temporary folder
// Counters:
//   steps               steps of the run
//   us_per_step         wall time per step (microseconds)
//   s_per_2e6_steps     wall time scaled to 2e6 steps (20 s simulated at
//                       dt = 1e-5 s, the figure)
//   cpu_s               process CPU time of the run (all threads)
//   joints_s, contacts_s, integrate_s, finish_s, observe_s, external_s
//                       the engine's own stage profile (summary.json's
//                       stage_seconds: sampled one step in 64 and scaled)
//   state_hash          48-bit hash of the final state (bitwise comparison
//                       across thread counts: the final line of the output
//                       says whether 1 and 2 threads agree)
//
// Run (Release build; one repetition of the three frames takes about a
// minute on one free core):
//   OMP_WAIT_POLICY=passive build_rel/validation/bench_frames
//     --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// Options of this program (before the Google Benchmark ones):
//   --record_seconds=S  use only S record seconds instead of the cases' 20
//                       (a quick look; the per-step figures stay comparable)
//   --threads=N         OpenMP threads (default 1: the target is one core);
//                       --threads=1,2 runs both and compares the final states
//   --intact_nodes=M    contact.intact_nodes of every frame (touch, the
//                       cases' own, ground_only or none; io/case_def.h); the
//                       benchmarks are then named BM_Frame/<X>.<M>/...
// The case files are read relative to the repository root, so run it from
// there (or set FQ_SOURCE_DIR).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bench_support.h"
#include "io/case_file.h"
#include "io/case_runner.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace {

double g_record_seconds = 0.0;  // 0: the case's own window
std::optional<fq::IntactNodeContact> g_intact_nodes;  // unset: the case's own

// --help: these, then Google Benchmark's flags.
constexpr const char* kOwnOptions =
    "bench_frames: wall time of frames A, B and C (cases/frame_*.yaml; run from the repository root or set\n"
    "FQ_SOURCE_DIR)\n"
    "Options of this program:\n"
    "  --record_seconds=S  use only S record seconds instead of the cases' 20 (a quick look; the per-step\n"
    "                      figures stay comparable)\n"
    "  --threads=N[,M..]   OpenMP threads of the no_output runs (default 1); --threads=1,2 runs both and\n"
    "                      compares the final states (exit status 1 if they differ)\n"
    "  --intact_nodes=M    contact.intact_nodes of every frame: touch (the cases' own), ground_only or none\n"
    "                      (cases/README.md); each benchmark's name then has .M after its frame's letter\n"
    "Google Benchmark's flags:\n";

std::filesystem::path case_path(const std::string& frame) {
  const char* root = std::getenv("FQ_SOURCE_DIR");
  std::filesystem::path base = root ? std::filesystem::path(root) : std::filesystem::current_path();
  return base / "cases" / ("frame_" + frame + ".yaml");
}

void set_threads(int threads) {
#if defined(_OPENMP)
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
}

void run_frame(benchmark::State& state, const std::string& frame, bool with_output, int threads) {
  set_threads(threads);
  fq::CaseDef def;
  try {
    def = fq::load_case_file(case_path(frame));
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  if (g_record_seconds > 0.0 && def.ground_motion) def.ground_motion->window_length_s = g_record_seconds;
  if (g_intact_nodes && def.contact) def.contact->intact_nodes = *g_intact_nodes;
  const auto out_dir = std::filesystem::temp_directory_path() / ("fq_bench_frame_" + frame);

  std::int64_t steps = 0;
  double wall = 0.0, cpu = 0.0;
  fq::StageProfile profile;
  std::uint64_t hash = 0;
  for (auto _ : state) {
    if (with_output) {
      std::filesystem::remove_all(out_dir);
      fq::CaseRunOptions options;
      options.output_folder = out_dir;
      const double cpu0 = fq::bench::process_cpu_s();
      const auto t0 = std::chrono::steady_clock::now();
      const fq::CaseRunReport report = fq::run_case(def, options);
      wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      cpu = fq::bench::process_cpu_s() - cpu0;
      steps = report.result.steps;
      hash = 0;
    } else {
      fq::Scene scene = fq::build_scene(def);
      const double cpu0 = fq::bench::process_cpu_s();
      const auto t0 = std::chrono::steady_clock::now();
      const fq::RunResult result = scene.simulation->run();
      wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      cpu = fq::bench::process_cpu_s() - cpu0;
      steps = result.steps;
      profile = scene.simulation->profile();
      hash = scene.simulation->state_hash();
    }
    state.SetIterationTime(wall);
  }
  if (with_output) std::filesystem::remove_all(out_dir);
  state.counters["steps"] = double(steps);
  state.counters["us_per_step"] = 1e6 * wall / double(steps);
  state.counters["s_per_2e6_steps"] = wall * 2e6 / double(steps);
  state.counters["cpu_s"] = cpu;
  if (!with_output) {
    auto stage = [&](fq::Stage s) { return profile.seconds[std::size_t(s)]; };
    state.counters["external_s"] = stage(fq::Stage::ExternalForces);
    state.counters["integrate_s"] = stage(fq::Stage::Integrate);
    state.counters["finish_s"] = stage(fq::Stage::FinishStep);
    if (profile.provider_seconds.size() >= 2) {
      state.counters["joints_s"] = profile.provider_seconds[0];
      state.counters["contacts_s"] = profile.provider_seconds[1];
    }
    state.counters["state_hash"] = double(hash & ((std::uint64_t(1) << 48) - 1));
    fq::bench::thread_hashes().record("frame " + frame, threads, hash);
    fq::bench::label_state_hash(state, hash);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> thread_counts{1};
  std::vector<char*> rest;
  std::string mode_name;
  for (int i = 0; i < argc; ++i) {
    const char* a = argv[i];
    if (std::strncmp(a, "--record_seconds=", 17) == 0) {
      g_record_seconds = std::atof(a + 17);
      if (!(g_record_seconds > 0.0)) {
        std::fprintf(stderr, "bench_frames: --record_seconds expects a positive number of record seconds, got '%s'\n",
                     a + 17);
        return 2;
      }
    } else if (std::strncmp(a, "--intact_nodes=", 15) == 0) {
      mode_name = a + 15;
      fq::IntactNodeContact mode{};
      if (fq::parse_intact_node_contact(mode_name, mode)) {
        g_intact_nodes = mode;
      } else {
        std::fprintf(stderr, "bench_frames: --intact_nodes expects touch, ground_only or none, got '%s'\n", a + 15);
        return 2;
      }
    } else if (std::strncmp(a, "--threads=", 10) == 0) {
      thread_counts.clear();
      for (const char* p = a + 10; *p;) {
        char* end = nullptr;
        const long n = std::strtol(p, &end, 10);
        if (end == p || n < 1) {
          std::fprintf(stderr, "bench_frames: --threads expects a list like 1,2, got '%s'\n", a + 10);
          return 2;
        }
        thread_counts.push_back(int(n));
        p = *end == ',' ? end + 1 : end;
      }
    } else {
      rest.push_back(argv[i]);
    }
  }
  for (const char* frame : {"A", "B", "C"}) {
    const std::string label = std::string(frame) + (mode_name.empty() ? "" : "." + mode_name);
    for (int threads : thread_counts) {
      const std::string suffix = "/threads:" + std::to_string(threads);
      benchmark::RegisterBenchmark(
          ("BM_Frame/" + label + "/no_output" + suffix).c_str(),
          [frame, threads](benchmark::State& s) { run_frame(s, frame, false, threads); })
          ->Iterations(1)
          ->UseManualTime()
          ->Unit(benchmark::kSecond);
    }
    benchmark::RegisterBenchmark(("BM_Frame/" + label + "/with_output/threads:1").c_str(),
                                 [frame](benchmark::State& s) { run_frame(s, frame, true, 1); })
        ->Iterations(1)
        ->UseManualTime()
        ->Unit(benchmark::kSecond);
  }
  return fq::bench::run_and_compare_threads(int(rest.size()), rest.data(), kOwnOptions);
}
