// A stack of ten boxes stands for 10 s: settles to the static closed form
// and does not drift.
#include <gtest/gtest.h>

#include <cmath>

#include "scene_helpers.h"

namespace {

using fq::Vec3;

TEST(BoxStack, TenBoxesSettleToTheStaticSolutionAndStand) {
  // 0.1 m cubes, 0.5 kg each, touching at t = 0; 4 corner springs of
  // k = 1e5 N/m per face contact (box-box and box-ground alike).
  constexpr int kCount = 10;
  constexpr double kSide = 0.1, kDensity = 500.0, kK = 1e5;
  fq::BodyStore store;
  for (int i = 0; i < kCount; ++i)
    fq::test::add_box(store, Vec3::Constant(kSide), kDensity, Vec3(0.0, 0.0, 0.5 * kSide + i * kSide));
  fq::SimulationSettings s;
  s.dt_s = 1e-4;
  s.duration_s = 5.0;
  auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
    c.set_ground(0.0, fq::test::params(kK, 0.5, 0.5));
    c.set_pair_params(0, 0, fq::test::params(kK, 0.5, 0.5));
  });
  auto& sim = *scene.sim;
  // dt well inside the stable range of the stiffest-mode estimate.
  EXPECT_LT(s.dt_s, 0.5 * 2.0 / scene.contacts->stiffest_mode(sim.bodies()).omega_radps);
  sim.run();

  // Closed form: the contact under box i carries the weight of the
  // (kCount - i) boxes above it on 4 points, overlap (kCount - i) m g / (4 k);
  // box i sinks by the sum of the overlaps below it. The slowest mode of the
  // chain (w1 ~ sqrt(4k/m) pi / (2 kCount) ~ 140 rad/s) has decayed by
  // exp(-zeta w1 5 s) ~ 1e-40 at t = 5 s. Tolerance: 1e-3 of one overlap.
  const double m = sim.bodies().mass_kg[0];
  const double d1 = m * fq::kStandardGravity_mps2 / (4.0 * kK);
  double sunk = 0.0;
  std::vector<Vec3> settled(kCount);
  for (int i = 0; i < kCount; ++i) {
    sunk += (kCount - i) * d1;
    const Vec3& x = sim.bodies().position_m[i];
    EXPECT_NEAR(x.z(), 0.5 * kSide + i * kSide - sunk, 1e-3 * d1) << "box " << i;
    settled[i] = x;
  }
  EXPECT_EQ(scene.contacts->contact_count(), std::size_t(4 * kCount));

  // Five more seconds: nothing moves (by more than 1e-3 of one overlap, a
  // creep of 2.5e-9 m/s would show), nothing tilts.
  for (int k = 0; k < 50000; ++k) sim.step();
  for (int i = 0; i < kCount; ++i) {
    EXPECT_LT((sim.bodies().position_m[i] - settled[i]).norm(), 1e-3 * d1) << "box " << i;
    EXPECT_LT(sim.bodies().velocity_mps[i].norm(), 1e-9) << "box " << i;
    EXPECT_NEAR(sim.bodies().rotation[i](2, 2), 1.0, 1e-12) << "box " << i;
  }
}

}  // namespace
