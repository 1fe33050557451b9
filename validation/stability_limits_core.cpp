#include "stability_limits_core.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <random>
#include <string>

#include "joints/joint_layout.h"

namespace fq::stability {

BodyStore chain_bodies(int links) {
  BodyStore store;
  BoxBodyDef base;
  base.name = "base";
  base.size_m = Vec3(0.05, 0.05, 0.02);
  base.density_kg_per_m3 = 500;
  base.position_m = Vec3(0, 0, -0.01);
  base.fixed = true;
  store.add_box(base);
  double z = 0.0;
  for (int i = 0; i < links; ++i) {
    BoxBodyDef b;
    b.name = "link_" + std::to_string(i);
    const double h = 0.1 + 0.02 * i;
    b.size_m = Vec3(0.02 + 0.002 * i, 0.03, h);
    b.density_kg_per_m3 = 500;
    b.position_m = Vec3(0, 0, z + 0.5 * h);
    z += h;
    store.add_box(b);
  }
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  store.update_rotations();
  for (BodyId b = 1; b < BodyId(store.size()); ++b) {
    store.velocity_mps[b] = 1e-4 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 w = 1e-3 * Vec3(u(rng), u(rng), u(rng));
    const Mat3& r = store.rotation[b];
    store.angular_velocity_radps[b] = w;
    store.angular_momentum_Nms[b] = r * store.principal_inertia_kgm2[b].asDiagonal() * (r.transpose() * w);
  }
  return store;
}

void add_chain_joints(JointSystem& joints, const BodyStore& bodies) {
  double z = 0.0;
  for (BodyId b = 1; b < BodyId(bodies.size()); ++b) {
    JointDef d;
    d.body_a = b - 1;
    d.body_b = b;
    d.origin_m = Vec3(0, 0, z);
    d.layout = four_corner_layout(0.01, 0.015, 1.0, linear_spring(2e4 * double(b), 0.0), linear_spring(5e4, 0.0));
    joints.add_joint(bodies, d);
    z += 2.0 * bodies.half_extents_m[b].z();
  }
}

StiffestMode chain_stiffest_mode(int links) {
  const BodyStore store = chain_bodies(links);
  JointSystem probe(nullptr);
  add_chain_joints(probe, store);
  return probe.stiffest_mode(store);
}

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
