// A box dropped on the ground: rest under its weight, and restitution.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "contacts/contact_params.h"
#include "scene_helpers.h"

namespace {

using fq::Vec3;

// 0.1 m cube of 500 kg/m^3 (m = 0.5 kg) on four corner springs of
// k = 1e5 N/m: bounce w = sqrt(4k/m) = 894 rad/s, so dt = 1e-4 s resolves a
// period with 70 steps and stays far below dt_crit (stiffest_mode).
constexpr double kSide = 0.1, kDensity = 500.0, kK = 1e5;

TEST(BoxDrop, ComesToRestCarryingItsWeightWithoutCreep) {
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(kSide), kDensity, Vec3(0.0, 0.0, 0.5 * kSide + 0.005));
  fq::SimulationSettings s;
  s.dt_s = 1e-4;
  s.duration_s = 2.0;
  auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
    c.set_ground(0.0, fq::test::params(kK, 0.5, 0.5));
  });
  auto& sim = *scene.sim;
  EXPECT_LT(s.dt_s, 2.0 / scene.contacts->stiffest_mode(sim.bodies()).omega_radps);
  sim.run();
  const double m = sim.bodies().mass_kg[0];
  const double weight = m * fq::kStandardGravity_mps2;
  // Transients decay as exp(-zeta w t) = exp(-0.255 * 894 * 2) ~ 1e-198 by
  // t = 2 s: what is left is the static state. Closed form: total normal
  // force = m g; each of the 4 corners carries m g / 4, so the overlap is
  // d_s = m g / (4 k) = 1.226e-5 m.
  EXPECT_EQ(scene.contacts->contact_count(), 4u);
  EXPECT_NEAR(scene.contacts->ground_normal_force_N(), weight, 1e-3 * weight);
  const double d_s = weight / (4.0 * kK);
  const Vec3 x_rest = sim.bodies().position_m[0];
  EXPECT_NEAR(0.5 * kSide - x_rest.z(), d_s, 1e-3 * d_s);

  // Eight more seconds: no creep, no jitter. A creep or a residual
  // oscillation of a thousandth of the static overlap (1.2e-8 m) would be
  // caught; the velocity of such an oscillation would be w * 1e-3 d_s.
  double max_speed = 0.0;
  const double w = std::sqrt(4.0 * kK / m);
  for (int k = 0; k < 80000; ++k) {
    sim.step();
    max_speed = std::max(max_speed, sim.bodies().velocity_mps[0].norm());
  }
  EXPECT_LT((sim.bodies().position_m[0] - x_rest).norm(), 1e-3 * d_s);
  EXPECT_LT(max_speed, w * 1e-3 * d_s);
  EXPECT_LT(sim.bodies().angular_velocity_radps[0].norm() * kSide, w * 1e-3 * d_s);
  EXPECT_NEAR(scene.contacts->ground_normal_force_N(), weight, 1e-3 * weight);
}

TEST(BoxDrop, RestitutionOfAFlatDropIsTheRestitutionAskedFor) {
  // No gravity: the box approaches the ground flat at v0 and leaves at v1.
  // The four corner points share the box mass (m/4 each), so the flat
  // impact is one linear spring-dashpot of stiffness 4k and mass m. The
  // compression-only clamp lets the box go when k d + c d' = 0, before the
  // overlap closes, and the contact's damping ratio is the one whose clamped
  // impact rebounds with e (contact_params.h), so v1 / v0 = e: a drop from
  // height h rebounds to e^2 h. (The free spring-dashpot's zeta(e) would
  // give 0.5503 for e = 0.5.)
  // Start: the box touches the ground at t = 0 (overlap 1e-12 m, nothing
  // physically) so the first force evaluation already carries the dashpot
  // force c v0: the leapfrog start then sees the true initial force, and no
  // impact begins between two steps (that would misplace the dashpot's jump
  // by up to one step: impulse error up to 2 zeta w dt / (1 + e)).
  // Tolerance: in Cundall's scheme the dashpot reads the velocity half a
  // step old, v(t - dt/2) ~ v - (dt/2) dv/dt, which with dv/dt ~ -2 zeta w v
  // raises the damping ratio by a factor (1 + zeta w dt): a first-order
  // error (halving dt halves it). Through de/dzeta = -pi e / (1 - zeta^2)^1.5
  // that bounds |de/e| by pi zeta^2 w dt / (1 - zeta^2)^1.5 (0.9 % for
  // e = 0.3 at w dt = 0.018), plus 2 (w dt)^2 for the second-order rest.
  for (double e : {0.3, 0.5, 0.8}) {
    fq::BodyStore store;
    const double v0 = 0.1;
    const auto id = fq::test::add_box(store, Vec3::Constant(kSide), kDensity, Vec3(0.0, 0.0, 0.5 * kSide - 1e-12));
    store.velocity_mps[id] = Vec3(0.0, 0.0, -v0);
    fq::SimulationSettings s;
    s.dt_s = 2e-5;
    s.duration_s = 0.02;
    s.gravity_mps2 = Vec3::Zero();
    auto scene = fq::test::make_scene(std::move(store), s, [e](fq::ContactSystem& c) {
      c.set_ground(0.0, fq::test::params(kK, e, 0.5));
    });
    scene.sim->run();
    ASSERT_EQ(scene.contacts->contact_count(), 0u);
    const double measured = scene.sim->bodies().velocity_mps[0].z() / v0;
    const double zeta = fq::damping_ratio_for_clamped_restitution(e);
    const double w_dt = std::sqrt(4.0 * kK / scene.sim->bodies().mass_kg[0]) * s.dt_s;
    const double lag = std::numbers::pi * zeta * zeta * w_dt / std::pow(1.0 - zeta * zeta, 1.5);
    EXPECT_NEAR(measured, e, (lag + 2.0 * w_dt * w_dt) * e) << "e = " << e;
    std::printf("e = %.2f: rebound %.5f (zeta %.4f, bound %.2e)\n", e, measured, zeta, lag + 2.0 * w_dt * w_dt);
    // The flat drop stays flat and centred (symmetric set-up).
    EXPECT_LT(scene.sim->bodies().angular_velocity_radps[0].norm(), 1e-9);
    EXPECT_LT(scene.sim->bodies().velocity_mps[0].head<2>().norm(), 1e-12);
  }
}

}  // namespace
