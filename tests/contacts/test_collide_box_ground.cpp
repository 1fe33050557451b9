// Box-ground narrow phase; expected values are the corner geometry by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "box_rotations.h"
#include "contacts/collide_box_ground.h"

namespace {

using fq::ContactManifold;
using fq::OrientedBox;
using fq::Vec3;

TEST(CollideBoxGround, FlatBoxGivesExactlyFourPoints) {
  // Bottom face at z = -0.001 below the ground 0: its 4 corners, depth 1 mm.
  OrientedBox box{Vec3(0.2, 0.1, 0.049), fq::Mat3::Identity(), Vec3(0.1, 0.2, 0.05)};
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_ground(box, 0.0, m), 4);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(m.points[k].depth_m, 0.001, 1e-15);
    EXPECT_EQ(m.points[k].normal, Vec3::UnitZ());
    EXPECT_NEAR(m.points[k].position_m.z(), -0.0005, 1e-15);
    EXPECT_NEAR(std::fabs(m.points[k].position_m.x() - 0.2), 0.1, 1e-15);
    EXPECT_NEAR(std::fabs(m.points[k].position_m.y() - 0.1), 0.2, 1e-15);
    EXPECT_EQ(m.points[k].feature & 4u, 0u);  // bottom corners (z sign -)
  }
  EXPECT_NEAR(fq::box_lowest_z_m(box), -0.001, 1e-15);
}

TEST(CollideBoxGround, CornerAndEdgeAndSunkenBox) {
  ContactManifold m;
  // Body diagonal vertical: one corner, sqrt(3) h below the centre.
  const fq::Mat3 r = fq::test::body_diagonal_onto_z().toRotationMatrix();
  OrientedBox corner{Vec3(0, 0, std::sqrt(3.0) * 0.5 - 0.002), r, Vec3::Constant(0.5)};
  ASSERT_EQ(fq::collide_box_ground(corner, 0.0, m), 1);
  EXPECT_NEAR(m.points[0].depth_m, 0.002, 1e-12);
  // Turned 45 deg about x: the lowest edge has 2 corners, sqrt(2) h below.
  OrientedBox edge{Vec3(0, 0, std::sqrt(2.0) * 0.5 - 0.002),
                   Eigen::AngleAxisd(std::numbers::pi / 4, Vec3::UnitX()).toRotationMatrix(), Vec3::Constant(0.5)};
  ASSERT_EQ(fq::collide_box_ground(edge, 0.0, m), 2);
  // Entirely below the plane: all 8 corners.
  OrientedBox sunk{Vec3(0, 0, -1), fq::Mat3::Identity(), Vec3::Constant(0.5)};
  ASSERT_EQ(fq::collide_box_ground(sunk, 0.0, m), 8);
  // Above: none.
  OrientedBox above{Vec3(0, 0, 0.5001), fq::Mat3::Identity(), Vec3::Constant(0.5)};
  EXPECT_EQ(fq::collide_box_ground(above, 0.0, m), 0);
}

}  // namespace
