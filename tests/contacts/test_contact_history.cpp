// A contact point's history (its shear spring and its reference depth)
// belongs to the patch of the faces it stands for, not to the name of the
// feature that made it (contact_system.cpp, process_item). Expected values
// are closed forms of a box pressed on an equal fixed box and moved by
// hand: the forces of the springs the displacements since first touch load.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "scene_helpers.h"

namespace {

using fq::Vec3;

constexpr double kSide = 0.05;   // cube edge (m)
constexpr double kKn = 1e5;      // normal stiffness per point (N/m)
constexpr double kKt = 8e4;      // tangential stiffness per point (N/m)
constexpr double kDt = 1e-5;     // (s)

// A fixed box and a free box (store bodies 0 and 1) pressed together by
// hand. No gravity, no dashpots (restitution 1), friction mu.
fq::test::ContactScene pressed_pair(fq::BodyStore store, double mu) {
  fq::SimulationSettings s;
  s.dt_s = kDt;
  s.duration_s = 1.0;
  s.gravity_mps2 = Vec3::Zero();
  return fq::test::make_scene(std::move(store), s, [mu](fq::ContactSystem& c) {
    c.set_pair_params(0, 0, fq::test::params(kKn, 1.0, mu, kKt));
  });
}

// A fixed cube at the origin and a free cube of the same size above it at
// `lift` (m) from touching, turned by `turn` about its centre.
fq::test::ContactScene stacked_cubes(double lift_m, double mu, const fq::Quat& turn = fq::Quat::Identity()) {
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(kSide), 500.0, Vec3::Zero(), fq::Quat::Identity(), true);
  fq::test::add_box(store, Vec3::Constant(kSide), 500.0, Vec3(0, 0, kSide + lift_m), turn);
  return pressed_pair(std::move(store), mu);
}

// Moves the upper box, held at orientation `turn`, from `from` (where the
// last step evaluated it) to `to` before the next step, with the velocity
// (to - from) / dt that the step's increments read, runs the step and sets
// `from` to `to`. Returns the total force on the upper box from the pair's
// points.
Vec3 step_to(fq::test::ContactScene& scene, Vec3& from, const Vec3& to, const fq::Quat& turn = fq::Quat::Identity()) {
  auto& bodies = scene.sim->bodies();
  bodies.velocity_mps[1] = (to - from) / kDt;
  bodies.position_m[1] = to;
  from = to;
  // No turning: the last step's torques would spin the box a little.
  bodies.orientation[1] = turn;
  bodies.rotation[1] = turn.toRotationMatrix();
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

TEST(ContactHistory, CornersKeepTheirShearSpringsWhileCrossingsRaceAlongTheEdges) {
  // The upper cube is twisted by theta = 1e-8 rad about the vertical: its
  // sides cross the lower cube's sides near their middles, at x = y / theta
  // along an edge for a lateral offset y, so an offset of 1e-10 m moves a
  // crossing by 10 mm. Moved back and forth in y by up to 3e-10 m, the
  // crossings race past the corners, points appear and vanish and the
  // corners are renamed. Every point that stands for a corner (weight near
  // 1; a crossing's weight is about theta / (pi / 2)) has been there since
  // first touch, so its shear spring holds k_t w times the whole offset:
  // F_y = -k_t w y (closed form of a sticking spring under a rigid shift).
  // (Taking records in the order of the points' features, a crossing 1 mm
  // from a renamed corner took its record, and the corner started empty.)
  const double d = 1e-6, theta = 1e-8;
  const fq::Quat twist(Eigen::AngleAxisd(theta, Vec3::UnitZ()));
  auto scene = stacked_cubes(1e-6, 10.0, twist);
  Vec3 at = scene.sim->bodies().position_m[1];
  EXPECT_TRUE(scene.sim->step());  // apart
  const Vec3 pressed(0, 0, kSide - d);
  int corner_checks = 0;
  const double offsets[] = {0.0, 1e-10, -1e-10, 2e-10, -2e-10, 3e-10, -3e-10, -2.4e-10, 3e-10, 2.4e-10, -2.6e-10, 1e-10, 0.0};
  for (double y : offsets) {
    step_to(scene, at, pressed + Vec3(0, y, 0), twist);
    for (const auto& c : scene.contacts->contacts()) {
      if (c.body_b != 1 || c.stiffness_scale < 0.5) continue;
      ++corner_checks;
      EXPECT_NEAR(c.tangential_force_N.y(), -kKt * c.stiffness_scale * y, 1e-3 * kKt * 3e-10)
          << "offset " << y << " point at " << c.position_m.transpose() << " weight " << c.stiffness_scale;
    }
  }
  EXPECT_GE(corner_checks, 4 * 13);
}

TEST(ContactHistory, ACornerSplitByASidePlaneHandsItsSpringOnAtTheNewShare) {
  // A small cube (side 20 mm, turned 20 deg about the vertical) pressed on
  // a large fixed box and pushed along +x in steps of 50 um until one of
  // its bottom corners crosses the large box's side x = 50 mm. The corner
  // (weight 1, a right angle) becomes two points on that side sharing its
  // turn, 20 deg and 70 deg. The one nearer the corner's last position
  // stands for the same patch and keeps its spring's displacement, the
  // whole push since first touch: F_x = -k_t w (x - x_0) with its new
  // share w (not the corner's force: that would load a spring of share w
  // as if it had share 1). The other is new: F_x = -k_t w (x - x_prev).
  const double d = 1e-4, half = 0.01, step = 5e-5;  // pressed in by d: friction cap 10 k_n d w, far above the springs
  fq::BodyStore store;
  fq::test::add_box(store, Vec3(0.1, 0.1, 0.1), 500.0, Vec3::Zero(), fq::Quat::Identity(), true);
  const fq::Quat turn(Eigen::AngleAxisd(20.0 * std::numbers::pi / 180.0, Vec3::UnitZ()));
  const Vec3 reach_x = turn * Vec3(half, -half, 0.0);  // the corner furthest along +x
  // Start with that corner 0.12 mm inside the side: the split comes at the third push.
  const Vec3 first(0.05 - reach_x.x() - 1.2e-4, 0.0, 0.05 + half + 1e-6);
  fq::test::add_box(store, Vec3::Constant(2 * half), 500.0, first, turn);
  auto scene = pressed_pair(std::move(store), 10.0);
  Vec3 at = scene.sim->bodies().position_m[1];
  EXPECT_TRUE(scene.sim->step());  // apart
  const Vec3 x0 = first - Vec3(0, 0, 1e-6 + d);
  std::vector<fq::ContactPoint> before;
  bool split_seen = false;
  for (int k = 0; k < 5 && !split_seen; ++k) {
    step_to(scene, at, x0 + Vec3(k * step, 0, 0), turn);
    std::vector<fq::ContactPoint> now;
    for (const auto& c : scene.contacts->contacts())
      if (c.body_b == 1) now.push_back(c);
    if (now.size() == 5 && before.size() == 4) {
      split_seen = true;
      // The corner that split: the record of the step before at the largest x.
      const fq::ContactPoint* corner = &before[0];
      for (const auto& c : before)
        if (c.position_m.x() > corner->position_m.x()) corner = &c;
      std::vector<const fq::ContactPoint*> fresh;
      for (const auto& c : now) {
        bool known = false;
        for (const auto& b : before) known = known || b.feature == c.feature;
        if (!known) fresh.push_back(&c);
        else EXPECT_NEAR(c.tangential_force_N.x(), -kKt * c.stiffness_scale * k * step, 1e-9 * kKt * step);
      }
      ASSERT_EQ(fresh.size(), 2u);
      const double d0 = (fresh[0]->position_m - corner->position_m).norm();
      const double d1 = (fresh[1]->position_m - corner->position_m).norm();
      const fq::ContactPoint& near = d0 <= d1 ? *fresh[0] : *fresh[1];
      const fq::ContactPoint& far = d0 <= d1 ? *fresh[1] : *fresh[0];
      EXPECT_NEAR(near.stiffness_scale + far.stiffness_scale, 1.0, 1e-9);
      EXPECT_LT(near.stiffness_scale, 0.9);  // a real split: the share changed
      EXPECT_NEAR(near.tangential_force_N.x(), -kKt * near.stiffness_scale * k * step, 1e-9 * kKt * step);
      EXPECT_NEAR(far.tangential_force_N.x(), -kKt * far.stiffness_scale * step, 1e-9 * kKt * step);
    }
    before = std::move(now);
  }
  EXPECT_TRUE(split_seen);
}

}  // namespace
