// The stable-time-step estimate of the joint network: JointSystem::
// stiffest_mode returns omega_max of the linearised system, and central
// difference is stable for omega_max dt < 2 (closed form: the leapfrog
// amplification matrix of an undamped mode has |r| = 1 iff omega dt <= 2).
// Checked by running a 3D chain of boxes, started with small random
// velocities that excite every mode, just below and just above 2/omega_max.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "dem_core/linearised_network.h"
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
  return test::chain_amplitude(dt_s, steps, damping_ratio);
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

// Two oscillators in one joint system, closed form. Each free cube (0.1 m,
// 450 kg/m^3, m = 0.45 kg) hangs on the fixed base by two normal springs of
// stiffness k and dashpot c at +-30 mm along t1 (their torques cancel in
// the bounce), so its bounce along n has omega = sqrt(2k/m) and damping
// ratio zeta = c / sqrt(2 k m); its rocking about t2 is softer (2 k x^2 /
// I = 0.54 x 2k/m) and less damped. Central difference with a dashpot read
// at v(n-1/2) keeps a mode bounded for dt <= (2/omega)(sqrt(1 + zeta^2) -
// zeta), so the system's limit is the smaller of the two bounces':
//   stiff cube: k = 1e6 N/m, zeta = 0.01 -> omega 2108 rad/s, limit 9.39e-4 s
//   soft cube:  k = 1e5 N/m, zeta = 1.0  -> omega  667 rad/s, limit 1.24e-3 s.
// A bound that pairs the highest frequency with the strongest damping
// (here from different cubes) would give 6.9e-4 s, 26 % low.
double two_oscillators_limit(double dt_s, int steps, StiffestMode* estimate) {
  BodyStore store;
  BoxBodyDef base;
  base.name = "base";
  base.size_m = Vec3::Constant(0.1);
  base.density_kg_per_m3 = 450.0;
  base.fixed = true;
  store.add_box(base);
  BoxBodyDef cube = base;
  cube.fixed = false;
  cube.name = "stiff";
  cube.position_m = Vec3(0, 0, 0.1);
  store.add_box(cube);
  cube.name = "soft";
  cube.position_m = Vec3(1, 0, 0.1);
  store.add_box(cube);
  store.update_rotations();
  // Small initial bounce and rocking velocities: every mode excited.
  store.velocity_mps[1] = Vec3(0, 0, 1e-4);
  store.velocity_mps[2] = Vec3(0, 0, -1e-4);
  const Vec3 w(0, 1e-3, 0);
  for (BodyId b : {1, 2}) {
    store.angular_velocity_radps[b] = w;
    store.angular_momentum_Nms[b] = store.principal_inertia_kgm2[b].asDiagonal() * w;
  }
  const double m = store.mass_kg[1];
  Simulation sim(std::move(store), test::weightless_steps(dt_s, steps));
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs());
  for (BodyId b : {1, 2}) {
    const double k = b == 1 ? 1e6 : 1e5, zeta = b == 1 ? 0.01 : 1.0;
    JointDef d;
    d.body_a = 0;
    d.body_b = b;
    d.origin_m = sim.bodies().position_m[b] - Vec3(0, 0, 0.05);
    SpringPointDef p;
    p.has_shear = false;
    p.normal = linear_spring(k);
    p.normal.dashpot.damping_ratio = 0.0;
    p.normal.dashpot.coefficient_Nspm = zeta * std::sqrt(2.0 * k * m);
    for (double x : {0.03, -0.03}) {
      p.offset_m = Vec3(x, 0, 0);
      d.layout.points.push_back(p);
    }
    js->add_joint(sim.bodies(), d);
  }
  *estimate = js->stiffest_mode(sim.bodies());
  sim.add_force_provider(std::move(js));
  return test::largest_displacement(sim, steps);
}

TEST(StableTimeStep, DampedLimitIsTheSmallestModeLimitNotTheStiffestModeWithTheStrongestDashpot) {
  const double m = 450.0 * 1e-3;
  auto limit = [](double omega, double zeta) { return 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta); };
  const double stiff = limit(std::sqrt(2e6 / m), 0.01), soft = limit(std::sqrt(2e5 / m), 1.0);
  ASSERT_LT(stiff, soft);
  StiffestMode mode;
  two_oscillators_limit(1e-5, 1, &mode);
  const double estimate = 2.0 / mode.omega_radps;
  EXPECT_NE(mode.where.find("'stiff'"), std::string::npos) << mode.where;
  // The eigenvalue search converges from below: the estimate may exceed the
  // closed form by its convergence error, well under 1e-3 for modes this
  // far apart.
  EXPECT_NEAR(estimate / stiff, 1.0, 1e-3) << "estimate " << estimate << " s, closed form " << stiff << " s";
  // And the engine's own runs agree: bounded just below, unbounded just above.
  StiffestMode unused;
  EXPECT_LT(two_oscillators_limit(0.98 * estimate, 4000, &unused), 1e-2);
  EXPECT_GT(two_oscillators_limit(1.02 * estimate, 4000, &unused), 1.0);
}

// One spring k on a free mass m along x: omega = sqrt(k / m), the closed
// form, and dt = 2 / omega. A stiffness whose products overflow (1e308 N/m)
// has no limit that can be computed: NaN, never the "no stiffness" answer
// (omega 0, dt infinite) that let such a case run unchecked.
TEST(StableTimeStep, OneSpringGivesItsClosedFormAndAnOverflowGivesNaNNotNoLimit) {
  BodyStore bodies;
  BoxBodyDef box;
  box.size_m = Vec3(0.1, 0.1, 0.1);
  box.density_kg_per_m3 = 1000.0;  // m = 1 kg
  const BodyId b = bodies.add_box(box);
  auto spring = [&](double k) {
    LinearisedSpring r;
    r.b = b;
    r.k_Npm = k;
    r.gb = mass_scaled_gradient(bodies, b, Vec3::Zero(), Vec3::UnitX());
    return std::vector<LinearisedSpring>{r};
  };
  const NetworkStableStep soft = network_stable_step(spring(1.0e4), bodies.size());
  EXPECT_NEAR(soft.omega_radps, 100.0, 1e-9);
  EXPECT_NEAR(soft.dt_crit_s, 0.02, 1e-13);
  const NetworkStableStep overflow = network_stable_step(spring(1.0e308), bodies.size());
  EXPECT_TRUE(std::isnan(overflow.omega_radps)) << overflow.omega_radps;
  EXPECT_TRUE(std::isnan(overflow.dt_crit_s)) << overflow.dt_crit_s;
}

// Long chains whose top modes crowd together, against their closed form. n
// bodies of m = 1 kg in a row along x, each tied to its neighbours, and the
// two ends to the ground, by springs of stiffness k with dashpots c (a
// fixed-fixed chain): the modes are omega_j^2 = (4 k / m) sin^2(j pi /
// (2 (n + 1))), j = 1..n, so the top two differ by a fraction of about
// (pi / n)^2 / 4 (2.7e-5 at n = 300, 2.7e-7 at n = 3000). The dashpot
// matrix is c/k times the stiffness matrix, so every mode keeps its shape,
// with damping ratio zeta_j = c omega_j / (2 k); the central-difference
// limit of a mode, (2 / omega)(sqrt(1 + zeta^2) - zeta), falls as omega
// grows, so the top mode sets it. An estimate above the true limit lets a
// run start at an unstable step, so it must be close: 300 bodies within
// 1e-6, which the Lanczos search reaches before its cap of 300 products;
// 3000 bodies within 1e-5, where the cap leaves about 3e-6. The power
// iteration it replaced (400 products from a smooth start) stopped 9e-4
// short of omega_max on both chains.
TEST(StableTimeStep, LongChainsWithCrowdedTopModesMeetTheirClosedForm) {
  for (const auto& [chain_bodies, chain_tolerance] : {std::pair{300, 1e-6}, std::pair{3000, 1e-5}}) {
    // Plain copies: a lambda below reads n, and clang 14 (CI's sanitizer
    // build) cannot capture a structured binding.
    const int n = chain_bodies;
    const double tolerance = chain_tolerance;
    SCOPED_TRACE("chain of " + std::to_string(n) + " bodies");
    const double k = 1.0e6, m = 1.0;
    BodyStore bodies;
    BoxBodyDef box;
    box.size_m = Vec3(0.1, 0.1, 0.1);
    box.density_kg_per_m3 = 1000.0;  // m = 1 kg
    for (int i = 0; i < n; ++i) {
      box.position_m = Vec3(0.2 * i, 0.0, 1.0);
      bodies.add_box(box);
    }
    auto chain = [&](double c_Nspm) {
      std::vector<LinearisedSpring> rows;
      for (int i = 0; i <= n; ++i) {  // spring i: body i - 1 (or the ground) to body i (or the ground)
        LinearisedSpring r;
        r.a = i == 0 ? kNoBody : BodyId(i - 1);
        r.b = i == n ? kNoBody : BodyId(i);
        r.k_Npm = k;
        r.c_Nspm = c_Nspm;
        if (r.a != kNoBody) r.ga = -mass_scaled_gradient(bodies, r.a, Vec3::Zero(), Vec3::UnitX());
        if (r.b != kNoBody) r.gb = mass_scaled_gradient(bodies, r.b, Vec3::Zero(), Vec3::UnitX());
        rows.push_back(r);
      }
      return rows;
    };
    const double omega_max = std::sqrt(4.0 * k / m) * std::sin(n * std::numbers::pi / (2.0 * (n + 1)));
    const NetworkStableStep undamped = network_stable_step(chain(0.0), bodies.size());
    EXPECT_NEAR(undamped.omega_radps / omega_max, 1.0, tolerance);
    EXPECT_NEAR(undamped.dt_crit_s * omega_max / 2.0, 1.0, tolerance);

    const double c = 20.0;  // N s/m: zeta of the top mode = c omega_max / (2 k) = 0.02
    const double zeta = c * omega_max / (2.0 * k);
    const double dt_damped = (2.0 / omega_max) * (std::sqrt(1.0 + zeta * zeta) - zeta);
    const NetworkStableStep damped = network_stable_step(chain(c), bodies.size());
    EXPECT_NEAR(damped.dt_crit_s / dt_damped, 1.0, tolerance);
  }
}

}  // namespace
}  // namespace fq
