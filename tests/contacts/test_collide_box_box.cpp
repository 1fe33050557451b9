// Box-box narrow phase. Expected values are geometry worked out by hand for
// each configuration (stated next to each case), not program output.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "box_rotations.h"
#include "contacts/collide_box_box.h"

namespace {

using fq::ContactManifold;
using fq::Mat3;
using fq::OrientedBox;
using fq::Vec3;

OrientedBox cube(const Vec3& c, const Mat3& r = Mat3::Identity(), double half = 0.5) {
  return {c, r, Vec3::Constant(half)};
}

Mat3 rot(double angle, const Vec3& axis) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

constexpr double kTol = 1e-12;

TEST(CollideBoxBox, FaceFaceGivesFourCornerPoints) {
  // Unit cubes, b resting on a with overlap 0.01: the incident face (b's
  // bottom) coincides laterally with a's top face -> its 4 corners, depth
  // 0.01, normal +z, each point midway (z = 0.495).
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0, 0, 0.99)), m), 4);
  for (int k = 0; k < m.count; ++k) {
    EXPECT_NEAR(m.points[k].depth_m, 0.01, kTol);
    EXPECT_NEAR((m.points[k].normal - Vec3::UnitZ()).norm(), 0.0, kTol);
    EXPECT_NEAR(std::fabs(m.points[k].position_m.x()), 0.5, kTol);
    EXPECT_NEAR(std::fabs(m.points[k].position_m.y()), 0.5, kTol);
    EXPECT_NEAR(m.points[k].position_m.z(), 0.495, kTol);
    EXPECT_EQ(m.points[k].feature & fq::kFeatureKindMask, fq::kFeatureFaceContact);
    for (int j = 0; j < k; ++j) EXPECT_NE(m.points[k].feature, m.points[j].feature);
  }
}

TEST(CollideBoxBox, SmallBoxOnLargeFaceGivesItsFourCorners) {
  // b (half 0.25) on a (half 0.5): b's bottom corners at (+-0.25, +-0.25).
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0.1, 0, 0.5 + 0.25 - 0.002), Mat3::Identity(), 0.25), m), 4);
  for (int k = 0; k < m.count; ++k) {
    EXPECT_NEAR(m.points[k].depth_m, 0.002, kTol);
    EXPECT_NEAR(std::fabs(m.points[k].position_m.x() - 0.1), 0.25, kTol);
    EXPECT_NEAR(std::fabs(m.points[k].position_m.y()), 0.25, kTol);
  }
}

TEST(CollideBoxBox, ParallelOffsetFacesGiveTheOverlapRectangle) {
  // Same cubes offset by (0.3, 0.2) in the plane: the contact patch is the
  // rectangle x in [-0.2, 0.5], y in [-0.3, 0.5]; its 4 corners are the points.
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0.3, 0.2, 0.99)), m), 4);
  for (int k = 0; k < m.count; ++k) {
    const Vec3& p = m.points[k].position_m;
    const bool x_ok = std::fabs(p.x() + 0.2) < 1e-9 || std::fabs(p.x() - 0.5) < 1e-9;
    const bool y_ok = std::fabs(p.y() + 0.3) < 1e-9 || std::fabs(p.y() - 0.5) < 1e-9;
    EXPECT_TRUE(x_ok && y_ok) << p.transpose();
    EXPECT_NEAR(m.points[k].depth_m, 0.01, kTol);
  }
}

TEST(CollideBoxBox, EdgeEdgeGivesOnePoint) {
  // a turned 45 deg about x: its top is a ridge along x at z = sqrt(2)/2.
  // b turned 45 deg about y: its bottom is a ridge along y at
  // z_b - sqrt(2)/2. With z_b = sqrt(2) - d the ridges cross at the origin's
  // vertical with overlap d: one point at (0, 0, sqrt(2)/2 - d/2), normal +z.
  const double d = 0.003;
  const double r2 = std::sqrt(2.0) / 2.0;
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero(), rot(std::numbers::pi / 4, Vec3::UnitX())),
                                cube(Vec3(0, 0, 2 * r2 - d), rot(std::numbers::pi / 4, Vec3::UnitY())), m),
            1);
  EXPECT_NEAR(m.points[0].depth_m, d, 1e-12);
  EXPECT_NEAR((m.points[0].normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((m.points[0].position_m - Vec3(0, 0, r2 - d / 2)).norm(), 0.0, 1e-12);
  EXPECT_EQ(m.points[0].feature & fq::kFeatureKindMask, fq::kFeatureEdgeContact);
}

TEST(CollideBoxBox, EdgeEdgeSeparatedOnlyAlongTheCrossAxis) {
  // Same ridges 0.003 apart: every face axis still overlaps (the projections
  // of the turned cubes on their face normals overlap), only the cross
  // product of the two ridges separates -> no contact.
  const double r2 = std::sqrt(2.0) / 2.0;
  ContactManifold m;
  EXPECT_EQ(fq::collide_box_box(cube(Vec3::Zero(), rot(std::numbers::pi / 4, Vec3::UnitX())),
                                cube(Vec3(0, 0, 2 * r2 + 0.003), rot(std::numbers::pi / 4, Vec3::UnitY())), m),
            0);
}

TEST(CollideBoxBox, VertexFaceGivesOnePointAtTheCorner) {
  // b turned so that its body diagonal (1,1,1) points along +z: its corner
  // (-,-,-) is lowest, sqrt(3)/2 below its centre. With z_b = 0.5 +
  // sqrt(3)/2 - d it dips d into a's top face: one point at (0, 0, 0.5 - d/2).
  const double d = 0.004;
  const Mat3 r = fq::test::body_diagonal_onto_z().toRotationMatrix();
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0, 0, 0.5 + std::sqrt(3.0) / 2 - d), r), m), 1);
  EXPECT_NEAR(m.points[0].depth_m, d, 1e-12);
  EXPECT_NEAR((m.points[0].normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((m.points[0].position_m - Vec3(0, 0, 0.5 - d / 2)).norm(), 0.0, 1e-12);
}

TEST(CollideBoxBox, DeepOverlapTakesTheAxisOfLeastPenetration) {
  // Centres 0.3 apart in z and 0.1 in x: overlaps are 0.7 along z, 0.9
  // along x, 1.0 along y -> normal +z, depth 0.7, the 4 clipped corners.
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0.1, 0, 0.3)), m), 4);
  for (int k = 0; k < m.count; ++k) {
    EXPECT_NEAR(m.points[k].depth_m, 0.7, kTol);
    EXPECT_NEAR((m.points[k].normal - Vec3::UnitZ()).norm(), 0.0, kTol);
  }
}

TEST(CollideBoxBox, SeparatedGivesNone) {
  ContactManifold m;
  EXPECT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0, 0, 1.0001)), m), 0);
  EXPECT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(1.2, 0.3, 0.2), rot(0.3, Vec3(1, 2, 3))), m), 0);
}

TEST(CollideBoxBox, RotatedConfigurationHasKnownDepthAndNormal) {
  // The face-face set-up in an arbitrarily rotated frame q, with b further
  // turned by 30 deg about the contact normal n = q z. b's bottom square,
  // turned 30 deg over a's equal top square, is cut to an octagon: 8 points,
  // all with depth d and normal n; swapping a and b flips the normal.
  const double d = 0.02;
  const Mat3 q = rot(0.7, Vec3(0.3, -1.0, 0.5));
  const Vec3 n = q.col(2);
  const Vec3 c = Vec3(0.4, -0.2, 1.1);
  const OrientedBox a = cube(c, q);
  const OrientedBox b = cube(c + (1.0 - d) * n, rot(std::numbers::pi / 6, n) * q);
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(a, b, m), 8);
  for (int k = 0; k < m.count; ++k) {
    EXPECT_NEAR(m.points[k].depth_m, d, 1e-12);
    EXPECT_NEAR((m.points[k].normal - n).norm(), 0.0, 1e-12);
    // Every point lies midway between the two faces, inside a's top face.
    const Vec3 local = q.transpose() * (m.points[k].position_m - c);
    EXPECT_NEAR(local.z(), 0.5 - d / 2, 1e-12);
    EXPECT_LE(std::fabs(local.x()), 0.5 + 1e-12);
    EXPECT_LE(std::fabs(local.y()), 0.5 + 1e-12);
  }
  // Weights: every vertex of this octagon is where a side of one square
  // crosses a side of the other, so the polygon turns there by 30 deg or
  // by 60 deg, alternately (exterior angles): weights 4 t / 2 pi of 1/3
  // and 2/3, four of each, adding up to 4. (All eight edges of this
  // octagon are equally long: shares of the perimeter would give 0.5.)
  int third = 0, two_thirds = 0;
  double total = 0.0;
  for (int k = 0; k < m.count; ++k) {
    const double w = m.points[std::size_t(k)].weight;
    third += std::fabs(w - 1.0 / 3.0) < 1e-12;
    two_thirds += std::fabs(w - 2.0 / 3.0) < 1e-12;
    total += w;
  }
  EXPECT_EQ(third, 4);
  EXPECT_EQ(two_thirds, 4);
  EXPECT_NEAR(total, 4.0, 1e-12);
  ContactManifold swapped;
  ASSERT_EQ(fq::collide_box_box(b, a, swapped), 8);
  for (int k = 0; k < swapped.count; ++k) {
    EXPECT_NEAR(swapped.points[k].depth_m, d, 1e-12);
    EXPECT_NEAR((swapped.points[k].normal + n).norm(), 0.0, 1e-12);
  }
}

TEST(CollideBoxBox, TiltedBoxRestingOnAnEdgeGivesTwoPoints) {
  // b tilted 10 deg about y, its lowest edge (along y) dipping d into a's
  // top face: the two ends of that edge, at y = +-0.5.
  const double d = 0.001;
  const double th = 10.0 * std::numbers::pi / 180.0;
  const double drop = 0.5 * (std::cos(th) + std::sin(th));  // centre height above the lowest edge
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0, 0, 0.5 + drop - d), rot(th, Vec3::UnitY())), m), 2);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(m.points[k].depth_m, d, 1e-12);
    EXPECT_NEAR(std::fabs(m.points[k].position_m.y()), 0.5, 1e-12);
  }
}

TEST(CollideBoxBox, FeaturesStayWhileTheSameFeaturesTouch) {
  // A small slide of b keeps the same 4 corner features (history continuity).
  ContactManifold m1, m2;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0.1, 0, 0.5 + 0.25 - 0.002), Mat3::Identity(), 0.25), m1), 4);
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(Vec3(0.11, 0.01, 0.5 + 0.25 - 0.0021), Mat3::Identity(), 0.25), m2), 4);
  for (int k = 0; k < 4; ++k) {
    bool found = false;
    for (int j = 0; j < 4; ++j) found = found || m1.points[k].feature == m2.points[j].feature;
    EXPECT_TRUE(found);
  }
}

}  // namespace

namespace {

TEST(CollideBoxBox, SeparatingAxisHintNeverChangesTheResult) {
  // The hint only reorders the search (collide_box_box.h): for any hint the
  // manifold must be bitwise that of the plain call. Poses sweep a box b
  // around and through a fixed box a (touching, separated along face axes,
  // separated only along edge axes), every hint value is tried, and when the
  // boxes are apart the axis returned must really separate them: a second
  // call starting from it must again give no contact.
  const OrientedBox a{Vec3(0.1, -0.2, 0.3), rot(0.3, Vec3(1, 2, 3)), Vec3(0.5, 0.2, 1.0)};
  int separated = 0, touching = 0;
  for (int k = 0; k < 400; ++k) {
    const double s = double(k);
    const Vec3 offset(1.4 * std::sin(0.37 * s), 1.1 * std::cos(0.53 * s), 1.9 * std::sin(0.71 * s + 1.0));
    const OrientedBox b{a.center_m + offset, rot(0.05 * s, Vec3(std::cos(s), 1.0, std::sin(0.3 * s))),
                        Vec3(0.3, 0.6, 0.25)};
    ContactManifold plain;
    const int n = fq::collide_box_box(a, b, plain);
    (n == 0 ? separated : touching) += 1;
    for (int hint = -1; hint < 15; ++hint) {
      std::int8_t h = std::int8_t(hint);
      ContactManifold m;
      ASSERT_EQ(fq::collide_box_box(a, b, m, &h), n) << "pose " << k << " hint " << hint;
      for (int p = 0; p < n; ++p) {
        const auto& x = plain.points[std::size_t(p)];
        const auto& y = m.points[std::size_t(p)];
        EXPECT_EQ(x.feature, y.feature);
        EXPECT_EQ(x.depth_m, y.depth_m);
        EXPECT_EQ(x.weight, y.weight);
        EXPECT_TRUE(x.position_m == y.position_m);
        EXPECT_TRUE(x.normal == y.normal);
      }
      if (n > 0) {
        EXPECT_EQ(h, -1) << "touching boxes leave no separating axis";
      } else {
        ASSERT_GE(h, 0);
        ASSERT_LT(h, 15);
        std::int8_t again = h;
        EXPECT_EQ(fq::collide_box_box(a, b, m, &again), 0);
        EXPECT_EQ(again, h) << "the remembered axis separates at once";
      }
    }
  }
  // The sweep must cover both outcomes for the check to mean anything.
  EXPECT_GT(separated, 30);
  EXPECT_GT(touching, 30);
}

}  // namespace

namespace {

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof(double)) == 0; }
bool same_bits(const Vec3& x, const Vec3& y) { return std::memcmp(x.data(), y.data(), 3 * sizeof(double)) == 0; }

TEST(CollideBoxBox, ShortcutsNeverChangeTheFullSearchsResult) {
  // collide_box_box's shortcuts (collide_box_box.h) must give bitwise the
  // manifold and the separating axis of collide_box_box_full_search. Four
  // families of poses: members resting face to face with tiny tilts and
  // overlaps (the frames' case, where the root-free edge pass decides),
  // crossed boxes in edge contact, arbitrary poses, and boxes turned by
  // about 1e-6 rad, where edge axes sit at the parallel cut-off.
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random_axis = [&]() -> Vec3 { return Vec3(u(rng), u(rng), u(rng)) + Vec3(0, 0, 1e-3); };
  int face = 0, edge = 0, apart = 0;
  for (int k = 0; k < 40000; ++k) {
    const int family = k % 4;
    const Vec3 ha(0.005 + 0.01 * std::abs(u(rng)), 0.005 + 0.01 * std::abs(u(rng)), 0.05 + 0.2 * std::abs(u(rng)));
    const Vec3 hb(0.005 + 0.01 * std::abs(u(rng)), 0.05 + 0.2 * std::abs(u(rng)), 0.005 + 0.01 * std::abs(u(rng)));
    OrientedBox a{Vec3(u(rng), u(rng), u(rng)), rot(1e-3 * u(rng), random_axis()), ha};
    OrientedBox b{a.center_m, a.rotation, hb};
    if (family == 0) {  // b on a face of a, overlap within +-1e-4 of the box size
      const int axis = k % 3;
      const double side = u(rng) > 0 ? 1.0 : -1.0;
      Vec3 offset(0.5 * ha.x() * u(rng), 0.5 * ha.y() * u(rng), 0.5 * ha.z() * u(rng));
      offset[axis] = side * (ha[axis] + hb[axis]) * (1.0 + 1e-4 * u(rng));
      b.center_m = a.center_m + a.rotation * offset;
      b.rotation = rot(1e-3 * u(rng), random_axis()) * a.rotation;
    } else if (family == 1) {  // crossed at right angles about a random axis, edges meeting
      b.rotation = rot(0.25 * std::numbers::pi * (1.0 + 0.2 * u(rng)), random_axis()) * a.rotation;
      b.center_m = a.center_m + 0.9 * (ha.norm() + hb.norm()) * random_axis().normalized();
    } else if (family == 2) {  // anywhere near a
      b.rotation = rot(3.0 * u(rng), random_axis());
      b.center_m = a.center_m + 0.8 * (ha.norm() + hb.norm()) * Vec3(u(rng), u(rng), u(rng));
    } else {  // nearly parallel: turned by ~1e-6 rad, touching or just apart
      b.rotation = rot(1e-6 * (1.0 + 0.05 * u(rng)), random_axis()) * a.rotation;
      b.center_m = a.center_m + a.rotation * Vec3(ha.x() + hb.x() * (1.0 + 1e-3 * u(rng)), 0.3 * ha.y() * u(rng), 0.0);
    }
    ContactManifold with, without;
    std::int8_t axis_with = -1, axis_without = -1;
    const int n = fq::collide_box_box(a, b, with, &axis_with);
    ASSERT_EQ(fq::collide_box_box_full_search(a, b, without, &axis_without), n) << "pose " << k;
    ASSERT_EQ(axis_with, axis_without) << "pose " << k;
    for (int p = 0; p < n; ++p) {
      const auto& x = with.points[std::size_t(p)];
      const auto& y = without.points[std::size_t(p)];
      ASSERT_EQ(x.feature, y.feature) << "pose " << k;
      ASSERT_TRUE(same_bits(x.depth_m, y.depth_m) && same_bits(x.weight, y.weight) &&
                  same_bits(x.position_m, y.position_m) && same_bits(x.normal, y.normal))
          << "pose " << k;
    }
    if (n == 0)
      ++apart;
    else if ((with.points[0].feature & fq::kFeatureKindMask) == fq::kFeatureEdgeContact)
      ++edge;
    else
      ++face;
  }
  std::printf("face contacts %d, edge contacts %d, apart %d\n", face, edge, apart);
  // Each outcome must be covered for the check to mean anything. (About
  // 320 edge contacts since the edge margin of 2026-11-26, which gives the
  // nearly parallel family face contacts; over 500 before. The root-free
  // edge pass runs, and is checked, whatever the outcome.)
  EXPECT_GT(face, 5000);
  EXPECT_GT(edge, 200);
  EXPECT_GT(apart, 5000);
}

}  // namespace

namespace {

// Sums over a face contact's points in the frame (x, y) of a's top face
// (rotation q, face centre c): total weight, first and second moments.
struct WeightMoments {
  double total = 0.0, x = 0.0, y = 0.0, xx = 0.0, yy = 0.0;
};
WeightMoments weight_moments(const ContactManifold& m, const Mat3& q, const Vec3& c) {
  WeightMoments s;
  for (int k = 0; k < m.count; ++k) {
    const Vec3 local = q.transpose() * (m.points[std::size_t(k)].position_m - c);
    const double w = m.points[std::size_t(k)].weight;
    s.total += w;
    s.x += w * local.x();
    s.y += w * local.y();
    s.xx += w * local.x() * local.x();
    s.yy += w * local.y() * local.y();
  }
  return s;
}

TEST(CollideBoxBoxWeights, ATriangleWeighsItsExteriorAngles) {
  // Geometry: b's bottom face turned 45 deg and placed so that only one of
  // its corners reaches over a's top face, across a's edge x = 0.5 at right
  // angles: the overlap is the right isosceles triangle with that corner
  // (90 deg inside, turn 90 deg) and two vertices on the edge (45 deg inside,
  // turn 135 deg). Weights 4 t / 2 pi: 1 at the corner, 1.5 at the others.
  const double d = 0.01;
  const double h = 0.5;  // half side of b
  const double reach = 0.1;  // how far b's corner lies inside a's edge
  // b's centre so that its corner pointing to -x sits at x = 0.5 - reach.
  const Vec3 centre(0.5 - reach + h * std::sqrt(2.0), 0.2, 1.0 - d);
  ContactManifold m;
  ASSERT_EQ(fq::collide_box_box(cube(Vec3::Zero()), cube(centre, rot(std::numbers::pi / 4, Vec3::UnitZ())), m), 3);
  for (int k = 0; k < 3; ++k) {
    const auto& p = m.points[std::size_t(k)];
    const bool at_corner = std::fabs(p.position_m.x() - (0.5 - reach)) < 1e-12;
    EXPECT_NEAR(p.weight, at_corner ? 1.0 : 1.5, 1e-12) << p.position_m.transpose();
  }
}

TEST(CollideBoxBoxWeights, EqualFacesTwistedByAHairKeepTheirStiffnessAndRockingStiffness) {
  // A 20 x 10 mm column end bearing on an equal end below (the frames'
  // columns at a floor node) twisted about the normal by a hair, as
  // round-off does. The overlap polygon gains crossings mid-edge where the
  // nearly parallel sides cross; physically it is still the rectangle, so
  // the total weight, the centre of the weights and the second moments
  // (the rocking stiffnesses about the face's two axes, in units of k_n)
  // must stay those of the untwisted face, 4, (0, 0) and 4 a^2, 4 b^2,
  // changing by no more than the twist itself moves the corners (a relative
  // 10 theta; the perimeter shares of the earlier weights dropped the
  // rocking stiffness about the long axis to 2/3 at any twist).
  const Vec3 half(0.01, 0.005, 0.1);
  const Mat3 q = rot(0.3, Vec3(1.0, 0.2, -0.4));
  const Vec3 n = q.col(2);
  const Vec3 c(0.3, 0.1, 2.0);
  const OrientedBox below{c, q, half};
  const double d = 1e-5;
  const Vec3 face_centre = c + half.z() * n;
  for (double theta : {0.0, 1e-12, 1e-10, 1e-8, 1e-6, 1e-4}) {
    for (double sign : {1.0, -1.0}) {
      const OrientedBox above{c + (2.0 * half.z() - d) * n, rot(sign * theta, n) * q, half};
      ContactManifold m;
      const int count = fq::collide_box_box(below, above, m);
      ASSERT_GE(count, 4) << theta;
      const WeightMoments s = weight_moments(m, q, face_centre);
      const double rel = 10.0 * theta + 1e-9;
      EXPECT_NEAR(s.total, 4.0, 1e-12) << theta;
      EXPECT_NEAR(s.x / half.x(), 0.0, 4.0 * rel) << theta;
      EXPECT_NEAR(s.y / half.y(), 0.0, 4.0 * rel) << theta;
      EXPECT_NEAR(s.xx / (4.0 * half.x() * half.x()), 1.0, rel) << theta << " points " << count;
      EXPECT_NEAR(s.yy / (4.0 * half.y() * half.y()), 1.0, rel) << theta << " points " << count;
    }
  }
}

TEST(CollideBoxBoxWeights, ACornerCrossingASidePlaneHandsItsWeightToTheTwoPointsItBecomes) {
  // A small square face (half 0.1, turned 20 deg) slid across a's edge
  // x = 0.5: while its corner is inside the edge the polygon is the square
  // and the corner weighs 1; just past the edge the corner becomes two
  // points a hair apart (a pentagon) that share its turn.
  // The weights near that corner must add up to the same on both sides of
  // the crossing, and the second moment of the weights must not jump. Past
  // by 1e-9 m the two points are 3e-9 m apart, past by 1e-10 m 3e-10 m:
  // their turns come from the lines they lie on, not from the short edge
  // between them, whose direction round-off would blur.
  const Mat3 turn = rot(20.0 * std::numbers::pi / 180.0, Vec3::UnitZ());
  const double h = 0.1;
  const Vec3 corner_local = turn * Vec3(h, -h, 0.0);  // the corner reaching furthest in +x
  const Vec3 other = turn * Vec3(h, h, 0.0);
  ASSERT_GT(corner_local.x(), other.x());
  auto moments_past_the_edge = [&](double eps) {
    const Vec3 centre(0.5 - corner_local.x() + eps, 0.1, 0.5 + h - 0.001);
    ContactManifold m;
    const int count = fq::collide_box_box(cube(Vec3::Zero()), cube(centre, turn, h), m);
    EXPECT_EQ(count, eps < 0 ? 4 : 5) << eps;
    return weight_moments(m, Mat3::Identity(), Vec3(0.5, 0.1, 0.5));
  };
  const WeightMoments before = moments_past_the_edge(-1e-9);
  EXPECT_NEAR(before.total, 4.0, 1e-12);
  for (double eps : {1e-9, 1e-10}) {
    const WeightMoments after = moments_past_the_edge(eps);
    EXPECT_NEAR(after.total, 4.0, 1e-12) << eps;
    EXPECT_NEAR(after.x, before.x, 1e-7) << eps;
    EXPECT_NEAR(after.xx, before.xx, 1e-7) << eps;
    EXPECT_NEAR(after.yy, before.yy, 1e-7) << eps;
  }
}

}  // namespace

namespace {

TEST(CollideBoxBox, ABoxTiltingOverAnEdgeKeepsAFaceContact) {
  // A 0.1 m cube turned 30 deg about the vertical lies across the edge
  // x = 0.15 m of a 0.3 x 0.3 x 0.1 m slab, overhanging it, and tips over
  // the edge by alpha about axes along and across the edge: its bottom
  // face touches the slab along the edge, pressed in by d at one point of
  // it, and rises inside. Geometry: the contact is the
  // slab's edge against the cube's bottom face, a face contact whose
  // deepest points lie along the edge. An edge-edge contact
  // (one point where a cube edge crosses the slab's edge, taken when its
  // axis overlaps less than 0.95 of the best face axis) puts the whole
  // load at one point of the edge and makes the contact jump between one
  // point and several as alpha and d change (a probe: a box sliding over
  // an edge, 2026-11-26).
  const OrientedBox slab{Vec3(0, 0, -0.05), Mat3::Identity(), Vec3(0.15, 0.15, 0.05)};
  const double d = 1e-6;
  int face = 0, cases = 0;
  for (double alpha : {1e-5, 1e-4, 1e-3}) {
    for (double centre_x : {0.12, 0.14, 0.16}) {
     for (const Vec3& tilt_axis : {Vec3(0, 1, 0), Vec3(0.5, 1, 0), Vec3(-0.5, 1, 0), Vec3(1, 0.2, 0)}) {
      const Mat3 r = rot(alpha, tilt_axis) * rot(std::numbers::pi / 6, Vec3::UnitZ());
      // Place the cube so that its bottom face passes through the edge
      // line (x = 0.15, z = 0) lowered by d: bottom-face centre c_f with
      // n . (edge point - c_f) = 0, n the face's outward normal -r z.
      const Vec3 n = -r.col(2);
      Vec3 centre(centre_x, 0.01, 0.0);
      // Bottom face plane: n . p = n . (centre + 0.05 n). Solve for centre.z
      // so that the point (0.15, 0.01, -d) lies on it.
      const Vec3 on_edge(0.15, 0.01, -d);
      centre.z() = (n.dot(on_edge) - 0.05 - n.x() * centre.x() - n.y() * centre.y()) / n.z();
      const OrientedBox cube_box{centre, r, Vec3::Constant(0.05)};
      ContactManifold m;
      const int count = fq::collide_box_box(slab, cube_box, m);
      ++cases;
      ASSERT_GE(count, 1) << alpha << " " << centre_x;
      const bool is_face = (m.points[0].feature & fq::kFeatureKindMask) == fq::kFeatureFaceContact;
      face += is_face;
      EXPECT_TRUE(is_face) << "alpha " << alpha << " centre x " << centre_x << ": " << count << " point(s)";
      // The point placed d deep lies inside the cube's footprint, so the
      // face contact reaches at least d; nothing lies deeper than d plus
      // the tilt times the cube's diagonal.
      double deepest = 0.0, weights = 0.0;
      for (int k = 0; k < count; ++k) {
        deepest = std::max(deepest, m.points[std::size_t(k)].depth_m);
        weights += m.points[std::size_t(k)].weight;
      }
      EXPECT_GE(deepest, d * (1.0 - 1e-6)) << alpha << " " << centre_x;
      EXPECT_LE(deepest, d + alpha * 0.15);
      EXPECT_LE(weights, 4.0 + 1e-12);
     }
    }
  }
  EXPECT_EQ(face, cases);
}

}  // namespace

namespace {

// Depth of the point with feature `feature` in the manifold of a and b, or
// NaN when the manifold has no such point.
double depth_of_feature(const OrientedBox& a, const OrientedBox& b, std::uint32_t feature) {
  ContactManifold m;
  fq::collide_box_box_full_search(a, b, m);
  for (int k = 0; k < m.count; ++k)
    if (m.points[k].feature == feature) return m.points[k].depth_m;
  return std::numeric_limits<double>::quiet_NaN();
}

// Box b turned by the small rotation `angle` (rad, a vector) about its own centre.
OrientedBox turned(const OrientedBox& b, const Vec3& angle) {
  OrientedBox t = b;
  if (angle.norm() > 0.0) t.rotation = rot(angle.norm(), angle) * b.rotation;
  return t;
}

}  // namespace

// A point's spring stores 1/2 k depth^2, so the force that does as much
// work as the energy changes is k depth times minus the depth's gradient:
// on b, for a move of b alone, normal + lean; on a the opposite; and for a
// turn of b about its centre, the moment of that force at the point's
// vertex (the polygon's vertex, half the depth from the reported position
// back along the reference normal). Checked against central differences of
// the narrow phase's own depth of the same feature (h = 1e-7 m and 1e-7
// rad: truncation ~h^2 / size, round-off ~1e-16 / h, both below 1e-8 of
// the unit gradient) over random face contacts of two boxes of different
// sizes (b's face smaller than a's or larger), b tilted up to 30 deg (0.3
// deg when larger) and
// shifted so that it often hangs over a's edges: incident corners (no lean), crossings of an incident edge with a
// side plane, and corners of the reference face inside the incident face,
// each kind present. A force along the normal alone, as before stop 42,
// misses the crossings' and reference corners' gradients by their lean
// (up to 0.4 here), so that the contact did work no energy paid for
// (contacts/README.md, "Forces of face points").
TEST(CollideBoxBox, EachFacePointPushesAlongTheGradientOfItsDepth) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double h = 1e-7;
  int kinds_seen[3] = {0, 0, 0};  // incident corner, crossing, reference corner
  double largest_lean = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    const OrientedBox a{Vec3::Zero(), rot(0.3 * u(rng), Vec3(u(rng), u(rng), u(rng))), Vec3(0.30, 0.25, 0.20)};
    // Every other trial b's bottom face is larger than a's top face, covers
    // it and is tilted by less (up to 0.3 deg), so that a's face, preferred
    // as a's, stays the reference and its corners lie inside b's and below
    // it (reference corners).
    const bool large_b = trial % 2 == 1;
    const Mat3 tilt = rot((large_b ? 0.005 : 0.52) * std::fabs(u(rng)), Vec3(u(rng), u(rng), 0.1 * u(rng)));
    const Vec3 half_b = large_b ? Vec3(0.45, 0.40, 0.10) : Vec3(0.20, 0.15, 0.10);
    // b above a's top face (a's z axis), shifted sideways up to past a's edges.
    const Vec3 offset_local = large_b ? Vec3(0.1 * u(rng), 0.1 * u(rng), 0.0) : Vec3(0.45 * u(rng), 0.4 * u(rng), 0.0);
    OrientedBox b{Vec3::Zero(), a.rotation * tilt, half_b};
    // Lower b along a's up axis until the deepest point of the manifold is
    // 2 mm deep (bisection; the depth grows as b comes down).
    const Vec3 up = a.rotation.col(2);
    auto deepest = [&](double height) {
      ContactManifold trial_m;
      fq::collide_box_box_full_search(a, {a.rotation * offset_local + height * up, b.rotation, b.half_extents_m}, trial_m);
      double d = 0.0;
      for (int k = 0; k < trial_m.count; ++k) d = std::max(d, trial_m.points[k].depth_m);
      return d;
    };
    double low = 0.0, high = 2.0;
    for (int it = 0; it < 60; ++it) ((deepest(0.5 * (low + high)) > 0.002) ? low : high) = 0.5 * (low + high);
    b.center_m = a.rotation * offset_local + low * up;
    ContactManifold m;
    fq::collide_box_box_full_search(a, b, m);
    for (int k = 0; k < m.count; ++k) {
      const fq::ContactPointGeometry& p = m.points[k];
      if ((p.feature & fq::kFeatureKindMask) != fq::kFeatureFaceContact) continue;
      const std::uint32_t code = p.feature & 0x7fffffu;
      const int kind = code < 8 ? 0 : code < 24 ? 1 : 2;
      const Vec3 g = p.normal + p.lean;  // the force's direction on b
      Vec3 grad_b, grad_a, moment_b;
      bool complete = true;
      for (int i = 0; i < 3 && complete; ++i) {
        const Vec3 step = h * Vec3::Unit(i);
        const double b_plus = depth_of_feature(a, {b.center_m + step, b.rotation, b.half_extents_m}, p.feature);
        const double b_minus = depth_of_feature(a, {b.center_m - step, b.rotation, b.half_extents_m}, p.feature);
        const double a_plus = depth_of_feature({a.center_m + step, a.rotation, a.half_extents_m}, b, p.feature);
        const double a_minus = depth_of_feature({a.center_m - step, a.rotation, a.half_extents_m}, b, p.feature);
        const double t_plus = depth_of_feature(a, turned(b, step), p.feature);
        const double t_minus = depth_of_feature(a, turned(b, -step), p.feature);
        complete = std::isfinite(b_plus + b_minus + a_plus + a_minus + t_plus + t_minus);
        grad_b[i] = -(b_plus - b_minus) / (2.0 * h);
        grad_a[i] = -(a_plus - a_minus) / (2.0 * h);
        moment_b[i] = -(t_plus - t_minus) / (2.0 * h);
      }
      if (!complete) continue;  // a feature that ends within h of here
      ++kinds_seen[kind];
      largest_lean = std::max(largest_lean, p.lean.norm());
      SCOPED_TRACE("trial " + std::to_string(trial) + ", point code " + std::to_string(code));
      EXPECT_NEAR((grad_b - g).norm(), 0.0, 1e-6);
      EXPECT_NEAR((grad_a + g).norm(), 0.0, 1e-6);
      const bool ref_is_b = (p.feature & (1u << 29)) != 0;
      const Vec3 reference_normal = ref_is_b ? Vec3(-p.normal) : p.normal;
      const Vec3 vertex = p.position_m - 0.5 * p.depth_m * reference_normal;
      EXPECT_NEAR((moment_b - (vertex - b.center_m).cross(g)).norm(), 0.0, 1e-6);
    }
  }
  // Each kind of point was checked, crossings and reference corners with a lean.
  EXPECT_GT(kinds_seen[0], 50);
  EXPECT_GT(kinds_seen[1], 50);
  EXPECT_GT(kinds_seen[2], 50);
  std::printf("points checked: %d incident corners, %d crossings, %d reference corners; largest lean %.3f\n",
              kinds_seen[0], kinds_seen[1], kinds_seen[2], largest_lean);
}
