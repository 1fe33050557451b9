// The contact stable-time-step estimate (ContactSystem::stiffest_mode)
// against the limit found by running: a box resting on the ground and a
// box resting on another box on the ground, both preloaded by gravity, with
// elastic contacts (restitution 1: no dashpot) and friction high enough
// that nothing slides, so the contact springs act as linear springs. The
// runs start with small random velocities that excite every mode; a run is
// unstable when its displacement from the start keeps growing (second half
// of the run peaks above twice the first half, or leaves 1e-4 m, far above
// the 1e-7 m the perturbation gives). Central difference is stable for
// omega_max dt <= 2 (closed form of the leapfrog on a linear mode), so the
// bisected limit must lie within 10 % of 2 / omega_max.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "scene_helpers.h"

namespace fq {
namespace {

constexpr double kKn = 1e5;        // normal stiffness per point (N/m)
constexpr double kDensity = 500.0;  // (kg/m^3)
const Vec3 kSize = Vec3::Constant(0.05);  // a cube: every face is its worst face (m)

// Preload: the box sinks until 4 k_n d = m g (and the upper box adds its weight).
BodyStore scene_bodies(int boxes) {
  BodyStore store;
  const double m = box_mass_kg(kSize, kDensity);
  const double g = kStandardGravity_mps2;
  double z = 0.0;
  for (int i = 0; i < boxes; ++i) {
    const double load_below = double(boxes - i) * m * g;  // weight carried by the contact under box i
    z += -load_below / (4.0 * kKn) + 0.5 * kSize.z();
    test::add_box(store, kSize, kDensity, Vec3(0.0, 0.0, z));
    z += 0.5 * kSize.z();
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  store.update_rotations();
  for (std::size_t b = 0; b < store.size(); ++b) {
    store.velocity_mps[b] = 1e-5 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 w = 1e-3 * Vec3(u(rng), u(rng), u(rng));
    store.angular_velocity_radps[b] = w;
    store.angular_momentum_Nms[b] = store.principal_inertia_kgm2[b].asDiagonal() * w;
  }
  return store;
}

// pair_kn: the box-box contact stiffness (the ground's is kKn).
test::ContactScene make(int boxes, double dt_s, int steps, double pair_kn) {
  SimulationSettings s;
  s.dt_s = dt_s;
  s.duration_s = dt_s * steps;
  return test::make_scene(scene_bodies(boxes), s, [pair_kn](ContactSystem& c) {
    c.set_pair_params(0, 0, test::params(pair_kn, 1.0, 10.0));
    c.set_ground(0.0, test::params(kKn, 1.0, 10.0));
  });
}

double growth(int boxes, double dt_s, int steps, double pair_kn) {
  test::ContactScene scene = make(boxes, dt_s, steps, pair_kn);
  const std::vector<Vec3> start = scene.sim->bodies().position_m;
  double first = 0.0, second = 0.0;
  for (int n = 0; n < steps; ++n) {
    if (!scene.sim->step()) return HUGE_VAL;
    double peak = 0.0;
    for (std::size_t b = 0; b < start.size(); ++b)
      peak = std::max(peak, (scene.sim->bodies().position_m[b] - start[b]).norm());
    if (!(peak < 1e-4)) return HUGE_VAL;
    double& half = n < steps / 2 ? first : second;
    half = std::max(half, peak);
  }
  return second / first;
}

void check(int boxes, const char* label, double pair_kn = kKn) {
  test::ContactScene probe = make(boxes, 1e-5, 1, pair_kn);
  const StiffestMode mode = probe.contacts->stiffest_mode(probe.sim->bodies());
  ASSERT_GT(mode.omega_radps, 0.0);
  const double estimate = 2.0 / mode.omega_radps;
  double lo = 0.5 * estimate, hi = 1.5 * estimate;
  const int steps = 3000;
  for (int it = 0; it < 12; ++it) {
    const double mid = 0.5 * (lo + hi);
    (growth(boxes, mid, steps, pair_kn) < 2.0 ? lo : hi) = mid;
  }
  const double bisected = 0.5 * (lo + hi);
  std::cout << "[" << label << "] estimate " << estimate << " s (" << mode.where << "), bisected " << bisected
            << " s, ratio " << bisected / estimate << "\n";
  EXPECT_NEAR(bisected / estimate, 1.0, 0.10) << label;
  EXPECT_NE(mode.where.find("contact"), std::string::npos);
}

TEST(ContactStableStep, BoxOnGround) { check(1, "box on ground"); }
TEST(ContactStableStep, BoxOnBoxOnGround) { check(2, "box on box"); }
// A lone box can only touch the ground: a box-box stiffness ten times the
// ground's, which no pair of this scene can have, must not lower its
// estimate (it did, by sqrt(10), before pairs that cannot occur were left out).
TEST(ContactStableStep, BoxOnGroundIsNotLimitedByAPairStiffnessItCannotHave) {
  check(1, "box on ground, stiffer pair material", 10.0 * kKn);
}

}  // namespace
}  // namespace fq
