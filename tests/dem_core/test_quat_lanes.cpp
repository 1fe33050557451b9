// The quaternion operations in lanes (dem_core/quat_lanes.h) against the
// Eigen calls they stand for, bit for bit, on random quaternions: unit and
// not unit, either hemisphere, with the special values a step can meet
// (zero, negative zero, identity). The joints' frames and the rotation
// drift rely on this equality to give the scalar code's results.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "dem_core/quat_lanes.h"

namespace fq {
namespace {

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

TEST(QuatLanes, EveryOperationIsBitwiseEigens) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random_quat = [&](int kind) {
    Quat q(u(rng), u(rng), u(rng), u(rng));
    if (kind == 0) q.normalize();
    if (kind == 1) q.coeffs() *= 1e-3;
    if (kind == 2) q = Quat::Identity();
    if (kind == 3) q = Quat(-0.0, 0.0, -0.0, 0.0);
    return q;
  };
  int checked = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Quat a[4], b[4];
    const Quat *pa[4], *pb[4];
    for (int k = 0; k < 4; ++k) {
      a[k] = random_quat(trial % 50 == 0 ? 2 + k % 2 : k % 2);
      b[k] = random_quat(trial % 37 == 0 ? 3 : 0);
      pa[k] = &a[k];
      pb[k] = &b[k];
    }
    const lanes::QuatLanes la = lanes::load_quats(pa, 4), lb = lanes::load_quats(pb, 4);
    const lanes::QuatLanes prod = lanes::product(la, lb);
    const lanes::v4d dots = lanes::dot(la, lb);
    const lanes::QuatLanes unit = lanes::normalized(la);
    lanes::v4d m[9];
    lanes::to_rotation_matrix(la, m);
    for (int k = 0; k < 4; ++k) {
      const Quat p = a[k] * b[k];
      EXPECT_TRUE(same(prod.x[k], p.x()) && same(prod.y[k], p.y()) && same(prod.z[k], p.z()) && same(prod.w[k], p.w()))
          << "product, trial " << trial;
      EXPECT_TRUE(same(dots[k], a[k].dot(b[k]))) << "dot, trial " << trial;
      Quat n = a[k];
      n.normalize();
      EXPECT_TRUE(same(unit.x[k], n.x()) && same(unit.y[k], n.y()) && same(unit.z[k], n.z()) && same(unit.w[k], n.w()))
          << "normalize, trial " << trial;
      const Mat3 r = a[k].toRotationMatrix();
      for (int i = 0; i < 9; ++i) EXPECT_TRUE(same(m[i][k], r.data()[i])) << "matrix entry " << i << ", trial " << trial;
      ++checked;
    }
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_EQ(checked, 80000);
}

TEST(QuatLanes, UnusedLanesHoldTheIdentity) {
  const Quat q(0.5, 0.5, 0.5, 0.5);
  const Quat* p[4] = {&q, nullptr, nullptr, nullptr};
  const lanes::QuatLanes l = lanes::load_quats(p, 1);
  EXPECT_EQ(l.w[0], 0.5);
  for (int k = 1; k < 4; ++k) {
    EXPECT_EQ(l.w[k], 1.0);
    EXPECT_EQ(l.x[k], 0.0);
  }
}

}  // namespace
}  // namespace fq
