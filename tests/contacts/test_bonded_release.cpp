// Pairs held by an intact joint do not collide; after BondedPairs::release
// the pair is in contact at the very next force evaluation, starting from the
// overlap the joint held it at (contact_system.h: a released pair's overlap
// is the reference depth, so the break creates no energy) and resisting any
// further penetration in full. The ground member (MemberKind::Ground) never
// collides as a box.
#include <gtest/gtest.h>

#include "scene_helpers.h"

namespace {

using fq::Vec3;

TEST(BondedRelease, PairCollidesTheStepAfterItsJointReleasesIt) {
  // Two boxes overlapping by 1 mm, no gravity, bonded at the start.
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.099, 0, 0));
  // A Ground member overlapping both: ignored (the ground is the half-space).
  fq::test::add_box(store, Vec3(1.0, 1.0, 0.1), 500.0, Vec3(0, 0, -0.099), fq::Quat::Identity(), true,
                    fq::MemberKind::Ground);
  fq::SimulationSettings s;
  s.dt_s = 1e-5;
  s.gravity_mps2 = Vec3::Zero();
  auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
    c.set_pair_params(0, 0, fq::test::params(1e5, 0.5, 0.4));
  });
  auto& sim = *scene.sim;
  sim.bonded_pairs().add(0, 1);
  for (int k = 0; k < 10; ++k) sim.step();
  EXPECT_EQ(scene.contacts->contact_count(), 0u);
  EXPECT_EQ(sim.bodies().velocity_mps[0], Vec3::Zero());
  // A joint breaking releases the pair in its finish_step; here by hand
  // between two steps, which is the same point of the step loop.
  sim.bonded_pairs().release(0, 1);
  sim.step();
  ASSERT_GT(scene.contacts->contact_count(), 0u);
  for (const auto& c : scene.contacts->contacts()) {
    EXPECT_EQ(c.body_a, 0);
    EXPECT_EQ(c.body_b, 1);
    EXPECT_NEAR(c.normal.x(), 1.0, 1e-12);  // face contact along x, from 0 to 1
    EXPECT_NEAR(c.depth_m, 1e-3, 1e-12);
    EXPECT_EQ(c.reference_depth_m, c.depth_m);  // the held overlap is the reference
    EXPECT_EQ(c.normal_force_N, 0.0);
  }
  EXPECT_EQ(sim.bodies().velocity_mps[0], Vec3::Zero());  // not thrown apart
  EXPECT_EQ(sim.bodies().velocity_mps[1], Vec3::Zero());
  // Pressing further in is resisted: body 1 moving towards body 0 pushes it.
  sim.bodies().velocity_mps[1] = Vec3(-0.01, 0, 0);
  for (int k = 0; k < 20; ++k) sim.step();
  EXPECT_LT(sim.bodies().velocity_mps[0].x(), 0.0);
  EXPECT_GT(scene.contacts->contacts()[0].normal_force_N, 0.0);
}

}  // namespace
