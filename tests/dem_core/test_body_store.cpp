// Body store: mass and inertia of a homogeneous box against their closed
// forms, fixed bodies, and refusal of unusable definitions.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "dem_core/body_store.h"

namespace {

using fq::BodyStore;
using fq::BoxBodyDef;
using fq::Mat3;
using fq::Quat;
using fq::Vec3;

// Three different edges so that each principal moment is different and a
// swapped axis would show.
BoxBodyDef generic_box() {
  BoxBodyDef def;
  def.name = "box";
  def.size_m = Vec3(0.1, 0.2, 0.35);
  def.density_kg_per_m3 = 450.0;  // softwood
  return def;
}

TEST(BodyStore, BoxMassAndPrincipalInertiaMatchClosedForm) {
  // Expected: m = rho a b c, I_x = m (b^2 + c^2) / 12 and cyclic (homogeneous
  // cuboid about its centre, any mechanics textbook).
  const BoxBodyDef def = generic_box();
  const double a = 0.1, b = 0.2, c = 0.35, rho = 450.0;
  const double m = rho * a * b * c;
  BodyStore store;
  const fq::BodyId id = store.add_box(def);
  ASSERT_EQ(id, 0);
  ASSERT_EQ(store.size(), 1u);
  // Round-off of a handful of products: 1e-14 relative.
  EXPECT_NEAR(store.mass_kg[0], m, 1e-14 * m);
  EXPECT_NEAR(store.inverse_mass_per_kg[0], 1.0 / m, 1e-14 / m);
  const Vec3 i_expected(m * (b * b + c * c) / 12.0, m * (a * a + c * c) / 12.0, m * (a * a + b * b) / 12.0);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(store.principal_inertia_kgm2[0][k], i_expected[k], 1e-14 * i_expected[k]) << "axis " << k;
    EXPECT_NEAR(store.inverse_inertia_per_kgm2[0][k], 1.0 / i_expected[k], 1e-14 / i_expected[k]) << "axis " << k;
  }
  EXPECT_TRUE(store.half_extents_m[0].isApprox(Vec3(0.05, 0.1, 0.175), 1e-15));
  // The free functions give the same numbers.
  EXPECT_NEAR(fq::box_mass_kg(def.size_m, rho), m, 1e-14 * m);
  EXPECT_TRUE(fq::box_principal_inertia_kgm2(def.size_m, m).isApprox(i_expected, 1e-14));
}

TEST(BodyStore, CubeHasIsotropicInertia) {
  // Expected: a cube of edge s has I = m s^2 / 6 about every axis.
  BoxBodyDef def;
  def.size_m = Vec3::Constant(0.3);
  def.density_kg_per_m3 = 700.0;
  BodyStore store;
  store.add_box(def);
  const double m = 700.0 * 0.027;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(store.principal_inertia_kgm2[0][k], m * 0.09 / 6.0, 1e-14 * m);
}

TEST(BodyStore, InitialAngularMomentumIsWorldInertiaTimesOmega) {
  // Expected: L = R diag(I) R^T w (world frame), with R from the given
  // orientation; checked against a tensor built here from the closed form.
  BoxBodyDef def = generic_box();
  def.orientation = Quat(Eigen::AngleAxisd(0.7, Vec3(1.0, -2.0, 0.5).normalized()));
  def.angular_velocity_radps = Vec3(1.5, -0.4, 2.2);
  def.velocity_mps = Vec3(0.3, 0.0, -1.0);
  BodyStore store;
  store.add_box(def);
  const double m = 450.0 * 0.1 * 0.2 * 0.35;
  const Vec3 i_body(m * (0.04 + 0.1225) / 12.0, m * (0.01 + 0.1225) / 12.0, m * (0.01 + 0.04) / 12.0);
  const Mat3 r = def.orientation.normalized().toRotationMatrix();
  const Mat3 i_world = r * i_body.asDiagonal() * r.transpose();
  const Vec3 l_expected = i_world * def.angular_velocity_radps;
  EXPECT_TRUE(store.angular_momentum_Nms[0].isApprox(l_expected, 1e-14));
  EXPECT_TRUE(store.rotation[0].isApprox(r, 1e-15));
  // Inverse tensor and the momentum -> velocity map invert the same tensor.
  EXPECT_TRUE((store.world_inverse_inertia(0) * i_world).isApprox(Mat3::Identity(), 1e-13));
  EXPECT_TRUE(store.angular_velocity_from_momentum(0, r, l_expected).isApprox(def.angular_velocity_radps, 1e-13));
  EXPECT_TRUE(store.velocity_mps[0].isApprox(def.velocity_mps, 0.0));
}

TEST(BodyStore, PointVelocityAndToWorldAreRigidBodyKinematics) {
  // Expected: v_P = v + w x (x_P - x) and x_P = x + R s (seed 000 Eq. 1).
  BoxBodyDef def = generic_box();
  def.position_m = Vec3(1.0, 2.0, 3.0);
  def.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi / 2.0, Vec3::UnitZ()));
  def.velocity_mps = Vec3(0.5, 0.0, 0.0);
  def.angular_velocity_radps = Vec3(0.0, 0.0, 2.0);
  BodyStore store;
  store.add_box(def);
  // Body x axis maps to world y after a quarter turn about z.
  EXPECT_TRUE(store.to_world(0, Vec3(0.1, 0.0, 0.0)).isApprox(Vec3(1.0, 2.1, 3.0), 1e-15));
  // w x r = 2 e_z x 0.1 e_y = -0.2 e_x.
  EXPECT_TRUE(store.point_velocity(0, Vec3(1.0, 2.1, 3.0)).isApprox(Vec3(0.3, 0.0, 0.0), 1e-14));
}

TEST(BodyStore, FixedBodyHasZeroInverseMassAndInertiaAndNoVelocity) {
  // Expected: a fixed body has infinite mass for the integrator (inverse 0)
  // and starts at rest whatever velocity its definition carried.
  BoxBodyDef def = generic_box();
  def.fixed = true;
  def.velocity_mps = Vec3(1.0, 2.0, 3.0);
  def.angular_velocity_radps = Vec3(4.0, 5.0, 6.0);
  BodyStore store;
  store.add_box(def);
  EXPECT_EQ(store.is_fixed[0], 1);
  EXPECT_EQ(store.inverse_mass_per_kg[0], 0.0);
  EXPECT_TRUE(store.inverse_inertia_per_kgm2[0].isZero(0.0));
  EXPECT_TRUE(store.velocity_mps[0].isZero(0.0));
  EXPECT_TRUE(store.angular_velocity_radps[0].isZero(0.0));
  EXPECT_TRUE(store.angular_momentum_Nms[0].isZero(0.0));
  // Its mass is still the physical one (reported, e.g. for base shear).
  EXPECT_GT(store.mass_kg[0], 0.0);
}

TEST(BodyStore, IdsAreConsecutiveAndInfoIsKept) {
  BodyStore store;
  BoxBodyDef def = generic_box();
  def.name = "column_1";
  def.kind = fq::MemberKind::Column;
  EXPECT_EQ(store.add_box(def), 0);
  def.name = "beam_1";
  def.kind = fq::MemberKind::Beam;
  EXPECT_EQ(store.add_box(def), 1);
  ASSERT_EQ(store.info.size(), 2u);
  EXPECT_EQ(store.info[1].name, "beam_1");
  EXPECT_EQ(store.info[1].kind, fq::MemberKind::Beam);
  fq::MemberKind k = fq::MemberKind::Other;
  EXPECT_TRUE(fq::parse_member_kind("brace", k));
  EXPECT_EQ(k, fq::MemberKind::Brace);
  EXPECT_FALSE(fq::parse_member_kind("girder", k));
  EXPECT_STREQ(fq::member_kind_name(fq::MemberKind::Column), "column");
}

TEST(BodyStore, InvalidSizeOrDensityThrowsAndNamesTheBody) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Vec3 bad_sizes[] = {Vec3(0.0, 0.2, 0.3), Vec3(0.1, -0.2, 0.3), Vec3(0.1, 0.2, nan), Vec3(inf, 0.2, 0.3)};
  for (const Vec3& size : bad_sizes) {
    BodyStore store;
    BoxBodyDef def = generic_box();
    def.name = "bad_box";
    def.size_m = size;
    try {
      store.add_box(def);
      ADD_FAILURE() << "size " << size.transpose() << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("bad_box"), std::string::npos) << e.what();
    }
    EXPECT_EQ(store.size(), 0u) << "a refused body must not be half added";
  }
  for (double rho : {0.0, -1.0, nan, inf}) {
    BodyStore store;
    BoxBodyDef def = generic_box();
    def.density_kg_per_m3 = rho;
    EXPECT_THROW(store.add_box(def), std::invalid_argument) << "density " << rho;
    EXPECT_EQ(store.size(), 0u);
  }
  // Positive, finite sizes and densities whose mass or inertia doubles
  // cannot hold: 1e-200 m edges (m = 0), 1e-100 m edges (I = 0), 1e200 m
  // edges (m = inf), 1e-300 kg/m^3 on 1 mm edges (m = 1e-309, subnormal).
  struct Extreme {
    Vec3 size_m;
    double density;
  };
  for (const Extreme& x : {Extreme{Vec3::Constant(1e-200), 450.0}, Extreme{Vec3::Constant(1e-100), 450.0},
                           Extreme{Vec3::Constant(1e200), 450.0}, Extreme{Vec3::Constant(1e-3), 1e-300}}) {
    BodyStore store;
    BoxBodyDef def = generic_box();
    def.name = "speck";
    def.size_m = x.size_m;
    def.density_kg_per_m3 = x.density;
    try {
      store.add_box(def);
      ADD_FAILURE() << "size " << x.size_m.x() << " m, density " << x.density << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'speck'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not representable"), std::string::npos) << e.what();
      // The edges as numbers can be read: "1e+200", not 201 digits or
      // 1e-200 as 0.000000.
      std::ostringstream edge;
      edge << "edges " << x.size_m.x() << "..";
      EXPECT_NE(std::string(e.what()).find(edge.str()), std::string::npos) << e.what();
      EXPECT_LT(std::string(e.what()).size(), 200u) << e.what();
    }
    EXPECT_EQ(store.size(), 0u);
  }
  // A 1 mm timber chip is fine.
  BodyStore store;
  BoxBodyDef chip = generic_box();
  chip.size_m = Vec3::Constant(1e-3);
  EXPECT_NO_THROW(store.add_box(chip));
}

}  // namespace
