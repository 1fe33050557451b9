// Bitwise identical final state with 1 and 2 OpenMP threads (STYLE.md 3.6):
// 200 boxes pressed together in columns, pushing each other about for 100
// steps (short, because OpenMP barriers are slow on an oversubscribed CI
// machine; every box is in contact from the first step), every parallel loop
// of the contact system forced on (parallel_threshold = 1), the broad
// phase's too (broad_phase_parallel_bodies = 1).
#include <gtest/gtest.h>

#include <cstring>

#include "pile_scene.h"
#include "scene_helpers.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace {

struct Final {
  std::vector<fq::Vec3> x, v, l;
  std::vector<fq::Quat> q;
  std::size_t contacts = 0;
  std::int64_t rebuilds = 0;
};

// scene 0: pressed columns (200 boxes, 100 steps); 1: falling pile (400
// boxes, 500 steps), whose touching pairs cluster among the lowest bodies,
// so the narrow phase's per-thread runs of chunks are cut at uneven counts
// (split by cost).
Final run_pile(int threads, int scene_kind = 0) {
#if defined(_OPENMP)
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  fq::SimulationSettings s;
  s.dt_s = 1e-4;  // w dt = 0.45 with k = 1e5 on 0.12 kg: stable, accuracy not at stake here
  s.duration_s = scene_kind == 0 ? 0.01 : 0.05;
  fq::ContactSystemSettings cs;
  cs.parallel_threshold = 1;
  cs.broad_phase_parallel_bodies = 1;
  auto scene = fq::test::make_scene(
      scene_kind == 0 ? fq::test::make_pressed_columns(200) : fq::test::make_box_pile(400), s,
      [](fq::ContactSystem& c) {
        c.set_ground(0.0, fq::test::params(1e5, 0.5, 0.4));
        c.set_pair_params(0, 0, fq::test::params(1e5, 0.5, 0.4));
      },
      {}, cs);
  scene.sim->run();
  const auto& b = scene.sim->bodies();
  return {b.position_m, b.velocity_mps, b.angular_momentum_Nms, b.orientation, scene.contacts->contact_count(),
          scene.contacts->broad_phase_rebuilds()};
}

bool same_bits(const double* a, const double* b, std::size_t n) { return std::memcmp(a, b, n * sizeof(double)) == 0; }

// The same contacts, rebuilds and, body by body, the same bits of every
// position, velocity, angular momentum and orientation.
void expect_same_final_state(const Final& one, const Final& two) {
  EXPECT_EQ(one.contacts, two.contacts);
  EXPECT_EQ(one.rebuilds, two.rebuilds);
  for (std::size_t i = 0; i < one.x.size(); ++i) {
    EXPECT_TRUE(same_bits(one.x[i].data(), two.x[i].data(), 3)) << "position of body " << i;
    EXPECT_TRUE(same_bits(one.v[i].data(), two.v[i].data(), 3)) << "velocity of body " << i;
    EXPECT_TRUE(same_bits(one.l[i].data(), two.l[i].data(), 3)) << "angular momentum of body " << i;
    EXPECT_TRUE(same_bits(one.q[i].coeffs().data(), two.q[i].coeffs().data(), 4)) << "orientation of body " << i;
  }
}

TEST(ContactDeterminism, OneAndTwoThreadsGiveTheSameBits) {
#if !defined(_OPENMP)
  GTEST_SKIP() << "built without OpenMP";
#endif
  const Final one = run_pile(1);
  const Final two = run_pile(2);
  ASSERT_GT(one.contacts, 400u);  // the boxes really are in contact
  expect_same_final_state(one, two);
}

TEST(ContactDeterminism, FallingPileOnOneAndTwoThreadsGivesTheSameBits) {
#if !defined(_OPENMP)
  GTEST_SKIP() << "built without OpenMP";
#endif
  const Final one = run_pile(1, 1);
  const Final two = run_pile(2, 1);
  // Not free flight only: boxes have landed and touch (at 0.05 s the
  // lowest layer is still bouncing and tumbling, so no count is asserted).
  ASSERT_GT(one.contacts, 0u);
  expect_same_final_state(one, two);
}

}  // namespace
