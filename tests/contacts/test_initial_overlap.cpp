// Bodies that overlap at the start without a joint holding them start from
// their overlap (contact_system.h, "Pairs that overlap at the start"), as
// pairs released by a joint do: no force at the overlap they start with, so
// no energy that no load put in, and full resistance to any further
// penetration. Expected values from the geometry: two 0.1 m cubes whose
// centres are 0.099 m apart along x overlap by exactly 1 mm.
#include <gtest/gtest.h>

#include "dem_core/state_io.h"
#include "scene_helpers.h"

namespace {

using fq::Vec3;

using fq::test::weightless_scene;

// Pair (0, 1) overlapping by 1 mm, pair (2, 3) face to face exactly, box 4 alone.
fq::BodyStore overlapping_and_touching_boxes() {
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.099, 0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 1.0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.1, 1.0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 3.0, 0));
  return store;
}

TEST(InitialOverlap, PairOverlappingAtTheStartIsListedAndNotThrownApart) {
  auto scene = weightless_scene(overlapping_and_touching_boxes());
  auto& sim = *scene.sim;
  EXPECT_TRUE(scene.contacts->initial_overlaps().empty());  // before step 0's forces
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(sim.step());
  // Listed once, with the geometry's 1 mm; the exactly touching pair is not.
  const auto& overlaps = scene.contacts->initial_overlaps();
  ASSERT_EQ(overlaps.size(), 1u);
  EXPECT_EQ(overlaps[0].body_a, 0);
  EXPECT_EQ(overlaps[0].body_b, 1);
  EXPECT_NEAR(overlaps[0].depth_m, 1e-3, 1e-12);
  // Without the soft start the 1 mm would push the boxes apart with
  // k d^2 / 2 = 0.05 J per point; here nothing moves.
  for (std::size_t b = 0; b < 5; ++b) EXPECT_EQ(sim.bodies().velocity_mps[b], Vec3::Zero()) << b;
  for (const auto& c : scene.contacts->contacts()) {
    EXPECT_EQ(c.reference_depth_m, c.depth_m);
    EXPECT_EQ(c.normal_force_N, 0.0);
  }
  EXPECT_EQ(sim.ledger().initial_stored_J, 0.0);
  // Pressing further in is resisted: body 1 moving into body 0 pushes it.
  sim.bodies().velocity_mps[1] = Vec3(-0.01, 0, 0);
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(sim.step());
  EXPECT_LT(sim.bodies().velocity_mps[0].x(), 0.0);
}

TEST(InitialOverlap, OnlyStepZeroCountsAndACheckpointKeepsTheList) {
  // Boxes that come to overlap later are ordinary contacts: (0, 1) start
  // 1 mm apart and are pushed into each other.
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.101, 0, 0), fq::Quat::Identity(), false);
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 1.0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.098, 1.0, 0));  // 2 mm at the start
  auto scene = weightless_scene(std::move(store));
  auto& sim = *scene.sim;
  sim.bodies().velocity_mps[1] = Vec3(-0.5, 0, 0);
  bool pressed = false;
  for (int k = 0; k < 600; ++k) {
    ASSERT_TRUE(sim.step());
    for (const auto& c : scene.contacts->contacts())
      if (c.body_a == 0) {
        EXPECT_EQ(c.reference_depth_m, 0.0);  // a new touch resists its whole overlap
        pressed = pressed || c.normal_force_N > 0.0;
      }
  }
  EXPECT_TRUE(pressed);
  ASSERT_EQ(scene.contacts->initial_overlaps().size(), 1u);
  EXPECT_EQ(scene.contacts->initial_overlaps()[0].body_a, 2);
  EXPECT_NEAR(scene.contacts->initial_overlaps()[0].depth_m, 2e-3, 1e-12);

  // A simulation resumed from a checkpoint has the same list and does not
  // look for overlaps again at its first step.
  fq::StateWriter out;
  sim.save_state(out);
  // (Built with body 3 clear of body 2: the list must come from the
  // checkpoint, not from the resumed scene's own first evaluation.)
  fq::BodyStore clear(sim.bodies());
  clear.position_m[3] = Vec3(0.5, 1.0, 0);
  auto resumed = weightless_scene(std::move(clear));
  fq::StateReader in(out.bytes());
  resumed.sim->load_state(in);
  ASSERT_EQ(resumed.contacts->initial_overlaps().size(), 1u);
  EXPECT_EQ(resumed.contacts->initial_overlaps()[0].body_b, 3);
  EXPECT_EQ(resumed.contacts->initial_overlaps()[0].depth_m, scene.contacts->initial_overlaps()[0].depth_m);
  ASSERT_TRUE(resumed.sim->step());
  ASSERT_TRUE(sim.step());
  EXPECT_EQ(resumed.sim->state_hash(), sim.state_hash());
}

}  // namespace
