// Broad phase: finds every touching pair (checked against all-pairs narrow
// phase), rebuilds only past the skin, honours the exclusions; the threaded
// rebuild of large scenes gives exactly the all-pairs box-overlap list on 1
// and 2 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

#if defined(_OPENMP)
#include <omp.h>
#endif

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

// The rebuild on threads (every pass of it forced on: parallel_min_bodies
// = 1), on 1 and 2 threads, against an independent all-pairs reference: the
// candidate pairs are by definition (broad_phase.h) every pair whose boxes,
// enlarged by half the skin, overlap, minus fixed-fixed, bonded and
// non-participating pairs, sorted by (a, b). 5000 boxes of mixed sizes give
// some 2e4 grid entries: more than one block of the radix sort and five
// chunks of the pair search, so the joins between blocks and chunks are
// exercised.
TEST(BroadPhase, ThreadedRebuildGivesTheAllPairsListOnOneAndTwoThreads) {
  fq::BodyStore store;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 5000;
  for (int i = 0; i < n; ++i) {
    const Vec3 size(0.02 + 0.15 * (u(rng) + 1.0), 0.02 + 0.04 * (u(rng) + 1.0), 0.02 + 0.02 * (u(rng) + 1.0));
    fq::test::add_box(store, size, 500.0, Vec3(1.5 * u(rng), 1.5 * u(rng), 0.8 * u(rng)),
                      fq::Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized())),
                      i % 7 == 0);  // every 7th box fixed
  }
  std::vector<std::uint8_t> participates;
  for (int i = 0; i < n; ++i) participates.push_back(i == 10 ? 0 : 1);  // body 10 takes no part
  fq::BondedPairs bonded;
  const double skin = 0.02;

  // Reference: all pairs, O(n^2). The boxes' bounds are kept as plain
  // doubles: the 12.5 million pair tests in Eigen expressions took 15 s
  // in the sanitizer build, whose test code is compiled at -O0 (nothing
  // inlined), against 0.1 s in the plain build.
  std::vector<std::array<double, 3>> lo(store.size()), hi(store.size());
  for (std::size_t i = 0; i < store.size(); ++i) {
    const Vec3 e = store.rotation[i].cwiseAbs() * store.half_extents_m[i] + Vec3::Constant(0.5 * skin);
    for (int d = 0; d < 3; ++d) {
      lo[i][std::size_t(d)] = store.position_m[i][d] - e[d];
      hi[i][std::size_t(d)] = store.position_m[i][d] + e[d];
    }
  }
  std::vector<fq::BodyPair> expected;
  for (std::size_t i = 0; i < std::size_t(n); ++i) {
    for (std::size_t j = i + 1; j < std::size_t(n); ++j) {
      if (!participates[i] || !participates[j]) continue;
      if (store.is_fixed[i] && store.is_fixed[j]) continue;
      bool apart = false;  // separated along some axis: max of the lows above min of the highs
      for (std::size_t d = 0; d < 3; ++d)
        apart = apart || std::max(lo[i][d], lo[j][d]) > std::min(hi[i][d], hi[j][d]);
      if (apart) continue;
      expected.push_back({fq::BodyId(i), fq::BodyId(j)});
    }
  }
  // Hold a few overlapping pairs by "joints".
  for (std::size_t k = 0; k < expected.size(); k += 97) bonded.add(expected[k].a, expected[k].b);
  std::erase_if(expected, [&](const fq::BodyPair& p) { return bonded.bonded(p.a, p.b); });
  ASSERT_GT(expected.size(), 5000u);

  auto run = [&](int threads, std::int64_t parallel_min_bodies, double& cell_m) {
#if defined(_OPENMP)
    omp_set_num_threads(threads);
#else
    (void)threads;
#endif
    fq::BroadPhase bp;
    bp.configure(skin, participates);
    bp.set_parallel_min_bodies(parallel_min_bodies);
    EXPECT_TRUE(bp.update(store, &bonded));
    cell_m = bp.cell_size_m();
    return bp.pairs();
  };
  double cell_serial = 0.0, cell_one = 0.0, cell_two = 0.0;
  const auto serial = run(1, std::int64_t(1) << 40, cell_serial);
  const auto one = run(1, 1, cell_one);
  const auto two = run(2, 1, cell_two);
  auto same = [](const std::vector<fq::BodyPair>& p, const std::vector<fq::BodyPair>& q) {
    return p.size() == q.size() && std::equal(p.begin(), p.end(), q.begin(), [](const auto& x, const auto& y) {
             return x.a == y.a && x.b == y.b;
           });
  };
  EXPECT_TRUE(same(serial, expected)) << serial.size() << " pairs against " << expected.size();
  EXPECT_TRUE(same(one, expected)) << one.size() << " pairs against " << expected.size();
  EXPECT_TRUE(same(two, expected)) << two.size() << " pairs against " << expected.size();
  EXPECT_EQ(cell_one, cell_serial);  // the cell size is summed in body order on any path
  EXPECT_EQ(cell_two, cell_serial);
}

}  // namespace
