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

#include <algorithm>
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
  EXPECT_EQ(p.measured, 0);
}

// A 0.1 m cube thrown at a plate 0.01 m thick (no gravity), the plate free
// or fixed; the records' own pressed depths, as the run passes them.
struct Throw {
  fq::test::ContactScene scene;
  double deepest_m = 0.0;
};
fq::BodyStore cube_and_plate(bool plate_fixed) {
  fq::BodyStore store;
  fq::test::add_box(store, Vec3(0.3, 0.3, 0.01), 500.0, Vec3(0, 0, 0), fq::Quat::Identity(), plate_fixed);
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0.0551));
  return store;
}
Throw throw_cube(bool plate_fixed) {
  Throw t{fq::test::weightless_scene(cube_and_plate(plate_fixed)), 0.0};
  t.scene.sim->bodies().velocity_mps[1] = Vec3(0, 0, -0.2);
  for (int k = 0; k < 3000; ++k) {
    EXPECT_TRUE(t.scene.sim->step());
    for (const auto& c : t.scene.contacts->contacts())
      t.deepest_m = std::max(t.deepest_m, c.depth_m - c.reference_depth_m);
  }
  return t;
}

TEST(ContactPress, AFreePlateIsMeasuredAndAFixedOneIsNotAndACheckpointKeepsThePeak) {
  // A free plate can pivot and come to rest on the press: measured against
  // its 5 mm half-thickness. A fixed one cannot: the cube's 50 mm counts,
  // as on the ground.
  const Throw free_plate = throw_cube(false);
  const fq::ContactPressPeak p = free_plate.scene.contacts->press_peak();
  EXPECT_GT(free_plate.deepest_m, 0.0);
  EXPECT_EQ(p.depth_m, free_plate.deepest_m);  // one pair, one half-thickness: the deepest is the largest
  EXPECT_EQ(p.half_dimension_m, 0.005);
  EXPECT_EQ(p.ratio, p.depth_m / 0.005);
  EXPECT_EQ(p.body_a, 0);
  EXPECT_EQ(p.body_b, 1);
  EXPECT_EQ(p.measured, 0);

  const Throw fixed_plate = throw_cube(true);
  const fq::ContactPressPeak f = fixed_plate.scene.contacts->press_peak();
  EXPECT_EQ(f.depth_m, fixed_plate.deepest_m);
  EXPECT_EQ(f.half_dimension_m, 0.05);
  EXPECT_EQ(f.ratio, f.depth_m / 0.05);
  EXPECT_EQ(f.measured, 1);

  fq::StateWriter out;
  free_plate.scene.sim->save_state(out);
  auto resumed = fq::test::weightless_scene(cube_and_plate(false));
  fq::StateReader in(out.bytes());
  resumed.sim->load_state(in);
  const fq::ContactPressPeak& q = resumed.contacts->press_peak();
  EXPECT_EQ(q.ratio, p.ratio);
  EXPECT_EQ(q.depth_m, p.depth_m);
  EXPECT_EQ(q.half_dimension_m, p.half_dimension_m);
  EXPECT_EQ(q.time_s, p.time_s);
  EXPECT_EQ(q.body_a, p.body_a);
  EXPECT_EQ(q.body_b, p.body_b);
  EXPECT_EQ(q.measured, p.measured);
}

TEST(ContactPress, TheLargestFractionWinsOverTheDeepestPress) {
  // A cube (half-thickness 50 mm) and a slab (10 mm) set down touching the
  // ground on soft springs without dashpots: each peaks at twice its static
  // depth m g / (4 k). The cube's press is the deeper (m = 0.5 against
  // 0.4 kg), the slab's the larger fraction of its section: the slab's is kept.
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0.05));
  fq::test::add_box(store, Vec3(0.2, 0.2, 0.02), 500.0, Vec3(1.0, 0, 0.01));
  fq::SimulationSettings s;
  s.dt_s = 1e-5;
  s.duration_s = 0.1;
  auto scene = fq::test::make_scene(std::move(store), s,
                                    [](fq::ContactSystem& c) { c.set_ground(0.0, fq::test::params(1e3, 1.0, 0.4)); });
  scene.sim->run();
  const fq::ContactPressPeak& p = scene.contacts->press_peak();
  const double g = fq::kStandardGravity_mps2;
  const double slab_m = 2.0 * (500.0 * 0.2 * 0.2 * 0.02) * g / 4e3, cube_m = 2.0 * (500.0 * 1e-3) * g / 4e3;
  ASSERT_GT(cube_m, slab_m);
  EXPECT_EQ(p.measured, 1);
  EXPECT_EQ(p.body_b, 1);
  EXPECT_NEAR(p.depth_m, slab_m, 1e-3 * slab_m);  // (omega dt)^2 below 1e-5
  EXPECT_EQ(p.half_dimension_m, 0.01);
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
  EXPECT_EQ(scene.contacts->press_peak().measured, fq::kNoBody);
}

}  // namespace
