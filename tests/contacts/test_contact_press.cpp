// The deepest press of the contact springs (ContactSystem::press_peak,
// contact_system.h "ContactPressPeak"), which the run warns about past 5 %
// of the thinner box's half-thickness (io/case_runner.h).
//
// Expected values from the closed form of a box on linear springs: a box
// released at rest exactly touching the ground, without dashpots
// (restitution 1), oscillates between 0 and twice its static depth
// m g / (4 k) on its four corner springs, reaching 2 m g / (4 k) at
// t = pi / omega, omega = sqrt(4 k / m).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dem_core/state_io.h"
#include "scene_helpers.h"

namespace {

using fq::Vec3;

// A slab 0.2 x 0.1 x 0.04 m lying flat: its smallest half-dimension is 0.02 m.
constexpr double kHalfThickness_m = 0.02;
const Vec3 kSlab(0.2, 0.1, 2.0 * kHalfThickness_m);
constexpr double kK = 1e4;  // N/m per corner

fq::test::ContactScene slab_on_ground(double duration_s, double dt_s) {
  fq::BodyStore store;
  fq::test::add_box(store, kSlab, 500.0, Vec3(0.0, 0.0, kHalfThickness_m));  // touching
  fq::SimulationSettings s;
  s.dt_s = dt_s;
  s.duration_s = duration_s;
  return fq::test::make_scene(std::move(store), s,
                              [](fq::ContactSystem& c) { c.set_ground(0.0, fq::test::params(kK, 1.0, 0.4)); });
}

TEST(ContactPress, ASlabReleasedTouchingTheGroundPeaksAtTwiceItsStaticDepth) {
  const double m = 500.0 * kSlab.prod();  // 0.4 kg
  const double omega = std::sqrt(4.0 * kK / m);
  const double dt = 2.0 * std::numbers::pi / omega / 400.0;  // 400 steps a period
  auto scene = slab_on_ground(2.0 * std::numbers::pi / omega, dt);  // one period
  auto& sim = *scene.sim;
  EXPECT_EQ(scene.contacts->press_peak().ratio, 0.0);
  sim.run();
  const fq::ContactPressPeak& p = scene.contacts->press_peak();
  const double expected_m = 2.0 * m * fq::kStandardGravity_mps2 / (4.0 * kK);  // 0.49 mm
  // Central difference resolves the bounce to (omega dt)^2 = 2.5e-4.
  EXPECT_NEAR(p.depth_m, expected_m, 1e-3 * expected_m);
  EXPECT_EQ(p.half_dimension_m, kHalfThickness_m);
  EXPECT_EQ(p.ratio, p.depth_m / kHalfThickness_m);
  EXPECT_NEAR(p.time_s, std::numbers::pi / omega, 2.0 * dt);
  EXPECT_EQ(p.body_a, fq::kNoBody);  // the ground
  EXPECT_EQ(p.body_b, 0);
}

TEST(ContactPress, APairTakesTheThinnerBoxAndACheckpointKeepsThePeak) {
  // A 0.1 m cube thrown at a plate 0.01 m thick (no gravity): the press is
  // measured against the plate's half-thickness, 5 mm, and named by the pair.
  fq::BodyStore store;
  fq::test::add_box(store, Vec3(0.3, 0.3, 0.01), 500.0, Vec3(0, 0, 0), fq::Quat::Identity(), true);
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0.0551));
  auto scene = fq::test::weightless_scene(std::move(store));
  auto& sim = *scene.sim;
  sim.bodies().velocity_mps[1] = Vec3(0, 0, -0.2);
  double deepest_m = 0.0;  // the records' own depths, as the run passes them
  for (int k = 0; k < 3000; ++k) {
    ASSERT_TRUE(sim.step());
    for (const auto& c : scene.contacts->contacts()) deepest_m = std::max(deepest_m, c.depth_m - c.reference_depth_m);
  }
  const fq::ContactPressPeak p = scene.contacts->press_peak();
  EXPECT_GT(deepest_m, 0.0);
  EXPECT_EQ(p.depth_m, deepest_m);
  EXPECT_EQ(p.half_dimension_m, 0.005);
  EXPECT_EQ(p.ratio, p.depth_m / 0.005);
  EXPECT_EQ(p.body_a, 0);
  EXPECT_EQ(p.body_b, 1);

  fq::StateWriter out;
  sim.save_state(out);
  fq::BodyStore again;
  fq::test::add_box(again, Vec3(0.3, 0.3, 0.01), 500.0, Vec3(0, 0, 0), fq::Quat::Identity(), true);
  fq::test::add_box(again, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0.0551));
  auto resumed = fq::test::weightless_scene(std::move(again));
  fq::StateReader in(out.bytes());
  resumed.sim->load_state(in);
  const fq::ContactPressPeak& q = resumed.contacts->press_peak();
  EXPECT_EQ(q.ratio, p.ratio);
  EXPECT_EQ(q.depth_m, p.depth_m);
  EXPECT_EQ(q.half_dimension_m, p.half_dimension_m);
  EXPECT_EQ(q.time_s, p.time_s);
  EXPECT_EQ(q.body_a, p.body_a);
  EXPECT_EQ(q.body_b, p.body_b);
}

TEST(ContactPress, AnOverlapAtTheStartIsNoPress) {
  // Two cubes whose centres are 0.099 m apart overlap by 1 mm from the
  // start; their contacts take it as their rest state (contact_system.h),
  // push with nothing, and press nothing: the peak stays 0.
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.099, 0, 0));
  auto scene = fq::test::weightless_scene(std::move(store));
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(scene.sim->step());
  ASSERT_GT(scene.contacts->contact_count(), 0u);
  EXPECT_EQ(scene.contacts->press_peak().ratio, 0.0);
  EXPECT_EQ(scene.contacts->press_peak().body_b, fq::kNoBody);
}

}  // namespace
