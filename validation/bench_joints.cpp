// Benchmark (not a test): cost of the joint springs and of the body update
// on a large jointed lattice, on 1 and 2 OpenMP threads.
//
// Scene: columns of 10 timber elements (10 x 20 mm section, 29 mm long:
// frame B's columns cut in ten) standing on fixed base blocks on a square
// grid 0.1 m apart; each element joined to the one below by a four-corner
// joint of frame B's trilinear springs (normal + two shear springs per
// corner, 5 % damping), so 12 springs per joint. No contacts. Every
// element starts with a horizontal velocity of 0.05 m/s, so the springs
// work (the columns sway under gravity) during the timed steps.
//
// Counters (medians over repetitions with --benchmark_repetitions):
//   ns_per_spring_step   joint provider time (forces + finish_step books) per
//                        spring and step, from the engine's stage profile,
//                        which times every step here (--profile_every=N
//                        times one step in N, the engine's default being 64:
//                        with 64 timed steps at 1e5 bodies that was a single
//                        step per repetition)
//   ns_per_body_step     integrate stage (leapfrog + rotation + ledger sums)
//                        per body and step, from the same profile
//   ns_per_step_total    wall time per step of the whole scene
//   cpu_ns_per_spring_step  process CPU time per spring-step (all threads,
//                        all stages: on a shared machine the wall time also
//                        counts waiting for a core)
//   busy_ns_per_step     CPU time of the busiest thread per step
//                        (bench_support.h: about the wall time on free
//                        cores, needs OMP_WAIT_POLICY=passive); the parallel
//                        efficiency free of the host's noise is
//                        busy(1 thread) / (2 busy(2 threads))
//   profiled_steps       how many of the timed steps the profile timed
//   state_hash           48-bit hash of the final state; the last lines of
//                        the output compare 1 and 2 threads (bitwise)
//
// Run: OMP_WAIT_POLICY=passive build_rel/validation/bench_joints
//        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bench_support.h"
#include "dem_core/simulation.h"
#include "joints/joint_system.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace {

constexpr int kElementsPerColumn = 10;
// Steps between two timed ones in the engine's stage profile (--profile_every).
int g_profile_every = 1;
constexpr int kWarmSteps = 64;  // untimed steps before the timed ones

fq::SpringDef frame_b_spring() {
  // cases/frame_B.yaml, joint type tenon_new.
  fq::TrilinearParams p;
  p.yield_strain_tension = p.yield_strain_compression = 0.01875;
  p.yield_force_tension_N = p.yield_force_compression_N = 15.0;
  p.ultimate_strain_tension = p.ultimate_strain_compression = 0.075;
  p.ultimate_force_tension_N = p.ultimate_force_compression_N = 22.5;
  return fq::trilinear_spring(p, 0.010, 0.05);
}

struct Lattice {
  std::unique_ptr<fq::Simulation> sim;
  std::size_t springs = 0;
  std::size_t free_bodies = 0;
};

Lattice make_lattice(int free_bodies) {
  const int columns = free_bodies / kElementsPerColumn;
  const int side = int(std::ceil(std::sqrt(double(columns))));
  const double width = 0.020, depth = 0.010, length = 0.029, pitch = 0.1;
  fq::BodyStore store;
  std::vector<std::pair<fq::BodyId, fq::BodyId>> pairs;
  std::vector<fq::Vec3> origins;
  for (int c = 0; c < columns; ++c) {
    const double x = pitch * (c % side), y = pitch * (c / side);
    fq::BoxBodyDef base;
    base.name = "base";
    base.size_m = fq::Vec3(width, depth, 0.02);
    base.position_m = fq::Vec3(x, y, -0.01);
    base.fixed = true;
    base.density_kg_per_m3 = 450.0;
    fq::BodyId below = store.add_box(base);
    for (int k = 0; k < kElementsPerColumn; ++k) {
      fq::BoxBodyDef e;
      e.name = "element";
      e.size_m = fq::Vec3(width, depth, length);
      e.position_m = fq::Vec3(x, y, (k + 0.5) * length);
      e.velocity_mps = fq::Vec3(0.05, 0.0, 0.0);
      e.density_kg_per_m3 = 450.0;
      const fq::BodyId id = store.add_box(e);
      pairs.push_back({below, id});
      origins.push_back(fq::Vec3(x, y, k * length));
      below = id;
    }
  }
  store.update_rotations();
  fq::SimulationSettings s;
  s.dt_s = 1e-5;  // seed 001's step
  s.duration_s = 1.0;
  // Timing every step costs two clock reads per stage (tens of ns against a
  // step of 85 us at 1e3 bodies).
  s.profile_every_steps = g_profile_every;
  Lattice l;
  l.sim = std::make_unique<fq::Simulation>(std::move(store), s);
  auto joints = std::make_unique<fq::JointSystem>(&l.sim->bonded_pairs());
  const fq::SpringDef spring = frame_b_spring();
  const fq::JointLayout layout = fq::four_corner_layout(0.5 * width, 0.5 * depth, 1.0, spring, spring);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    fq::JointDef d;
    d.body_a = pairs[k].first;
    d.body_b = pairs[k].second;
    d.origin_m = origins[k];
    d.layout = layout;
    joints->add_joint(l.sim->bodies(), d);
  }
  l.springs = joints->spring_count();
  l.free_bodies = pairs.size();
  l.sim->add_force_provider(std::move(joints));
  return l;
}

void BM_JointLattice(benchmark::State& state) {
  const int bodies = int(state.range(0));
  const int threads = int(state.range(1));
#if defined(_OPENMP)
  omp_set_num_threads(threads);
#else
  if (threads > 1) {
    state.SkipWithError("built without OpenMP");
    return;
  }
#endif
  const int timed_steps = bodies <= 1000 ? 2000 : bodies <= 10000 ? 256 : 64;
  // The timed steps are kWarmSteps .. kWarmSteps + timed_steps - 1; the
  // profile times those whose index is a multiple of the interval.
  int profiled = 0;
  for (int k = kWarmSteps; k < kWarmSteps + timed_steps; ++k) profiled += k % g_profile_every == 0;
  if (profiled == 0) {
    state.SkipWithError(("--profile_every=" + std::to_string(g_profile_every) + " times none of the " +
                         std::to_string(timed_steps) + " timed steps")
                            .c_str());
    return;
  }
  double ns_spring = 0.0, ns_body = 0.0, ns_step = 0.0, cpu_ns_spring = 0.0, busy_ns_step = 0.0;
  std::uint64_t hash = 0;
  for (auto _ : state) {
    Lattice l = make_lattice(bodies);
    l.sim->initialize();
    for (int k = 0; k < kWarmSteps; ++k) l.sim->step();  // warm caches and the profile's phase
    const fq::StageProfile p0 = l.sim->profile();
    const double cpu0 = fq::bench::process_cpu_s();
    const std::vector<double> busy0 = fq::bench::thread_cpu_s(threads);
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < timed_steps; ++k) l.sim->step();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double busy = fq::bench::busiest_thread_s(busy0, fq::bench::thread_cpu_s(threads));
    const double cpu = fq::bench::process_cpu_s() - cpu0;
    const fq::StageProfile& p1 = l.sim->profile();
    // Joint provider time: its force stage plus the finish stage (joints are
    // the only provider, so the whole finish stage is theirs).
    const double joints_s = (p1.provider_seconds[0] - p0.provider_seconds[0]) +
                            (p1.seconds[int(fq::Stage::FinishStep)] - p0.seconds[int(fq::Stage::FinishStep)]);
    const double integrate_s = p1.seconds[int(fq::Stage::Integrate)] - p0.seconds[int(fq::Stage::Integrate)];
    state.SetIterationTime(wall);
    const double spring_steps = double(l.springs) * timed_steps;
    // The profile scales each timed step by the interval; per step timed:
    const double profile_steps = double(profiled) * g_profile_every;
    ns_spring = 1e9 * joints_s / (double(l.springs) * profile_steps);
    ns_body = 1e9 * integrate_s / (double(l.free_bodies) * profile_steps);
    ns_step = 1e9 * wall / timed_steps;
    cpu_ns_spring = 1e9 * cpu / spring_steps;
    busy_ns_step = 1e9 * busy / timed_steps;
    hash = l.sim->state_hash();
    state.counters["springs"] = double(l.springs);
  }
  state.counters["ns_per_spring_step"] = ns_spring;
  state.counters["ns_per_body_step"] = ns_body;
  state.counters["ns_per_step_total"] = ns_step;
  state.counters["cpu_ns_per_spring_step"] = cpu_ns_spring;
  state.counters["busy_ns_per_step"] = busy_ns_step;
  state.counters["profiled_steps"] = profiled;
  state.counters["state_hash"] = double(hash & ((std::uint64_t(1) << 48) - 1));
  fq::bench::label_state_hash(state, hash);
  fq::bench::thread_hashes().record("joint lattice, " + std::to_string(bodies) + " bodies", threads, hash);
}

BENCHMARK(BM_JointLattice)->Apply(fq::bench::large_scene_sizes);

}  // namespace

int main(int argc, char** argv) {
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::strncmp(argv[i], "--profile_every=", 16) == 0) {
      char* end = nullptr;
      const long n = std::strtol(argv[i] + 16, &end, 10);
      if (end == argv[i] + 16 || *end != '\0' || n < 1 || n > 1000000) {
        std::fprintf(stderr, "bench_joints: --profile_every expects a whole number of steps from 1, got '%s'\n",
                     argv[i] + 16);
        return 2;
      }
      g_profile_every = int(n);
    } else {
      rest.push_back(argv[i]);
    }
  }
  int rest_count = int(rest.size());
  return fq::bench::run_and_compare_threads(
      rest_count, rest.data(),
      "  --profile_every=N   time one step in N in the engine's stage profile (default 1: every step)\n");
}
