// The set-up indexes (io/point_grid.h, NameIndex in io/case_def.h) that
// replaced scans making set-up quadratic in the case's size. Expected
// values: the brute-force scans they replaced, on seeded random inputs. The
// locality checks count the points a query looks at instead of timing it, so
// a return to scanning all points fails here on any machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/case_def.h"
#include "io/point_grid.h"

namespace fq {
namespace {

bool in_box(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
}

TEST(PointGrid, CandidatesHoldExactlyTheBruteForcePointsOfRandomBoxes) {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> coord(-3.0, 5.0), size(0.0, 2.5), cell(0.05, 3.0);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Vec3> points(1 + rng() % 400);
    for (Vec3& p : points) p = Vec3(coord(rng), coord(rng), coord(rng));
    // Repeated points and points on a shared plane (a floor of nodes).
    for (std::size_t i = 0; i + 3 < points.size(); i += 7) points[i + 1] = points[i];
    for (std::size_t i = 0; i < points.size(); i += 5) points[i].z() = 1.0;
    const PointGrid grid(points, cell(rng));
    for (int q = 0; q < 50; ++q) {
      const Vec3 lo(coord(rng), coord(rng), coord(rng));
      const Vec3 hi = lo + Vec3(size(rng), size(rng), size(rng));
      std::vector<int> got;
      grid.candidates(lo, hi, got);
      ASSERT_TRUE(std::is_sorted(got.begin(), got.end()));
      ASSERT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end());
      std::vector<int> inside, expected;
      for (const int i : got)
        if (in_box(points[std::size_t(i)], lo, hi)) inside.push_back(i);
      for (std::size_t i = 0; i < points.size(); ++i)
        if (in_box(points[i], lo, hi)) expected.push_back(int(i));
      ASSERT_EQ(inside, expected) << "trial " << trial << " query " << q;
    }
    // A box reaching exactly to a point's coordinates holds it.
    std::vector<int> got;
    grid.candidates(points[0], points[0], got);
    EXPECT_TRUE(std::find(got.begin(), got.end(), 0) != got.end());
  }
}

TEST(PointGrid, QueryLooksOnlyAtPointsNearTheBox) {
  // A 40 x 40 x 10 lattice of 1 m spacing (16 000 points), cells of 1 m: a
  // box of 1 m around one point covers 8 cells, one point each.
  std::vector<Vec3> points;
  for (int x = 0; x < 40; ++x)
    for (int y = 0; y < 40; ++y)
      for (int z = 0; z < 10; ++z) points.emplace_back(x, y, z);
  const PointGrid grid(points, 1.0);
  std::size_t most = 0;
  for (const Vec3& c : {Vec3(20, 20, 5), Vec3(0, 0, 0), Vec3(39, 39, 9), Vec3(7.5, 30.2, 2.9)}) {
    std::vector<int> got;
    std::size_t examined = 0;
    grid.candidates(c - Vec3::Constant(0.5), c + Vec3::Constant(0.5), got, &examined);
    EXPECT_EQ(examined, got.size());
    most = std::max(most, examined);
  }
  EXPECT_LE(most, 27u);
  // A member-like box, 3 m long and 0.2 m across, looks at one line of cells.
  std::vector<int> got;
  std::size_t examined = 0;
  grid.candidates(Vec3(10, 10.9, 4.9), Vec3(13, 11.1, 5.1), got, &examined);
  EXPECT_LE(examined, 4u * 2u * 2u);
}

TEST(PointGrid, NonFinitePointsAreInEveryAnswerAndWideBoxesStayExact) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(nan, 0, 0), Vec3(1e5, -1e5, 3), Vec3(-1e5, 1e5, -3)};
  const PointGrid grid(points, 1e-3);  // 2e5 m across in 1 mm cells: enlarged
  std::vector<int> got;
  grid.candidates(Vec3(-1, -1, -1), Vec3(1, 1, 1), got);
  EXPECT_EQ(got, (std::vector<int>{0, 1}));
  got.clear();
  grid.candidates(Vec3::Constant(-inf), Vec3::Constant(inf), got);
  EXPECT_EQ(got, (std::vector<int>{0, 1, 2, 3}));
  got.clear();
  grid.candidates(Vec3(5, 5, 5), Vec3(4, 4, 4), got);  // an empty box
  EXPECT_EQ(got, (std::vector<int>{1}));
}

TEST(NameIndex, FindsWhatTheScanFindsOnRandomNames) {
  std::mt19937 rng(7);
  std::vector<NodeDef> nodes(300);
  // "n" + std::to_string(...) draws a false -Wstringop-overflow from GCC 12.
  auto name_of = [](unsigned k) { return std::string("n").append(std::to_string(k)); };
  for (NodeDef& n : nodes) n.id = name_of(unsigned(rng() % 200));  // with repeats
  const NameIndex index(nodes, &NodeDef::id);
  for (unsigned k = 0; k < 260; ++k) {
    const std::string name = name_of(k);
    EXPECT_EQ(index.find(name), case_def_detail::find_by_key(nodes, &NodeDef::id, name)) << name;
  }
  EXPECT_EQ(index.find(""), -1);
}

}  // namespace
}  // namespace fq
