// A contact point's history (its shear spring and its reference depth)
// belongs to the patch of the faces it stands for, not to the name of the
// feature that made it (contact_system.cpp, process_item). Expected values
// are closed forms of a box pressed on an equal fixed box and moved by
// hand: the forces of the springs the displacements since first touch load.
#include <gtest/gtest.h>

#include <cmath>

#include "scene_helpers.h"

namespace {

using fq::Vec3;

constexpr double kSide = 0.05;   // cube edge (m)
constexpr double kKn = 1e5;      // normal stiffness per point (N/m)
constexpr double kKt = 8e4;      // tangential stiffness per point (N/m)
constexpr double kDt = 1e-5;     // (s)

// A fixed cube at the origin and a free cube of the same size above it at
// `lift` (m) from touching. No gravity, no dashpots (restitution 1).
fq::test::ContactScene stacked_cubes(double lift_m, double mu) {
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(kSide), 500.0, Vec3::Zero(), fq::Quat::Identity(), true);
  fq::test::add_box(store, Vec3::Constant(kSide), 500.0, Vec3(0, 0, kSide + lift_m));
  fq::SimulationSettings s;
  s.dt_s = kDt;
  s.duration_s = 1.0;
  s.gravity_mps2 = Vec3::Zero();
  return fq::test::make_scene(std::move(store), s, [mu](fq::ContactSystem& c) {
    c.set_pair_params(0, 0, fq::test::params(kKn, 1.0, mu, kKt));
  });
}

// Moves the upper cube, unturned, from `from` (where the last step
// evaluated it) to `to` before the next step, with the velocity (to - from) / dt that the
// step's increments read, runs the step and sets `from` to `to`. Returns
// the total force on the upper cube from the pair's points.
Vec3 step_to(fq::test::ContactScene& scene, Vec3& from, const Vec3& to) {
  auto& bodies = scene.sim->bodies();
  bodies.velocity_mps[1] = (to - from) / kDt;
  bodies.position_m[1] = to;
  from = to;
  // No turning: the last step's torques would spin the cube a little.
  bodies.orientation[1] = fq::Quat::Identity();
  bodies.rotation[1] = fq::Mat3::Identity();
  bodies.angular_velocity_radps[1] = Vec3::Zero();
  bodies.angular_momentum_Nms[1] = Vec3::Zero();
  EXPECT_TRUE(scene.sim->step());
  Vec3 total = Vec3::Zero();
  for (const auto& c : scene.contacts->contacts())
    if (c.body_b == 1) total += c.force_N();
  return total;
}

TEST(ContactHistory, ShearSpringsSurviveThePointsBeingRenamedByAnOffsetOfChangingSign) {
  // Equal faces lying on each other name their corner points by the sign
  // of the lateral offset (an incident corner, or where an incident edge
  // crosses a side plane). Pressed in by d, the cube is moved by +delta,
  // -delta, +delta, -delta along x. Four sticking shear springs of k_t
  // each, loaded by the displacement since first touch, give
  // F_x = -4 k_t x; with the history lost at each renaming the springs
  // would hold only the last step's increment, F_x = -4 k_t (x - x_prev),
  // twice as much and of alternating sign.
  auto scene = stacked_cubes(1e-6, 10.0);
  const double d = 1e-6, delta = 1e-7;
  const Vec3 pressed(0, 0, kSide - d);
  Vec3 at = scene.sim->bodies().position_m[1];
  EXPECT_TRUE(scene.sim->step());  // apart: no contact yet
  const Vec3 first = step_to(scene, at, pressed);
  EXPECT_NEAR(first.z(), 4.0 * kKn * d, 1e-9);
  EXPECT_NEAR(first.x(), 0.0, 1e-12);
  for (double sign : {1.0, -1.0, 1.0, -1.0, 1.0}) {
    const Vec3 f = step_to(scene, at, pressed + Vec3(sign * delta, 0, 0));
    EXPECT_NEAR(f.x(), -4.0 * kKt * sign * delta, 1e-6 * kKt * delta) << sign;
    EXPECT_NEAR(f.y(), 0.0, 1e-6 * kKt * delta);
    EXPECT_NEAR(f.z(), 4.0 * kKn * d, 1e-9);
  }
}

TEST(ContactHistory, PointsThatAppearInAPairStartedInOverlapResistFurtherPenetration) {
  // The upper cube starts shifted by +0.3 side along x and overlapping the
  // lower one by d0: the pair starts from its overlap (contact_system.h),
  // no force. Its points: the upper cube's two corners at x = -0.2 side
  // and two crossings on the lower cube's side x = +0.5 side. Then it is
  // moved to -0.3 side and pressed in by e more: the points are now the
  // upper cube's other two corners (x = +0.2 side) and two crossings on
  // the side x = -0.5 side, each at least 0.3 side (15 mm) from every old
  // point, so new points of a pair started in overlap. Each overlaps by
  // d0 + e and may start from no more than the d0 the pair allows, so
  // each pushes with k_n e: 4 k_n e in all. (Taking their own depth as the
  // start, they would push with nothing, and the cube could be pushed in
  // step by step without resistance.)
  const double d0 = 2e-5, e = 1e-5;
  auto scene = stacked_cubes(-d0, 0.0);
  auto& bodies = scene.sim->bodies();
  bodies.position_m[1].x() = 0.3 * kSide;
  const Vec3 start = bodies.position_m[1];
  Vec3 at = start;
  const Vec3 f0 = step_to(scene, at, start);
  EXPECT_EQ(f0.norm(), 0.0);
  const Vec3 f1 = step_to(scene, at, start + Vec3(-0.6 * kSide, 0, -e));
  int points = 0;
  for (const auto& c : scene.contacts->contacts()) points += c.body_b == 1;
  EXPECT_EQ(points, 4);
  EXPECT_NEAR(f1.z(), 4.0 * kKn * e, 1e-9 * kKn * e);
}

}  // namespace
