// The stable-time-step estimate of the joint network: JointSystem::
// stiffest_mode returns omega_max of the linearised system, and central
// difference is stable for omega_max dt < 2 (closed form: the leapfrog
// amplification matrix of an undamped mode has |r| = 1 iff omega dt <= 2).
// Checked by running a 3D chain of boxes, started with small random
// velocities that excite every mode, just below and just above 2/omega_max.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "dem_core/simulation.h"
#include "joints/joint_layout.h"
#include "joints/joint_system.h"

namespace fq {
namespace {

// A vertical chain of `n` boxes of different proportions on a fixed base,
// joined by four-corner linear joints (normal and shear).
BodyStore chain_bodies(int n) {
  BodyStore store;
  BoxBodyDef base;
  base.name = "base";
  base.size_m = Vec3(0.05, 0.05, 0.02);
  base.density_kg_per_m3 = 500;
  base.position_m = Vec3(0, 0, -0.01);
  base.fixed = true;
  store.add_box(base);
  double z = 0.0;
  for (int i = 0; i < n; ++i) {
    BoxBodyDef b;
    b.name = "link_" + std::to_string(i);
    const double h = 0.1 + 0.02 * i;
    b.size_m = Vec3(0.02 + 0.002 * i, 0.03, h);
    b.density_kg_per_m3 = 500;
    b.position_m = Vec3(0, 0, z + 0.5 * h);
    z += h;
    store.add_box(b);
  }
  store.update_rotations();
  return store;
}

void add_chain_joints(JointSystem& js, const BodyStore& store, double damping_ratio = 0.0) {
  double z = 0.0;
  for (BodyId b = 1; b < BodyId(store.size()); ++b) {
    JointDef d;
    d.body_a = b - 1;
    d.body_b = b;
    d.origin_m = Vec3(0, 0, z);
    d.layout = four_corner_layout(0.01, 0.015, 1.0, linear_spring(2e4 * double(b), damping_ratio),
                                  linear_spring(5e4, damping_ratio));
    js.add_joint(store, d);
    z += 2.0 * store.half_extents_m[b].z();
  }
}

// Largest |displacement| from rest reached over `steps` steps at dt.
double run_amplitude(double dt_s, int steps, double damping_ratio = 0.0) {
  BodyStore store = chain_bodies(5);
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (BodyId b = 1; b < BodyId(store.size()); ++b) {
    store.velocity_mps[b] = 1e-4 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 w = 1e-3 * Vec3(u(rng), u(rng), u(rng));
    const Mat3& r = store.rotation[b];
    store.angular_velocity_radps[b] = w;
    store.angular_momentum_Nms[b] = r * store.principal_inertia_kgm2[b].asDiagonal() * (r.transpose() * w);
  }
  const std::vector<Vec3> rest = store.position_m;
  SimulationSettings settings;
  settings.dt_s = dt_s;
  settings.duration_s = dt_s * steps;
  settings.gravity_mps2 = Vec3::Zero();
  Simulation sim(std::move(store), settings);
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs());
  add_chain_joints(*js, sim.bodies(), damping_ratio);
  sim.add_force_provider(std::move(js));
  double amplitude = 0.0;
  for (int s = 0; s < steps; ++s) {
    if (!sim.step()) return INFINITY;
    for (std::size_t b = 1; b < sim.bodies().size(); ++b)
      amplitude = std::max(amplitude, (sim.bodies().position_m[b] - rest[b]).norm());
    if (amplitude > 1.0) return amplitude;
  }
  return amplitude;
}

TEST(StableTimeStep, EstimateMatchesTheObservedStabilityLimit) {
  BodyStore store = chain_bodies(5);
  JointSystem probe(nullptr);
  add_chain_joints(probe, store);
  const StiffestMode mode = probe.stiffest_mode(store);
  ASSERT_GT(mode.omega_radps, 0.0);
  EXPECT_NE(mode.where.find("joint"), std::string::npos);
  const double dt_crit = 2.0 / mode.omega_radps;

  // Below the limit the motion stays at the size the initial velocities give
  // (|v| / omega_min ~ 1e-4 m); 3 % above it the top mode grows by a factor
  // |r| = 1 + 2 sqrt(0.03) + ... ~ 1.4 per step and leaves any bound.
  const int steps = 4000;
  const double below = run_amplitude(0.97 * dt_crit, steps);
  const double above = run_amplitude(1.03 * dt_crit, steps);
  EXPECT_LT(below, 1e-2) << "dt = 0.97 dt_crit must be stable";
  EXPECT_GT(above, 1.0) << "dt = 1.03 dt_crit must be unstable (estimate too low)";
}

// Dashpots lower the stable step: a spring-level damping ratio of 0.5 makes
// the light rotational modes of the chain overdamped, and central
// difference with a dashpot reading v(n-1/2) is stable only for
// dt <= (2/omega)(sqrt(1 + zeta^2) - zeta). The estimate includes this; the
// run at 0.97 of it must stay bounded, and the undamped limit 2/omega must
// be refused by the estimate (it is unstable with these dashpots).
TEST(StableTimeStep, DashpotsLowerTheEstimateAndItStaysStable) {
  BodyStore store = chain_bodies(5);
  JointSystem undamped(nullptr), damped(nullptr);
  add_chain_joints(undamped, store, 0.0);
  add_chain_joints(damped, store, 0.5);
  const double dt_undamped = 2.0 / undamped.stiffest_mode(store).omega_radps;
  const double dt_damped = 2.0 / damped.stiffest_mode(store).omega_radps;
  EXPECT_LT(dt_damped, dt_undamped);
  EXPECT_LT(run_amplitude(0.97 * dt_damped, 4000, 0.5), 1e-2);
  EXPECT_GT(run_amplitude(0.97 * dt_undamped, 4000, 0.5), 1.0)
      << "with these dashpots the undamped limit is unstable, so the damped estimate must be lower";
}

}  // namespace
}  // namespace fq
