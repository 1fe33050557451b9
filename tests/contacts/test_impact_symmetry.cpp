// Box-box impacts whose set-up is mirror-symmetric must have a mirror-
// symmetric outcome (edge-edge and vertex-face). Expected values come from
// symmetry alone.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "box_rotations.h"
#include "scene_helpers.h"

namespace {

using fq::Mat3;
using fq::Quat;
using fq::Vec3;

struct Result {
  Vec3 v, w;
};

// b (free, 0.1 m cube) thrown at a (fixed 0.1 m cube) with velocity v0, no
// gravity; returns b's velocities once the two have parted.
Result throw_at(const Quat& qa, const Vec3& xb, const Quat& qb, const Vec3& v0) {
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3::Zero(), qa, true);
  const auto b = fq::test::add_box(store, Vec3::Constant(0.1), 500.0, xb, qb);
  store.velocity_mps[b] = v0;
  fq::SimulationSettings s;
  s.dt_s = 2e-5;
  s.duration_s = 0.05;
  s.gravity_mps2 = Vec3::Zero();
  auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
    c.set_pair_params(0, 0, fq::test::params(1e5, 0.5, 0.4));
  });
  scene.sim->run();
  EXPECT_EQ(scene.contacts->contact_count(), 0u);  // parted
  return {scene.sim->bodies().velocity_mps[b], scene.sim->bodies().angular_velocity_radps[b]};
}

Quat about(double angle, const Vec3& axis) { return Quat(Eigen::AngleAxisd(angle, axis.normalized())); }

// Reflection x -> -x: positions and velocities map by M, angular velocities
// (pseudovectors) by -M, rotations by M R M.
const Mat3 kMirror = Vec3(-1.0, 1.0, 1.0).asDiagonal();
Quat mirrored(const Quat& q) { return Quat(Mat3(kMirror * q.toRotationMatrix() * kMirror)); }

TEST(ImpactSymmetry, CentredEdgeOnEdgeBouncesStraight) {
  // Ridge of a (along x) under ridge of b (along y), b falling on it: the
  // set-up is symmetric under x -> -x and y -> -y, so b leaves with no
  // horizontal velocity and no spin (to round-off: 1e-9 of the impact speed).
  const double r2 = std::sqrt(2.0) * 0.05;
  const Vec3 v0(0.0, 0.0, -0.2);
  const Result r = throw_at(about(std::numbers::pi / 4, Vec3::UnitX()), Vec3(0, 0, 2 * r2 + 1e-4),
                            about(std::numbers::pi / 4, Vec3::UnitY()), v0);
  EXPECT_GT(r.v.z(), 0.0);  // it bounced
  EXPECT_LT(r.v.head<2>().norm(), 1e-9 * v0.norm());
  EXPECT_LT(r.w.norm() * 0.05, 1e-9 * v0.norm());
}

TEST(ImpactSymmetry, OffCentreEdgeImpactAndItsMirrorImage) {
  // b's ridge strikes a's ridge 20 mm off centre, obliquely; the mirrored
  // set-up must give the mirrored outcome: v' = M v, w' = -M w.
  const double r2 = std::sqrt(2.0) * 0.05;
  const Quat qa = about(std::numbers::pi / 4, Vec3::UnitX());
  const Quat qb = about(0.3, Vec3::UnitZ()) * about(std::numbers::pi / 4, Vec3::UnitY());
  const Vec3 xb(0.02, 0.01, 2 * r2 + 1e-4);
  const Vec3 v0(-0.05, 0.02, -0.2);
  const Result r1 = throw_at(qa, xb, qb, v0);
  const Result r2m = throw_at(mirrored(qa), kMirror * xb, mirrored(qb), kMirror * v0);
  EXPECT_GT(r1.w.norm(), 1e-3);  // the off-centre impact does spin b
  EXPECT_LT((r2m.v - kMirror * r1.v).norm(), 1e-9 * v0.norm());
  EXPECT_LT((r2m.w + kMirror * r1.w).norm() * 0.05, 1e-9 * v0.norm());
}

TEST(ImpactSymmetry, VertexOnFaceBouncesStraightAndMirrors) {
  // b's body diagonal vertical, corner down onto a's top face: the normal
  // force passes through b's centre, so b leaves straight up without spin.
  const Quat corner_down = fq::test::body_diagonal_onto_z();
  const Vec3 v0(0.0, 0.0, -0.2);
  const Result r = throw_at(Quat::Identity(), Vec3(0, 0, 0.05 + std::sqrt(3.0) * 0.05 + 1e-4), corner_down, v0);
  EXPECT_GT(r.v.z(), 0.0);
  EXPECT_LT(r.v.head<2>().norm(), 1e-9 * v0.norm());
  EXPECT_LT(r.w.norm() * 0.05, 1e-9 * v0.norm());
  // Tilted corner, off centre, oblique: mirror image gives the mirrored outcome.
  const Quat q = about(0.2, Vec3(1, 2, 0)) * corner_down;
  const Vec3 xb(0.01, -0.015, 0.05 + std::sqrt(3.0) * 0.05 + 1e-4);
  const Vec3 v1(0.04, 0.03, -0.2);
  const Result a = throw_at(Quat::Identity(), xb, q, v1);
  const Result b = throw_at(Quat::Identity(), kMirror * xb, mirrored(q), kMirror * v1);
  EXPECT_GT(a.w.norm(), 1e-3);
  EXPECT_LT((b.v - kMirror * a.v).norm(), 1e-9 * v1.norm());
  EXPECT_LT((b.w + kMirror * a.w).norm() * 0.05, 1e-9 * v1.norm());
}

}  // namespace

namespace {

// A 0.1 m cube tilted by 10 degrees about y, standing on one edge on a
// fixed plate, falls over and rocks on it without friction; returns the
// cube's velocity after 0.25 s. `cube_first` lists the cube before the
// plate (the pair's box a), else after it. The plate (0.3 m square) is
// wider than the cube rocks: every contact is the cube's corners or edges
// on the plate's top face. (On a plate as wide as the cube, which this
// test used before stop 42, the cube rocks about the plate's own edge; a
// frictionless contact of the plate's edge with the cube's tilted face
// pushes along that face's normal, partly sideways, as the contacts have
// since stop 42: contacts/README.md, "Forces of face points".)
Vec3 rock_without_friction_on_fixed_plate(bool cube_first) {
  fq::BodyStore store;
  const Quat tilt = about(10.0 * std::numbers::pi / 180.0, Vec3::UnitY());
  // Centre height with the lowest edge on the plate's top face (z = 0):
  // half the cube's diagonal in the xz plane times cos(45 deg - 10 deg).
  const double centre_z = 0.05 * std::sqrt(2.0) * std::cos((45.0 - 10.0) * std::numbers::pi / 180.0);
  auto add_cube = [&] { return fq::test::add_box(store, Vec3::Constant(0.1), 450.0, Vec3(0, 0, centre_z), tilt); };
  auto add_plate = [&] {
    fq::test::add_box(store, Vec3(0.3, 0.3, 0.05), 450.0, Vec3(0, 0, -0.025), Quat::Identity(), true);
  };
  fq::BodyId cube;
  if (cube_first) {
    cube = add_cube();
    add_plate();
  } else {
    add_plate();
    cube = add_cube();
  }
  fq::SimulationSettings s;
  s.dt_s = 1e-5;
  s.duration_s = 0.25;
  auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
    c.set_pair_params(0, 0, fq::test::params(1e6, 0.5, 0.0));
  });
  scene.sim->run();
  return scene.sim->bodies().velocity_mps[cube];
}

// Without friction a fixed plate's horizontal top face pushes only
// vertically, so the cube's horizontal momentum stays exactly zero
// (Newton's second law: no horizontal force), whichever body the case lists
// first. With the cube listed first its own face was the contact's
// reference, tilted by the rocking, and it gained 2.5e-4 m/s (contacts
// probe, 2026-11-27); now the fixed body's face is preferred.
TEST(ImpactSymmetry, ARockingCubeOnAFixedPlateGainsNoHorizontalVelocityWhicheverIsListedFirst) {
  for (const bool cube_first : {true, false}) {
    const Vec3 v = rock_without_friction_on_fixed_plate(cube_first);
    EXPECT_EQ(v.x(), 0.0) << (cube_first ? "cube listed first" : "plate listed first");
    EXPECT_EQ(v.y(), 0.0) << (cube_first ? "cube listed first" : "plate listed first");
  }
}

}  // namespace
