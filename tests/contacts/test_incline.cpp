// Block on an incline, made by tilting gravity over a level ground: sticks
// when tan(theta) < mu, slides with a = g (sin theta - mu cos theta)
// otherwise (Coulomb's law for a rigid block, the closed form).
#include <gtest/gtest.h>

#include <cmath>

#include "scene_helpers.h"

namespace {

using fq::Vec3;

// 0.1 m cube, 0.5 kg, corner springs k_n = 1e5 N/m, k_t = 0.82 k_n, mu = 0.5.
constexpr double kSide = 0.1, kDensity = 500.0, kK = 1e5, kMu = 0.5;

struct InclineRun {
  std::unique_ptr<fq::Simulation> sim;
  fq::ContactSystem* contacts;
};

InclineRun make_incline(double tan_theta) {
  const double theta = std::atan(tan_theta);
  const double g = fq::kStandardGravity_mps2;
  fq::BodyStore store;
  const double m = kSide * kSide * kSide * kDensity;
  // Start at the static normal overlap m g cos(theta) / (4 k): no drop.
  const double d = m * g * std::cos(theta) / (4.0 * kK);
  fq::test::add_box(store, Vec3::Constant(kSide), kDensity, Vec3(0.0, 0.0, 0.5 * kSide - d));
  fq::SimulationSettings s;
  s.dt_s = 1e-4;
  s.duration_s = 10.0;
  s.gravity_mps2 = Vec3(g * std::sin(theta), 0.0, -g * std::cos(theta));
  auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
    c.set_ground(0.0, fq::test::params(kK, 0.5, kMu));
  });
  return {std::move(scene.sim), scene.contacts};
}

TEST(Incline, SticksBelowTheFrictionAngle) {
  // tan(theta) = 0.3 < mu = 0.5: the block must stop and stay. Gravity is
  // applied suddenly, so the springs overshoot once; during that first
  // swing the rear corners, unloaded by the friction moment (rear pair
  // carries m g cos(theta) (1 - tan(theta)) / 2 at rest), may slip locally
  // even though the block as a whole is within the friction cone. Rigid
  // Coulomb theory allows no slip at all; the point model may slip only
  // during that transient, by no more than the first overshoot of the
  // elastic shear, (1 + e) u_s.
  auto run = make_incline(0.3);
  const double theta = std::atan(0.3);
  const double m = run.sim->bodies().mass_kg[0];
  const double x0 = run.sim->bodies().position_m[0].x();
  for (int k = 0; k < 10000; ++k) run.sim->step();
  const double x1 = run.sim->bodies().position_m[0].x();
  bool slid_late = false;
  for (int k = 0; k < 10000; ++k) {
    run.sim->step();
    for (const auto& c : run.contacts->contacts()) slid_late = slid_late || c.sliding;
  }
  // After the start-up swing (decay exp(-zeta w t) ~ 1e-80 at t = 1 s):
  // no point slides, the block does not move and is at rest.
  EXPECT_FALSE(slid_late);
  EXPECT_LT(std::fabs(run.sim->bodies().position_m[0].x() - x1), 1e-12);
  EXPECT_LT(run.sim->bodies().velocity_mps[0].norm(), 1e-9);
  // Elastic shear of 4 corner springs in parallel carrying m g sin(theta):
  // u_s = m g sin(theta) / (4 k_t); the friction moment tilts the block,
  // moving the centre by a further fraction of u_s: 2 u_s bounds the elastic
  // part, (1 + e) u_s the transient slip.
  const double kt = fq::kTangentialToNormalStiffness * kK;
  const double u_s = m * fq::kStandardGravity_mps2 * std::sin(theta) / (4.0 * kt);
  const double moved = run.sim->bodies().position_m[0].x() - x0;
  EXPECT_GT(moved, 0.0);
  EXPECT_LT(moved, (2.0 + 1.5) * u_s);
}

TEST(Incline, SlidesWithTheCoulombAcceleration) {
  // tan(theta) = 0.7 > mu: a = g (sin theta - mu cos theta) = 1.607 m/s^2.
  // Measured from the velocity gain between t = 0.5 s (start-up transients
  // decayed: exp(-zeta w 0.5) ~ 1e-40) and t = 1.5 s, within 1 %.
  auto run = make_incline(0.7);
  const double theta = std::atan(0.7);
  const double expected = fq::kStandardGravity_mps2 * (std::sin(theta) - kMu * std::cos(theta));
  for (int k = 0; k < 5000; ++k) run.sim->step();
  const double v1 = run.sim->bodies().velocity_mps[0].x();
  for (int k = 0; k < 10000; ++k) run.sim->step();
  const double v2 = run.sim->bodies().velocity_mps[0].x();
  EXPECT_NEAR((v2 - v1) / 1.0, expected, 0.01 * expected);
  for (const auto& c : run.contacts->contacts()) EXPECT_TRUE(c.sliding);
  // Friction work shows in the ledger: mu m g cos(theta) times the slid distance.
  EXPECT_GT(run.contacts->dissipated_friction_J(), 0.0);
}

}  // namespace
