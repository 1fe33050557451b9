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

using fq::test::weightless_scene;

TEST(BondedRelease, PairCollidesTheStepAfterItsJointReleasesIt) {
  // Two boxes overlapping by 1 mm, no gravity, bonded at the start.
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.099, 0, 0));
  // A Ground member overlapping both: ignored (the ground is the half-space).
  fq::test::add_box(store, Vec3(1.0, 1.0, 0.1), 500.0, Vec3(0, 0, -0.099), fq::Quat::Identity(), true,
                    fq::MemberKind::Ground);
  auto scene = weightless_scene(std::move(store));
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

TEST(BondedRelease, APairNeverBondedStartsFromZeroOverlapBesideAReleasedOne) {
  // Only a released pair starts from its overlap (contact_system.h). Here a
  // released pair (2, 3) stays in contact, each of its points holding the
  // 1 mm it was released at as reference depth, while a pair never bonded,
  // (0, 1), comes into contact: its points come first in the contact list
  // (keys in pair order), in the places the released pair's points held
  // two steps before, and must start from a reference depth of zero, i.e.
  // resist their whole overlap: F_n > 0 at the first touch, as for any
  // new contact (the records of a step are reused, contact_system.cpp).
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0), fq::Quat::Identity(), true);
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.1005, 0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 1.0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.099, 1.0, 0));
  auto scene = weightless_scene(std::move(store));
  auto& sim = *scene.sim;
  sim.bonded_pairs().add(2, 3);
  sim.step();
  sim.bonded_pairs().release(2, 3);
  sim.bodies().velocity_mps[1] = Vec3(-0.1, 0, 0);  // 0.5 mm gap: first touch after about 500 steps
  int first_touch_points = 0;
  for (int k = 0; k < 1000 && first_touch_points == 0; ++k) {
    sim.step();
    int released_points = 0;
    for (const auto& c : scene.contacts->contacts()) {
      if (c.body_a == 2) {
        ++released_points;
        EXPECT_NEAR(c.reference_depth_m, 1e-3, 1e-9) << "step " << k;
      } else {
        ASSERT_EQ(c.body_a, 0);
        ++first_touch_points;
        EXPECT_EQ(c.reference_depth_m, 0.0) << "step " << k;
        EXPECT_GT(c.normal_force_N, 0.0) << "step " << k;
      }
    }
    ASSERT_EQ(released_points, 4) << "step " << k;  // the released pair touches throughout
  }
  EXPECT_EQ(first_touch_points, 4);  // a face on a face: four points
}

}  // namespace
