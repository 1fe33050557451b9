// Breaking is identical with 1 and 2 OpenMP threads: a chain whose joints
// yield and break under a strong alternating kick (soft joints, E = 1e7 Pa,
// so that a few hundred steps suffice), with every loop forced onto
// the thread team (parallel_min_items = 1). Same events (all fields) and a
// bitwise identical final state are required: each spring writes its own
// slots and each body gathers them in a fixed order (joint_system.h).
#include <gtest/gtest.h>

#include "dem_core/simulation.h"
#include "joint_test_util.h"
#if defined(_OPENMP)
#include <omp.h>
#endif

namespace fq {
namespace {

test::JointRunOutcome run(int threads) {
#if defined(_OPENMP)
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  test::ChainSpec spec;
  spec.n = 8;
  spec.length_m = 0.8;
  spec.width_m = spec.depth_m = 0.03;
  const BeamSection sec = rectangular_section(spec.width_m, spec.depth_m);
  const double l = spec.length_m / spec.n;
  auto layout_of = [&](int i) {
    JointLayout lay = calibrated_beam_layout(sec, 1e7, 1e7 / 16, i == 0 ? 0.5 * l : l, 0.02);
    for (SpringPointDef& p : lay.points) {
      if (!p.has_normal) continue;
      const double k = p.normal.law.linear.stiffness_Npm;
      // Brittle-ish timber joint: yields at 0.2 mm, breaks at 1 mm (10 mm reference length).
      TrilinearParams t;
      t.yield_strain_tension = t.yield_strain_compression = 0.02;
      t.yield_force_tension_N = t.yield_force_compression_N = k * 2e-4;
      t.ultimate_strain_tension = t.ultimate_strain_compression = 0.1;
      t.ultimate_force_tension_N = t.ultimate_force_compression_N = k * 2e-4 * 1.2;
      p.normal = trilinear_spring(t, 0.01, 0.02);
    }
    return lay;
  };
  BodyStore bodies = test::chain_bodies(spec);
  double omega_max = 0.0;
  {
    JointSystem probe(nullptr);
    test::add_chain_joints(probe, bodies, spec, layout_of);
    omega_max = probe.stiffest_mode(bodies).omega_radps;
  }
  // Alternating kick: neighbours pull apart and shear past each other.
  for (int i = 1; i <= spec.n; ++i) {
    const double sgn = (i % 2) ? 1.0 : -1.0;
    bodies.velocity_mps[std::size_t(i)] = Vec3(0.9 * sgn, 0.3 * sgn, 1.2 * sgn);
  }
  SimulationSettings settings;
  settings.dt_s = 0.9 / omega_max;           // omega_max is an upper bound; the limit is 2 / omega_max
  settings.duration_s = 40 * settings.dt_s;  // few steps: forced threading costs a thread wake-up per loop
  Simulation sim(std::move(bodies), settings);
  JointSystemSettings js_settings;
  js_settings.parallel_min_items = 1;
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs(), js_settings);
  test::add_chain_joints(*js, sim.bodies(), spec, layout_of);
  const JointSystem* joints = js.get();
  sim.add_force_provider(std::move(js));
  const RunResult rr = sim.run();
  EXPECT_EQ(rr.status, RunStatus::Completed);
  return test::capture_outcome(sim, *joints);
}

TEST(JointThreads, BreakingIsIdenticalWithOneAndTwoThreads) {
  const test::JointRunOutcome a = run(1), b = run(2);
  EXPECT_GT(a.counts.broken, 0);  // the scenario does break joints
  test::expect_identical(a, b);
  // Events come out in ascending (step, joint, spring) order.
  for (std::size_t i = 1; i < a.events.size(); ++i) {
    const Event &p = a.events[i - 1], &q = a.events[i];
    if (p.step == q.step) {
      EXPECT_LE(p.joint_id, q.joint_id);
    }
  }
  std::printf("threads: %zu events, %d joints broken, %d yielded, last event at step %ld\n", a.events.size(),
              a.counts.broken, a.counts.yielded, a.events.empty() ? -1L : long(a.events.back().step));
}

}  // namespace
}  // namespace fq
