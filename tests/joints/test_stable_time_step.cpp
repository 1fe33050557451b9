// The stable-time-step estimate of the joint network: JointSystem::
// stiffest_mode returns omega_max of the linearised system, and central
// difference is stable for omega_max dt < 2 (closed form: the leapfrog
// amplification matrix of an undamped mode has |r| = 1 iff omega dt <= 2).
// Checked by running a 3D chain of boxes, started with small random
// velocities that excite every mode, just below and just above 2/omega_max.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "dem_core/simulation.h"
#include "joint_test_util.h"
#include "joints/joint_layout.h"
#include "joints/joint_system.h"

namespace fq {
namespace {

using test::add_irregular_chain_joints;
using test::irregular_chain_bodies;

// Largest |displacement| from rest reached over `steps` steps at dt.
double run_amplitude(double dt_s, int steps, double damping_ratio = 0.0) {
  BodyStore store = irregular_chain_bodies(5);
  test::set_small_random_motion(store);
  const std::vector<Vec3> rest = store.position_m;
  SimulationSettings settings;
  settings.dt_s = dt_s;
  settings.duration_s = dt_s * steps;
  settings.gravity_mps2 = Vec3::Zero();
  Simulation sim(std::move(store), settings);
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs());
  add_irregular_chain_joints(*js, sim.bodies(), damping_ratio);
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
  BodyStore store = irregular_chain_bodies(5);
  JointSystem probe(nullptr);
  add_irregular_chain_joints(probe, store);
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
  BodyStore store = irregular_chain_bodies(5);
  JointSystem undamped(nullptr), damped(nullptr);
  add_irregular_chain_joints(undamped, store, 0.0);
  add_irregular_chain_joints(damped, store, 0.5);
  const double dt_undamped = 2.0 / undamped.stiffest_mode(store).omega_radps;
  const double dt_damped = 2.0 / damped.stiffest_mode(store).omega_radps;
  EXPECT_LT(dt_damped, dt_undamped);
  EXPECT_LT(run_amplitude(0.97 * dt_damped, 4000, 0.5), 1e-2);
  EXPECT_GT(run_amplitude(0.97 * dt_undamped, 4000, 0.5), 1.0)
      << "with these dashpots the undamped limit is unstable, so the damped estimate must be lower";
}

}  // namespace
}  // namespace fq
