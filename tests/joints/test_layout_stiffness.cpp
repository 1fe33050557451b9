// Effective stiffness of joint layouts: (1) the closed forms derived in
// joint_layout.h by hand (axial, shear, bending, torsion; seed 000 Eqs.
// 19-27 for the link system), (2) the library's K = sum k g g^T, and (3)
// central finite differences of the actual force routine (JointSystem) must
// agree. Expected values come from the closed forms written out here.
#include <gtest/gtest.h>

#include <cmath>

#include "joint_test_util.h"

namespace fq {
namespace {

// Finite-difference stiffness of body b about the joint origin: -dQ/du with
// Q = (force on b, torque on b about the origin), u = (translation, rotation).
Mat6 finite_difference_stiffness(const JointLayout& layout, double h_m, double h_rad) {
  BondedPairs bonded;
  BodyStore store = test::two_boxes(0.2);
  JointSystem js(&bonded);
  JointDef d;
  d.body_a = 0;
  d.body_b = 1;
  d.layout = layout;
  d.fracture.criterion = BreakCriterion::Never;
  js.add_joint(store, d);
  js.prepare(store);
  const Vec3 rest = store.position_m[1];
  const Quat rest_q = store.orientation[1];
  Mat6 k;
  for (int c = 0; c < 6; ++c) {
    Eigen::Matrix<double, 6, 1> qp, qm;
    for (int sgn : {1, -1}) {
      Vec3 t = Vec3::Zero(), phi = Vec3::Zero();
      if (c < 3)
        t[c] = sgn * h_m;
      else
        phi[c - 3] = sgn * h_rad;
      const test::Wrench w = test::drive(js, store, 1, rest, rest_q, t, phi, Vec3::Zero());
      Eigen::Matrix<double, 6, 1>& q = sgn > 0 ? qp : qm;
      q.head<3>() = w.force_N;
      q.tail<3>() = w.torque_Nm;
    }
    k.col(c) = -(qp - qm) / (2.0 * (c < 3 ? h_m : h_rad));
  }
  return k;
}

void expect_matrix_near(const Mat6& a, const Mat6& b, double rel) {
  const double scale = b.cwiseAbs().maxCoeff();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      // Translational and rotational entries have different units: compare
      // each against its own diagonal scale sqrt(K_ii K_jj) as well.
      const double local = std::sqrt(std::abs(b(i, i) * b(j, j)));
      EXPECT_NEAR(a(i, j), b(i, j), rel * std::max(local, 1e-12 * scale)) << "entry " << i << "," << j;
    }
}

TEST(LayoutStiffness, FourCornerClosedFormsAndFiniteDifferences) {
  const double kn = 3e6, ks = 1e6, c1 = 0.03, c2 = 0.05;
  const JointLayout l = four_corner_layout(c1, c2, 1.0, linear_spring(kn), linear_spring(ks));
  const EffectiveStiffness e = effective_stiffness(l);
  EXPECT_DOUBLE_EQ(e.axial_Npm, 4 * kn);
  EXPECT_DOUBLE_EQ(e.shear_1_Npm, 4 * ks);
  EXPECT_DOUBLE_EQ(e.shear_2_Npm, 4 * ks);
  EXPECT_NEAR(e.bending_1_Nmprad, 4 * kn * c2 * c2, 1e-9 * 4 * kn * c2 * c2);
  EXPECT_NEAR(e.bending_2_Nmprad, 4 * kn * c1 * c1, 1e-9 * 4 * kn * c1 * c1);
  EXPECT_NEAR(e.torsion_Nmprad, 4 * ks * (c1 * c1 + c2 * c2), 1e-9 * 4 * ks * (c1 * c1 + c2 * c2));
  // Symmetric layout in its plane: no coupling between the six modes.
  const Mat6 k = layout_stiffness_matrix(l);
  EXPECT_NEAR((k - Mat6(k.diagonal().asDiagonal())).cwiseAbs().maxCoeff(), 0.0, 1e-9 * k.maxCoeff());
  // Central differences: truncation O(h^2) relative to the geometry (0.1 m):
  // h = 1e-6 m, 1e-5 rad give ~1e-9; round-off ~ 1e-16 F / h ~ 1e-8 relative.
  expect_matrix_near(finite_difference_stiffness(l, 1e-6, 1e-5), k, 1e-6);
}

TEST(LayoutStiffness, SinglePointAndRadiusOfGyration) {
  const JointLayout one = single_point_layout(linear_spring(2e6), linear_spring(5e5));
  const EffectiveStiffness e = effective_stiffness(one);
  EXPECT_DOUBLE_EQ(e.axial_Npm, 2e6);
  EXPECT_DOUBLE_EQ(e.shear_1_Npm, 5e5);
  EXPECT_EQ(e.bending_1_Nmprad, 0.0);
  EXPECT_EQ(e.torsion_Nmprad, 0.0);
  expect_matrix_near(finite_difference_stiffness(one, 1e-6, 1e-5), layout_stiffness_matrix(one), 1e-6);
  // Points at the radius of gyration of a b x h rectangle with k_n = EA/4L
  // give K_b1 = E (b h^3 / 12) / L exactly.
  const double b = 0.04, h = 0.08, E = 1e10, L = 0.5;
  const JointLayout rg = four_corner_layout(b / 2, h / 2, kRadiusOfGyrationFraction, linear_spring(E * b * h / (4 * L)),
                                            linear_spring(1e6));
  const EffectiveStiffness r = effective_stiffness(rg);
  EXPECT_NEAR(r.bending_1_Nmprad, E * b * h * h * h / 12 / L, 1e-9 * E * b * h * h * h / 12 / L);
  EXPECT_NEAR(r.bending_2_Nmprad, E * h * b * b * b / 12 / L, 1e-9 * E * h * b * b * b / 12 / L);
}

TEST(LayoutStiffness, SeedLinkSystemEqs19To27) {
  // Seed 000 Fig. 4 link system: side a, gap l; k axial, k' diagonal
  // (faces normal to t2), k_s shear diagonals (faces normal to t1).
  const double a = 0.1, l = 0.05, k = 4e6, kd = 1.5e6, ksh = 1e6;
  LinkSystemDef def;
  def.side_m = a;
  def.gap_m = l;
  def.axial = linear_spring(k);
  def.diagonal = linear_spring(kd);
  def.shear = linear_spring(ksh);
  const JointLayout layout = link_system_layout(def);
  ASSERT_EQ(layout.links.size(), 12u);
  const double diag = std::sqrt(a * a + l * l);
  const double s = a / diag, c = l / diag;  // sin, cos of theta
  const Mat6 km = layout_stiffness_matrix(layout);
  const double tol = 1e-9;
  EXPECT_NEAR(km(2, 2), 4 * k + 4 * (kd + ksh) * c * c, tol * km(2, 2));    // axial (Eq. 20)
  EXPECT_NEAR(km(0, 0), 4 * kd * s * s, tol * km(0, 0));                    // shear t1 (Eq. 22)
  EXPECT_NEAR(km(1, 1), 4 * ksh * s * s, tol * km(1, 1));                   // shear t2
  EXPECT_NEAR(km(4, 4), a * a * (k + (kd + ksh) * c * c), tol * km(4, 4));  // bending about t2 (Eq. 26)
  EXPECT_NEAR(km(3, 3), a * a * (k + (kd + ksh) * c * c), tol * km(3, 3));  // bending about t1
  // Shear-bending coupling: K(4,0) = sum k' (r x e)_2 e_1 over the x-z
  // diagonals = -2 k' a sin(theta) cos(theta) (joint_layout.h).
  EXPECT_NEAR(km(4, 0), -2 * kd * a * s * c, tol * 2 * kd * a);
  // Seed's planar system (no shear diagonals): K_axial = 4k + 4k' cos^2.
  def.with_shear_links = false;
  EXPECT_NEAR(effective_stiffness(link_system_layout(def)).axial_Npm, 4 * k + 4 * kd * c * c,
              tol * (4 * k + 4 * kd * c * c));
  def.with_shear_links = true;
  expect_matrix_near(finite_difference_stiffness(layout, 1e-7, 1e-6), km, 1e-5);
  // Bending with the shear free (joint_layout.h): the x-z diagonals cross at
  // mid-gap, n = -l/2, and a rotation phi about t2 through that point (at P
  // the translation phi l/2 along t1 and the rotation phi) stretches none of
  // them, so u^T K u / phi^2 = a^2 (k + k_s cos^2(theta)); condensing the
  // shear out of the (t1, phi2) block gives the same.
  Eigen::Matrix<double, 6, 1> u = Eigen::Matrix<double, 6, 1>::Zero();
  u(0) = 0.5 * l;
  u(4) = 1.0;
  const double free_bending = a * a * (k + ksh * c * c);
  EXPECT_NEAR(u.dot(km * u), free_bending, tol * free_bending);
  EXPECT_NEAR(km(4, 4) - km(4, 0) * km(4, 0) / km(0, 0), free_bending, tol * free_bending);
}

TEST(LayoutStiffness, BeamCalibrationGivesBeamStiffnesses) {
  // Derivation in joint_layout.h: EA/L, E I/L, kappa G A/L, G J/L.
  const BeamSection sec = rectangular_section(0.05, 0.1);
  // Rectangle formulas: A = b h, I1 = b h^3/12, I2 = h b^3/12; J by the
  // series (Roark), for h/b = 2: J = 0.229 h b^3 within 0.5 %.
  EXPECT_DOUBLE_EQ(sec.area_m2, 0.005);
  EXPECT_NEAR(sec.inertia_1_m4, 0.05 * 1e-3 / 12, 1e-18);
  EXPECT_NEAR(sec.torsion_m4, 0.229 * 0.1 * std::pow(0.05, 3), 0.005 * 0.229 * 0.1 * std::pow(0.05, 3));
  const double E = 1.1e10, G = 6.5e8, L = 0.3;
  const JointLayout l = calibrated_beam_layout(sec, E, G, L);
  const EffectiveStiffness e = effective_stiffness(l);
  const double tol = 1e-9;
  EXPECT_NEAR(e.axial_Npm, E * sec.area_m2 / L, tol * e.axial_Npm);
  EXPECT_NEAR(e.bending_1_Nmprad, E * sec.inertia_1_m4 / L, tol * e.bending_1_Nmprad);
  EXPECT_NEAR(e.bending_2_Nmprad, E * sec.inertia_2_m4 / L, tol * e.bending_2_Nmprad);
  EXPECT_NEAR(e.shear_1_Npm, sec.shear_coefficient * G * sec.area_m2 / L, tol * e.shear_1_Npm);
  EXPECT_NEAR(e.shear_2_Npm, sec.shear_coefficient * G * sec.area_m2 / L, tol * e.shear_2_Npm);
  EXPECT_NEAR(e.torsion_Nmprad, G * sec.torsion_m4 / L, tol * e.torsion_Nmprad);
  expect_matrix_near(finite_difference_stiffness(l, 1e-8, 1e-7), layout_stiffness_matrix(l), 1e-5);
}

TEST(JointSystemView, StiffestModeAndOutputView) {
  // One normal spring through the free body's centre line (no lever arm):
  // the only mode is translation along n with omega^2 = k / m exactly.
  BondedPairs bonded;
  BodyStore store = test::two_boxes(0.1);
  JointSystem js(&bonded);
  JointDef d;
  d.body_a = 0;
  d.body_b = 1;
  SpringPointDef p;
  p.has_shear = false;
  TrilinearParams t;
  t.yield_strain_tension = t.yield_strain_compression = 0.01;
  t.yield_force_tension_N = t.yield_force_compression_N = 1000.0;
  t.ultimate_strain_tension = t.ultimate_strain_compression = 0.05;
  t.ultimate_force_tension_N = t.ultimate_force_compression_N = 1200.0;
  p.normal = trilinear_spring(t, 0.1);  // k0 = 1000 N / 1 mm
  d.layout.points.push_back(p);
  js.add_joint(store, d);
  const StiffestMode mode = js.stiffest_mode(store);
  EXPECT_NEAR(mode.omega_radps, std::sqrt(1e6 / store.mass_kg[1]), 1e-9 * mode.omega_radps);
  EXPECT_NE(mode.where.find("joint 0"), std::string::npos);
  EXPECT_TRUE(bonded.bonded(0, 1));
  // View after a force evaluation at 2.5 mm: ratio 2.5 / 5, yielded, ends in world.
  js.prepare(store);
  const Vec3 rest = store.position_m[1];
  test::drive(js, store, 1, rest, store.orientation[1], Vec3(0, 0, 2.5e-3));
  ASSERT_EQ(js.spring_count(), 1u);
  EXPECT_NEAR(js.spring_strain_ratio(0), 0.5, 1e-12);
  EXPECT_EQ(js.spring_status(0), SpringStatus::Yielded);
  EXPECT_EQ(js.joint_status(0), JointStatus::Yielded);
  EXPECT_NEAR((js.spring_end_b_m()[0] - js.spring_end_a_m()[0]).z(), 2.5e-3, 1e-15);
  EXPECT_NEAR(js.spring_force_N()[0], 1000.0 + 200.0 / 4e-3 * 1.5e-3, 1e-9);
  EXPECT_EQ(js.spring_joint()[0], 0);
  const JointCounts c = js.counts();
  EXPECT_EQ(c.intact + c.yielded + c.broken, 1);
  EXPECT_EQ(c.yielded, 1);
}

}  // namespace
}  // namespace fq
