// Benchmark (not a test): a pile of falling boxes handled by the contact
// system alone, at 1e3, 1e4 and 1e5 bodies, on 1 and 2 OpenMP threads; and
// the same numbers of boxes standing in pressed columns (every box in
// contact), which weighs the per-contact work more.
//
// Reports per run (Google Benchmark counters):
//   ns_per_body_step   wall time of the timed steps / (bodies * steps)
//   cpu_ns_per_body_step  the same with the process CPU time (all threads)
//   busy_ns_per_body_step  the same with the busiest thread's CPU time
//                      (bench_support.h: about the wall time on free cores;
//                      needs OMP_WAIT_POLICY=passive). The parallel
//                      efficiency on 2 threads, free of the host's noise,
//                      is busy(1 thread) / (2 busy(2 threads)).
//   rebuilds_per_step  broad-phase rebuilds per timed step
//   contacts           contact points at the end
//   state_hash         48-bit FNV-1a hash of the final positions, orientations
//                      and velocities; equal hashes for 1 and 2 threads mean a
//                      bitwise identical final state (also checked at exit).
// Each repetition builds the scene, runs untimed steps (200 for the pile, so
// that it has landed and is colliding; 20 for the columns), then times a
// fixed number of steps (1000, 200, 50 for 1e3, 1e4, 1e5 bodies).
//
// Run: build_dir/validation/bench_contact_pile --benchmark_repetitions=3
//        --benchmark_report_aggregates_only=true
// On a machine shared with other jobs, set OMP_WAIT_POLICY=passive: with
// spinning barriers, a thread waiting for a descheduled partner burns whole
// time slices and the 2-thread figures become meaningless.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstring>
#include <memory>
#include <string>

#include "bench_support.h"
#include "contacts/contact_system.h"
#include "dem_core/simulation.h"
#include "pile_scene.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace {

std::uint64_t fnv1a(std::uint64_t h, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

std::uint64_t state_hash(const fq::BodyStore& b) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < b.size(); ++i) {
    h = fnv1a(h, b.position_m[i].data(), 3 * sizeof(double));
    h = fnv1a(h, b.orientation[i].coeffs().data(), 4 * sizeof(double));
    h = fnv1a(h, b.velocity_mps[i].data(), 3 * sizeof(double));
  }
  return h & ((std::uint64_t(1) << 48) - 1);  // exact in a double counter
}

// scene 0: falling pile (make_box_pile), 1: pressed columns, every box in
// contact from the start (make_pressed_columns).
void run_contact_benchmark(benchmark::State& state, int scene) {
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
  const int timed_steps = bodies <= 1000 ? 1000 : bodies <= 10000 ? 200 : 50;
  double ns_per_body_step = 0.0, cpu_ns_per_body_step = 0.0, busy_ns_per_body_step = 0.0, rebuild_rate = 0.0,
         contacts = 0.0;
  std::uint64_t hash = 0;
  for (auto _ : state) {
    fq::SimulationSettings s;
    s.dt_s = 1e-4;  // k = 1e5 N/m on 0.12 kg boxes: w dt = 0.45 (stable)
    s.duration_s = 1.0;
    auto sim = std::make_unique<fq::Simulation>(
        scene == 0 ? fq::test::make_box_pile(bodies) : fq::test::make_pressed_columns(bodies), s);
    auto system = std::make_unique<fq::ContactSystem>(&sim->bonded_pairs());
    fq::ContactParams p;
    p.normal_stiffness_N_per_m = 1e5;
    system->set_ground(0.0, p);
    system->set_pair_params(0, 0, p);
    const fq::ContactSystem* contacts_view = system.get();
    sim->add_force_provider(std::move(system));
    const int warm_up_steps = scene == 0 ? 200 : 20;  // the columns touch from the start
    for (int k = 0; k < warm_up_steps; ++k) sim->step();
    const auto rebuilds0 = contacts_view->broad_phase_rebuilds();
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = fq::bench::process_cpu_s();
    const std::vector<double> busy0 = fq::bench::thread_cpu_s(threads);
    for (int k = 0; k < timed_steps; ++k) sim->step();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double busy = fq::bench::busiest_thread_s(busy0, fq::bench::thread_cpu_s(threads));
    cpu_ns_per_body_step = 1e9 * (fq::bench::process_cpu_s() - cpu0) / (double(bodies) * timed_steps);
    busy_ns_per_body_step = 1e9 * busy / (double(bodies) * timed_steps);
    state.SetIterationTime(wall);
    ns_per_body_step = 1e9 * wall / (double(bodies) * timed_steps);
    rebuild_rate = double(contacts_view->broad_phase_rebuilds() - rebuilds0) / timed_steps;
    contacts = double(contacts_view->contact_count());
    hash = state_hash(sim->bodies());
  }
  state.counters["ns_per_body_step"] = ns_per_body_step;
  state.counters["cpu_ns_per_body_step"] = cpu_ns_per_body_step;
  state.counters["busy_ns_per_body_step"] = busy_ns_per_body_step;
  state.counters["rebuilds_per_step"] = rebuild_rate;
  state.counters["contacts"] = contacts;
  state.counters["state_hash"] = double(hash);
  fq::bench::label_state_hash(state, hash);
  const std::string name = std::string(scene == 0 ? "pile" : "columns") + ", " + std::to_string(bodies) + " bodies";
  fq::bench::thread_hashes().record(name, threads, hash);
}

void BM_ContactPile(benchmark::State& state) { run_contact_benchmark(state, 0); }
void BM_ContactColumns(benchmark::State& state) { run_contact_benchmark(state, 1); }

BENCHMARK(BM_ContactColumns)->Apply(fq::bench::large_scene_sizes);

BENCHMARK(BM_ContactPile)->Apply(fq::bench::large_scene_sizes);

}  // namespace

int main(int argc, char** argv) { return fq::bench::run_and_compare_threads(argc, argv); }
