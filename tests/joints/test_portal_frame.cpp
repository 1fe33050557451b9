// One-bay portal frame of rigid members: two columns (height H) on a fixed
// ground block, one beam (span B); joints at the column bases and at the
// beam-column connections, each a four-corner spring group. All flexibility
// sits in the joints, so the lateral stiffness follows from the joints'
// rotational and shear stiffnesses (joint_layout.h: K_b = 4 k_n c^2,
// K_s = 4 k_s).
//
// Closed form (slope-deflection with rigid members, derived here). Under a
// lateral load F on the beam each column carries a shear V (2V = F by
// symmetry of the sway). A column rotates rigidly by phi; its base spring
// gives M0 = K_b0 phi, its top spring M1 = K_b1 (phi - psi) with psi the
// beam rotation. Column moment equilibrium: V H = M0 + M1. With axially
// rigid columns psi = 0 (the beam ends cannot move vertically), so
// phi = V H / (K_b0 + K_b1). The beam displacement adds the column rotation
// and the slips of the two shear spring groups:
//   Delta = V [ H^2 / (K_b0 + K_b1) + 1/K_s0 + 1/K_s1 ],  K_lat = F / Delta
//         = 2 / [ H^2 / (K_b0 + K_b1) + 1/K_s0 + 1/K_s1 ].
// Neglected: axial flexibility of the joints (k_n very large here with
// small c, so K_b stays moderate). Its effects are the beam rotation psi,
// restrained by 2 (B/2)^2 / (2/(4 k_n)) = k_n B^2 against K_b1, relative
// size K_b1/(k_n B^2) ~ 2e-5, and frame rocking from column elongation
// N = F H / B, relative size ~ 2 H^2 (2/(4 k_n)) K_lat / B^2 ~ 2e-4. The
// tolerance 1e-3 covers both.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>

#include "joint_test_util.h"

namespace fq {
namespace {

TEST(PortalFrame, LateralStiffnessMatchesSlopeDeflection) {
  const double h = 1.0, b = 2.0, sec = 0.1;
  const double kn = 1e9;                // N/m per normal spring (near-rigid axially)
  const double c0 = 0.005, c1 = 0.004;  // corner offsets of base and top joints (m)
  const double ks0 = 2.5e5, ks1 = 4e5;  // N/m per shear spring
  BodyStore store;
  BoxBodyDef g;
  g.name = "ground";
  g.size_m = Vec3(b + 1.0, 1.0, 0.1);
  g.position_m = Vec3(0.5 * b, 0, -0.05);
  g.fixed = true;
  store.add_box(g);
  for (double x : {0.0, b}) {
    BoxBodyDef col;
    col.name = "column";
    col.kind = MemberKind::Column;
    col.size_m = Vec3(sec, sec, h);
    col.position_m = Vec3(x, 0, 0.5 * h);
    store.add_box(col);
  }
  BoxBodyDef beam;
  beam.name = "beam";
  beam.kind = MemberKind::Beam;
  beam.size_m = Vec3(b, sec, sec);
  beam.position_m = Vec3(0.5 * b, 0, h);
  store.add_box(beam);
  store.update_rotations();

  BondedPairs bonded;
  JointSystem js(&bonded);
  const JointLayout base = four_corner_layout(c0, c0, 1.0, linear_spring(kn), linear_spring(ks0));
  const JointLayout top = four_corner_layout(c1, c1, 1.0, linear_spring(kn), linear_spring(ks1));
  for (int i = 0; i < 2; ++i) {
    JointDef d;
    d.body_a = 0;
    d.body_b = 1 + i;
    d.origin_m = Vec3(i * b, 0, 0);
    d.layout = base;
    js.add_joint(store, d);
    d.body_a = 1 + i;
    d.body_b = 3;
    d.origin_m = Vec3(i * b, 0, h);
    d.layout = top;
    js.add_joint(store, d);
  }
  js.prepare(store);
  const Eigen::MatrixXd k = test::system_stiffness(js, store, 1e-9, 1e-9);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(k.rows());
  f(12) = 1.0;  // unit lateral load on the beam (third free body), at its centre (height H)
  const Eigen::VectorXd u = k.partialPivLu().solve(f);
  const double k_lat = 1.0 / u(12);

  const double kb0 = 4 * kn * c0 * c0, kb1 = 4 * kn * c1 * c1;
  const double k_closed = 2.0 / (h * h / (kb0 + kb1) + 1.0 / (4 * ks0) + 1.0 / (4 * ks1));
  EXPECT_NEAR(k_lat, k_closed, 1e-3 * k_closed);
  std::printf("portal frame: lateral stiffness %.6e N/m, closed form %.6e N/m, relative difference %.2e\n", k_lat,
              k_closed, k_lat / k_closed - 1.0);
  // Both columns lean by the same angle; the beam stays level (psi ~ 0).
  EXPECT_NEAR(u(4), u(10), 1e-6 * std::abs(u(4)));
  EXPECT_LT(std::abs(u(16)), 1e-3 * std::abs(u(4)));
}

}  // namespace
}  // namespace fq
