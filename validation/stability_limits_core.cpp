#include "stability_limits_core.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <string>

#include "joint_test_util.h"

namespace fq::stability {

// The chain and its joints are the ones tests/joints/test_stable_time_step
// checks the estimate on (joint_test_util.h), started moving.
BodyStore chain_bodies(int links) {
  BodyStore store = test::irregular_chain_bodies(links);
  test::set_small_random_motion(store);
  return store;
}

void add_chain_joints(JointSystem& joints, const BodyStore& bodies) { test::add_irregular_chain_joints(joints, bodies); }

StiffestMode chain_stiffest_mode(int links) {
  const BodyStore store = chain_bodies(links);
  JointSystem probe(nullptr);
  add_chain_joints(probe, store);
  return probe.stiffest_mode(store);
}

StiffestMode damped_chain_stiffest_mode(double damping_ratio) {
  const BodyStore store = chain_bodies(5);
  JointSystem probe(nullptr);
  test::add_irregular_chain_joints(probe, store, damping_ratio);
  return probe.stiffest_mode(store);
}

double damped_chain_amplitude(double damping_ratio, double dt_s, int steps) {
  return test::chain_amplitude(dt_s, steps, damping_ratio);
}

double largest_displacement(Simulation& sim, int steps, double stop_m) {
  return test::largest_displacement(sim, steps, stop_m);
}

void set_small_random_motion(BodyStore& store) { test::set_small_random_motion(store); }

double mechanical_energy_J(const Simulation& sim, const std::vector<const ForceProvider*>& elastic) {
  const BodyStore& b = sim.bodies();
  double energy = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (b.is_fixed[i]) continue;
    energy += 0.5 * b.mass_kg[i] * b.velocity_mps[i].squaredNorm() +
              0.5 * b.angular_momentum_Nms[i].dot(b.angular_velocity_radps[i]);
  }
  EnergyLedger ledger;
  for (const ForceProvider* p : elastic) p->report_energy(ledger);
  return energy + ledger.elastic_J;
}

GrowthRun measure_growth(Simulation& sim, const std::vector<const ForceProvider*>& elastic, int steps,
                         bool stop_when_unstable, double factor) {
  sim.initialize();  // forces (and so the elastic energy) of the start state
  const std::vector<Vec3> start = sim.bodies().position_m;
  const double e0 = mechanical_energy_J(sim, elastic);
  GrowthRun run;
  run.max_energy_ratio = 1.0;
  double peak_first = 0.0, peak_second = 0.0;
  for (int n = 0; n < steps; ++n) {
    const bool finite = sim.step();
    run.steps_run = n + 1;
    double ratio = finite ? mechanical_energy_J(sim, elastic) / e0 : HUGE_VAL;
    if (!std::isfinite(ratio)) ratio = HUGE_VAL;
    run.max_energy_ratio = std::max(run.max_energy_ratio, ratio);
    if (ratio > factor) run.unstable = true;
    if (ratio == HUGE_VAL) return run;  // nothing further to step
    double peak = 0.0;
    for (std::size_t i = 0; i < start.size(); ++i)
      peak = std::max(peak, (sim.bodies().position_m[i] - start[i]).norm());
    run.max_displacement_m = std::max(run.max_displacement_m, peak);
    double& half = n < steps / 2 ? peak_first : peak_second;
    half = std::max(half, peak);
    if (run.unstable && stop_when_unstable) return run;
  }
  run.halves_ratio = peak_second / peak_first;
  return run;
}

GrowthRun chain_growth(Integrator method, double dt_s, int steps, bool stop_when_unstable) {
  SimulationSettings s;
  s.dt_s = dt_s;
  s.duration_s = dt_s * steps;
  s.gravity_mps2 = Vec3::Zero();
  s.integrator = method;
  Simulation sim(chain_bodies(5), s);
  auto joints = std::make_unique<JointSystem>(&sim.bonded_pairs());
  add_chain_joints(*joints, sim.bodies());
  const std::vector<const ForceProvider*> elastic{joints.get()};
  sim.add_force_provider(std::move(joints));
  return measure_growth(sim, elastic, steps, stop_when_unstable);
}

double bisect_stable_dt(Integrator method, double estimate_s, int steps) {
  double lo = 0.5 * estimate_s, hi = 1.5 * estimate_s;
  while (hi - lo > 1e-4 * lo) {
    const double mid = 0.5 * (lo + hi);
    (chain_growth(method, mid, steps).unstable ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

double rk4_amplification(double x) {
  const std::complex<double> z(0.0, x);
  return std::abs(1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0);
}

}  // namespace fq::stability
