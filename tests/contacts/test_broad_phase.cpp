// Broad phase: finds every touching pair (checked against all-pairs narrow
// phase), rebuilds only past the skin, honours the exclusions.
#include <gtest/gtest.h>

#include <random>

#include "contacts/broad_phase.h"
#include "contacts/collide_box_box.h"
#include "pile_scene.h"
#include "scene_helpers.h"

namespace {

using fq::Vec3;

fq::OrientedBox box_of(const fq::BodyStore& b, int i) {
  return {b.position_m[i], b.rotation[i], b.half_extents_m[i]};
}

TEST(BroadPhase, ContainsEveryTouchingPairOnceAndSorted) {
  // Boxes of mixed sizes thrown into a small volume: many touch.
  fq::BodyStore store;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 300; ++i) {
    const Vec3 size(0.02 + 0.3 * (u(rng) + 1.0), 0.02 + 0.05 * (u(rng) + 1.0), 0.02 + 0.02 * (u(rng) + 1.0));
    fq::test::add_box(store, size, 500.0, Vec3(0.6 * u(rng), 0.6 * u(rng), 0.6 * u(rng)),
                      fq::Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized())));
  }
  fq::BroadPhase bp;
  bp.configure(0.01, std::vector<std::uint8_t>(store.size(), 1));
  ASSERT_TRUE(bp.update(store, nullptr));
  const auto& pairs = bp.pairs();
  for (std::size_t k = 1; k < pairs.size(); ++k) {
    const bool ordered = pairs[k - 1].a < pairs[k].a || (pairs[k - 1].a == pairs[k].a && pairs[k - 1].b < pairs[k].b);
    ASSERT_TRUE(ordered) << k;  // sorted and unique
  }
  std::size_t touching = 0;
  fq::ContactManifold m;
  for (int i = 0; i < int(store.size()); ++i) {
    for (int j = i + 1; j < int(store.size()); ++j) {
      if (fq::collide_box_box(box_of(store, i), box_of(store, j), m) == 0) continue;
      ++touching;
      const bool found = std::binary_search(pairs.begin(), pairs.end(), fq::BodyPair{i, j},
                                            [](const fq::BodyPair& p, const fq::BodyPair& q) {
                                              return p.a != q.a ? p.a < q.a : p.b < q.b;
                                            });
      EXPECT_TRUE(found) << i << " " << j;
    }
  }
  EXPECT_GT(touching, 50u);
}

TEST(BroadPhase, RebuildsOnlyPastTheSkin) {
  fq::BodyStore store = fq::test::make_box_pile(50);
  fq::BroadPhase bp;
  const double skin = 0.01;
  bp.configure(skin, std::vector<std::uint8_t>(store.size(), 1));
  bp.update(store, nullptr);
  EXPECT_EQ(bp.rebuild_count(), 1);
  EXPECT_FALSE(bp.update(store, nullptr));  // nothing moved
  store.position_m[7].x() += 0.49 * skin;   // within skin / 2
  EXPECT_FALSE(bp.update(store, nullptr));
  store.position_m[7].x() += 0.02 * skin;   // now past skin / 2
  EXPECT_TRUE(bp.update(store, nullptr));
  EXPECT_EQ(bp.rebuild_count(), 2);
  // A rotation moves the corners by up to half-diagonal x angle.
  const double r = store.half_extents_m[3].norm();
  store.orientation[3] = store.orientation[3] * fq::Quat(Eigen::AngleAxisd(0.6 * skin / r, Vec3::UnitZ()));
  EXPECT_TRUE(bp.update(store, nullptr));
}

TEST(BroadPhase, SkipsBondedFixedAndExcludedPairsAndSeesReleases) {
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, 0));
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.099, 0, 0));          // touches 0
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0.099, 0), fq::Quat::Identity(), true);  // fixed
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0.099, 0.099, 0), fq::Quat::Identity(), true);  // fixed
  fq::test::add_box(store, Vec3::Constant(0.1), 500.0, Vec3(0, 0, -0.099), fq::Quat::Identity(), true,
                    fq::MemberKind::Ground);
  fq::BondedPairs bonded;
  bonded.add(0, 1);
  std::vector<std::uint8_t> participates{1, 1, 1, 1, 0};
  fq::BroadPhase bp;
  bp.configure(0.01, participates);
  bp.update(store, &bonded);
  auto has = [&](int a, int b) {
    for (const auto& p : bp.pairs())
      if (p.a == a && p.b == b) return true;
    return false;
  };
  EXPECT_FALSE(has(0, 1));  // bonded
  EXPECT_TRUE(has(0, 2));
  EXPECT_FALSE(has(2, 3));  // fixed-fixed
  for (const auto& p : bp.pairs()) EXPECT_NE(p.b, 4);  // the ground member takes no part
  bonded.release(0, 1);
  EXPECT_TRUE(bp.update(store, &bonded));  // the release alone forces a rebuild
  EXPECT_TRUE(has(0, 1));
}

}  // namespace
