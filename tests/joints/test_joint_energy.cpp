// Energy ledger with joints.
// (1) Elastic laws, no dashpots, free vibration: the leapfrog scheme keeps a
//     shadow energy; the ledger's total then oscillates with a relative
//     amplitude <= (w_max dt)^2 / 8 (harmonic oscillator: the modified
//     energy differs from the true one by (w dt)^2/8 of it at most), and the
//     error is second order: halving dt divides it by ~4 (asserted 3..5).
// (2) Trilinear springs that yield, dashpots on (zeta = 0.05), gravity: the
//     books (elastic stored, plastic = work - stored by the trapezoid rule,
//     viscous by the leapfrog average velocity) balance to the same O(dt^2)
//     bound: the trapezoid rule is exact on linear branches and the dashpot
//     sum is the leapfrog work of the applied dashpot forces (trapezoid in
//     time from t = 0, as the ledger's kinetic energy is); so the error is
//     again second order (halving dt divides it by 3..5).
#include <gtest/gtest.h>

#include <algorithm>

#include "dem_core/simulation.h"
#include "joint_test_util.h"

namespace fq {
namespace {

struct MaxError : StepObserver {
  double max_abs_J = 0.0;
  double scale_J = 0.0;
  double last_plastic_J = 0.0, last_viscous_J = 0.0;
  void on_sample(const Simulation& sim) override {
    max_abs_J = std::max(max_abs_J, std::abs(sim.ledger().balance_error_J()));
    scale_J = sim.ledger().scale_J;
    last_plastic_J = sim.ledger().dissipated_plastic_J;
    last_viscous_J = sim.ledger().dissipated_viscous_J;
  }
};

struct RunSummary {
  double rel_error = 0.0;
  double omega_dt = 0.0;
  double plastic_J = 0.0, viscous_J = 0.0;
  int yield_events = 0;
};

RunSummary run_chain(bool inelastic, double dt_fraction) {
  test::ChainSpec spec;
  spec.n = 3;
  spec.length_m = 0.6;
  spec.width_m = 0.04;
  spec.depth_m = 0.03;
  const BeamSection sec = rectangular_section(spec.width_m, spec.depth_m);
  const double e = 1e9, g = e / 16.0, l = spec.length_m / spec.n;
  auto layout_of = [&](int i) {
    JointLayout lay = calibrated_beam_layout(sec, e, g, i == 0 ? 0.5 * l : l, inelastic ? 0.05 : 0.0);
    if (inelastic) {
      for (SpringPointDef& p : lay.points) {
        if (!p.has_normal) continue;
        // Yield at strain 1e-4 of a 10 mm reference length (1 um), far
        // below what the initial kick produces, ultimate far beyond it.
        const double k = p.normal.law.linear.stiffness_Npm;
        TrilinearParams t;
        t.yield_strain_tension = t.yield_strain_compression = 1e-4;
        t.yield_force_tension_N = t.yield_force_compression_N = k * 1e-6;
        t.ultimate_strain_tension = t.ultimate_strain_compression = 1.0;
        t.ultimate_force_tension_N = t.ultimate_force_compression_N = k * 1e-6 + 0.05 * k * (1e-2 - 1e-6);
        p.normal = trilinear_spring(t, 0.01, 0.05);
      }
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
  // A kick: lateral and out-of-plane velocity and a spin on the top element.
  bodies.velocity_mps[3] = Vec3(0.05, 0.02, 0.0);
  bodies.angular_momentum_Nms[3] = Vec3(0.0, 0.0, 1e-6);
  bodies.angular_velocity_radps[3] = bodies.world_inverse_inertia(3) * bodies.angular_momentum_Nms[3];
  SimulationSettings settings;
  settings.dt_s = dt_fraction * 2.0 / omega_max;
  settings.gravity_mps2 = inelastic ? Vec3(0, 0, -kStandardGravity_mps2) : Vec3::Zero();
  settings.duration_s = 0.2;
  Simulation sim(std::move(bodies), settings);
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs());
  test::add_chain_joints(*js, sim.bodies(), spec, layout_of);
  sim.add_force_provider(std::move(js));
  MaxError obs;
  sim.add_observer(&obs, 1);
  const RunResult r = sim.run();
  EXPECT_EQ(r.status, RunStatus::Completed);
  RunSummary out;
  out.rel_error = obs.max_abs_J / obs.scale_J;
  out.omega_dt = omega_max * settings.dt_s;
  out.plastic_J = obs.last_plastic_J;
  out.viscous_J = obs.last_viscous_J;
  out.yield_events = int(sim.events().count(EventKind::SpringYielded));
  return out;
}

TEST(JointEnergy, ElasticFreeVibrationConservesToSecondOrder) {
  const RunSummary a = run_chain(false, 0.1), b = run_chain(false, 0.05);
  std::printf("elastic: max |balance error| / scale = %.3e at w dt = %.3f, %.3e at w dt = %.3f, ratio %.2f\n",
              a.rel_error, a.omega_dt, b.rel_error, b.omega_dt, a.rel_error / b.rel_error);
  EXPECT_LT(a.rel_error, a.omega_dt * a.omega_dt / 8.0);
  EXPECT_LT(b.rel_error, b.omega_dt * b.omega_dt / 8.0);
  EXPECT_GT(a.rel_error / b.rel_error, 3.0);
  EXPECT_LT(a.rel_error / b.rel_error, 5.0);
  EXPECT_GT(a.rel_error / b.rel_error, 3.0);
  EXPECT_LT(a.rel_error / b.rel_error, 5.0);
  EXPECT_EQ(a.plastic_J, 0.0);
  EXPECT_EQ(a.viscous_J, 0.0);
}

TEST(JointEnergy, DissipativeLedgerBalances) {
  const RunSummary a = run_chain(true, 0.1), b = run_chain(true, 0.05);
  std::printf(
      "inelastic + dashpots: max |balance error| / scale = %.3e at w dt = %.3f, %.3e at w dt = %.3f; "
      "plastic %.3e J, viscous %.3e J, %d yield events\n",
      a.rel_error, a.omega_dt, b.rel_error, b.omega_dt, a.plastic_J, a.viscous_J, a.yield_events);
  EXPECT_LT(b.rel_error, b.omega_dt * b.omega_dt / 8.0);
  EXPECT_GT(a.rel_error / b.rel_error, 3.0);
  EXPECT_LT(a.rel_error / b.rel_error, 5.0);
  EXPECT_GT(a.yield_events, 0);
  EXPECT_GT(a.plastic_J, 0.0);
  EXPECT_GT(a.viscous_J, 0.0);
  EXPECT_LT(a.rel_error, a.omega_dt * a.omega_dt / 8.0);
}

}  // namespace
}  // namespace fq
