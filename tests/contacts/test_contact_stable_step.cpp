// The contact stable-time-step estimate (ContactSystem::stiffest_mode)
// against the limit found by running: a box resting on the ground and a
// box resting on another box on the ground, both preloaded by gravity, with
// elastic contacts (restitution 1: no dashpot) and with damped ones
// (restitution 0.5 and 0.2), and friction high enough that nothing slides,
// so the contact springs and dashpots act as linear ones. The
// runs start with small random velocities that excite every mode; a run is
// unstable when its motion from the start (displacement of the centre plus
// rotation times the half edge) leaves 1e-4 m (1e-5 m with dashpots), far
// above the 1e-8 m the perturbation gives and the 1.5e-6 m by which the
// upper box of the stack sinks (box-box overlaps present at the start are
// taken as the rest state: contact_system.h), or does not die out as it
// should: without dashpots the second half of the run peaks above twice
// the first half; with them the speed of the last quarter does not fall
// below half that of the first (`stable`). A damped stack just past its
// limit moved 35 um and then came to rest on shifted contacts, which the
// speed alone would call stable. Central difference is stable for
// omega_max dt <= 2 (closed form of the leapfrog on a linear mode), and
// with dashpots read at v(n-1/2) up to the dt where lambda_max(dt^2 K~ +
// 2 dt C~) = 4 (dem_core/linearised_network.h), so the bisected limit must
// lie within 10 % of the estimate. Before the contact dashpots entered the
// network (2026-11-26) the estimate divided the undamped limit by the
// nominal sqrt(1 + zeta^2) - zeta, 1.24 times the bisected limit at
// restitution 0.5: a corner's dashpot damps the box's fastest modes more
// than the nominal ratio.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "scene_helpers.h"

namespace fq {
namespace {

constexpr double kKn = 1e5;        // normal stiffness per point (N/m)
constexpr double kDensity = 500.0;  // (kg/m^3)
const Vec3 kSize = Vec3::Constant(0.05);  // a cube: every face is its worst face (m)

// Preload: the box sinks until 4 k_n d = m g (and the upper box adds its
// weight). With `preload_pairs` false a box on a box starts just touching
// it (the lower box still sinks under both): a box-box overlap present at
// the start is the contact's rest state (contact_system.h,
// initial_overlaps), so a preloaded upper box would start unsupported.
BodyStore scene_bodies(int boxes, bool preload_pairs) {
  BodyStore store;
  const double m = box_mass_kg(kSize, kDensity);
  const double g = kStandardGravity_mps2;
  double z = 0.0;
  for (int i = 0; i < boxes; ++i) {
    const double load_below = double(boxes - i) * m * g;  // weight carried by the contact under box i
    z += (i == 0 || preload_pairs ? -load_below / (4.0 * kKn) : 0.0) + 0.5 * kSize.z();
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
test::ContactScene make(int boxes, double dt_s, int steps, double pair_kn, double restitution) {
  SimulationSettings s;
  s.dt_s = dt_s;
  s.duration_s = dt_s * steps;
  return test::make_scene(scene_bodies(boxes, restitution == 1.0), s, [pair_kn, restitution](ContactSystem& c) {
    c.set_pair_params(0, 0, test::params(pair_kn, restitution, 10.0));
    c.set_ground(0.0, test::params(kKn, restitution, 10.0));
  });
}

double growth(int boxes, double dt_s, int steps, double pair_kn, double restitution) {
  test::ContactScene scene = make(boxes, dt_s, steps, pair_kn, restitution);
  const std::vector<Vec3> start = scene.sim->bodies().position_m;
  const std::vector<Quat> start_q = scene.sim->bodies().orientation;
  double first = 0.0, second = 0.0;
  for (int n = 0; n < steps; ++n) {
    if (!scene.sim->step()) return HUGE_VAL;
    // Displacement of the centre plus rotation times the half edge: the
    // damped modes that go unstable first include the twist about the
    // vertical, which does not move the centre.
    double peak = 0.0;
    for (std::size_t b = 0; b < start.size(); ++b)
      peak = std::max(peak, (scene.sim->bodies().position_m[b] - start[b]).norm() +
                                0.5 * kSize.x() * scene.sim->bodies().orientation[b].angularDistance(start_q[b]));
    if (!(peak < 1e-4)) return HUGE_VAL;
    if (restitution < 1.0) {
      if (!(peak < 1e-5)) return HUGE_VAL;
      // Damped: the speed (of the centre plus the spin times the half
      // edge) in the first and the last quarter; the box may settle a few
      // nm from where it started, but it comes to rest.
      if (n >= steps / 4 && n < 3 * steps / 4) continue;
      double speed = 0.0;
      for (std::size_t b = 0; b < start.size(); ++b)
        speed = std::max(speed, scene.sim->bodies().velocity_mps[b].norm() +
                                    0.5 * kSize.x() * scene.sim->bodies().angular_velocity_radps[b].norm());
      double& part = n < steps / 2 ? first : second;
      part = std::max(part, speed);
    } else {
      // Undamped: the motion in the first and the second half.
      double& part = n < steps / 2 ? first : second;
      part = std::max(part, peak);
    }
  }
  return second / first;
}

// Stable: an undamped run's motion does not grow (second half below twice
// the first); a damped run's decays (last quarter below half the first).
// A damped contact past its limit need not grow without bound: its
// dashpot force soon exceeds the preload and the compression-only clamp
// holds it to a chatter of the preload's size (1.5e-6 m here), which never
// settles.
bool stable(int boxes, double dt_s, int steps, double pair_kn, double restitution) {
  const double ratio = growth(boxes, dt_s, steps, pair_kn, restitution);
  return restitution < 1.0 ? ratio < 0.5 : ratio < 2.0;
}

void check(int boxes, const char* label, double pair_kn = kKn, double restitution = 1.0) {
  test::ContactScene probe = make(boxes, 1e-5, 1, pair_kn, restitution);
  const StiffestMode mode = probe.contacts->stiffest_mode(probe.sim->bodies());
  ASSERT_GT(mode.omega_radps, 0.0);
  const double estimate = 2.0 / mode.omega_radps;
  double lo = 0.5 * estimate, hi = 1.5 * estimate;
  const int steps = 3000;
  for (int it = 0; it < 12; ++it) {
    const double mid = 0.5 * (lo + hi);
    (stable(boxes, mid, steps, pair_kn, restitution) ? lo : hi) = mid;
  }
  const double bisected = 0.5 * (lo + hi);
  std::cout << "[" << label << "] estimate " << estimate << " s (" << mode.where << "), bisected " << bisected
            << " s, ratio " << bisected / estimate << "\n";
  EXPECT_NEAR(bisected / estimate, 1.0, 0.10) << label;
  EXPECT_NE(mode.where.find("contact"), std::string::npos);
}

TEST(ContactStableStep, BoxOnGround) { check(1, "box on ground"); }
TEST(ContactStableStep, BoxOnBoxOnGround) { check(2, "box on box"); }
TEST(ContactStableStep, DampedBoxOnGround) {
  check(1, "box on ground, restitution 0.5", kKn, 0.5);
  check(1, "box on ground, restitution 0.2", kKn, 0.2);
}
TEST(ContactStableStep, DampedBoxOnBoxOnGround) { check(2, "box on box, restitution 0.5", kKn, 0.5); }
// A lone box can only touch the ground: a box-box stiffness ten times the
// ground's, which no pair of this scene can have, must not lower its
// estimate (it did, by sqrt(10), before pairs that cannot occur were left out).
TEST(ContactStableStep, BoxOnGroundIsNotLimitedByAPairStiffnessItCannotHave) {
  check(1, "box on ground, stiffer pair material", 10.0 * kKn);
}

// Contacts that may form later use only coefficients their bodies can
// have: two boxes of different materials (0 below, 1 on top) meet through
// their pair's coefficients, and each lands on the ground through the
// ground's; a material with itself needs two bodies of it. So the
// stiffness set for material 0 with itself, which no pair of this scene
// can use, must not move the estimate (it set it, ten times over, when
// the estimate took the stiffest of every coefficient set).
TEST(ContactStableStep, LaterContactsUseOnlyCoefficientsTheirBodiesCanHave) {
  auto estimate = [](double unused_kn) {
    SimulationSettings s;
    s.dt_s = 1e-5;
    s.duration_s = 1e-5;
    test::ContactScene scene = test::make_scene(scene_bodies(2, false), s, [unused_kn](ContactSystem& c) {
      c.set_body_material(0, 0);
      c.set_body_material(1, 1);
      c.set_pair_params(0, 0, test::params(unused_kn, 0.5, 10.0));
      c.set_pair_params(1, 1, test::params(unused_kn, 0.5, 10.0));
      c.set_pair_params(0, 1, test::params(0.1 * kKn, 0.5, 10.0));
      c.set_ground(0.0, test::params(kKn, 0.5, 10.0));
    });
    return std::pair(scene.contacts->stiffest_mode(scene.sim->bodies()),
                     scene.contacts->later_stiffest_mode(scene.sim->bodies()));
  };
  const StiffestMode soft = estimate(0.1 * kKn).first, stiff = estimate(100.0 * kKn).first;
  EXPECT_GT(soft.omega_radps, 0.0);
  EXPECT_EQ(soft.omega_radps, stiff.omega_radps) << soft.where << "\n" << stiff.where;
  // A bound on contacts not yet made says so, and that it takes the box's
  // worst face (a slab lying flat was told "if it lands flat on one" of a
  // bound set by its edge face; stable-step probe).
  const StiffestMode later = estimate(0.1 * kKn).second;
  EXPECT_NE(later.where.find("on its worst face, should it land flat on one: a contact that may form later"),
            std::string::npos)
      << later.where;
}

// The linearised terms of the contacts present now carry each pair's own
// coefficients (linearised_springs solves each pair of materials once and
// reuses it). A box on a box on the ground, the box-box pair 3 times as
// stiff as the ground (normal and tangential, both given): the two
// contacts are face on face over the same 0.05 m square, so their points
// share the same weights, and the summed stiffness of the pair's terms
// must be 3 times that of the ground's. A point's dashpot is 2 zeta
// sqrt(k m), with m its share of the pair's mass (the lower box's m on the
// ground, m / 2 between two equal boxes), so the summed dashpots must stand
// in the ratio (zeta_pair / zeta_ground) sqrt(3 / 2), the damping ratios
// solved from the pair's restitution 0.2 and the ground's 0.5.
TEST(ContactStableStep, EachContactsTermsCarryItsOwnPairsCoefficients) {
  SimulationSettings s;
  s.dt_s = 1e-5;
  s.duration_s = 1e-5;
  test::ContactScene scene = test::make_scene(scene_bodies(2, false), s, [](ContactSystem& c) {
    c.set_pair_params(0, 0, test::params(3.0 * kKn, 0.2, 10.0, 3.0 * 0.8 * kKn));
    c.set_ground(0.0, test::params(kKn, 0.5, 10.0, 0.8 * kKn));
  });
  std::vector<LinearisedSpring> rows;
  scene.contacts->linearised_springs(scene.sim->bodies(), rows);
  double k_ground = 0.0, k_pair = 0.0, c_ground = 0.0, c_pair = 0.0;
  for (const LinearisedSpring& r : rows) {
    (r.a == kNoBody ? k_ground : k_pair) += r.k_Npm;
    (r.a == kNoBody ? c_ground : c_pair) += r.c_Nspm;
  }
  ASSERT_GT(k_ground, 0.0);
  EXPECT_NEAR(k_pair / k_ground, 3.0, 1e-12);
  ASSERT_GT(c_ground, 0.0);
  const double zeta_pair = damping_ratio_for_clamped_restitution(0.2);
  const double zeta_ground = damping_ratio_for_clamped_restitution(0.5);
  EXPECT_NEAR(c_pair / c_ground, zeta_pair / zeta_ground * std::sqrt(1.5), 1e-12);
}

}  // namespace
}  // namespace fq
