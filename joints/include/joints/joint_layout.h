// Where the springs of a joint sit, and what stiffness a layout gives.
//
// Joint frame: origin at the connection point, columns (t1, t2, n) of a
// rotation matrix; n is the normal of the connection plane. Two kinds of
// springs:
//  * point springs: zero-length springs at a point of the connection plane
//    (offset (r1, r2, 0) in the joint frame). A point carries one normal
//    spring (along n) and two shear springs (along t1, t2); their
//    deformation is the joint-frame component of p_b - p_a, where p_a and p_b
//    are the attachment points carried by bodies a and b (equal at rest);
//  * links (seed 000 Fig. 4): two-point springs between a point carried by a
//    and a point carried by b, with rest length L0 and elongation |L| - L0.
//
// Effective stiffness (small displacements of body b, translation t and
// rotation phi about the joint origin, body a fixed): each spring has a
// deformation delta_i = g_i . (t, phi) with g_i = (e_i, r_i x e_i), e_i its
// direction and r_i its point on b relative to the origin, so the 6x6
// stiffness is K = sum_i k_i g_i g_i^T (layout_stiffness_matrix). For a
// point layout (r_i in the plane):
//   axial      K_n   = sum k_n
//   shear      K_t1  = K_t2 = sum k_s
//   bending    K_b1  = sum k_n r2^2   (rotation about t1: delta_n = phi1 r2)
//              K_b2  = sum k_n r1^2   (rotation about t2: delta_n = -phi2 r1)
//   torsion    K_tor = sum k_s (r1^2 + r2^2)
// Four corners at (+-c1, +-c2): K_n = 4 k_n, K_b1 = 4 k_n c2^2, K_b2 = 4 k_n c1^2,
// K_t = 4 k_s, K_tor = 4 k_s (c1^2 + c2^2).
//
// Seed 000 link system (Fig. 4; Eqs. 19-27 re-derived, the copy lost them):
// two square planes of side a, plane a at n = -l (carried by body a), plane b
// at n = 0 (carried by body b, the joint origin P at its centre); corners at
// (+-a/2, +-a/2). Twelve links:
//   1-4   axial links joining corresponding corners, length l, stiffness k
//   5-8   diagonal links crossing in the two faces normal to t2 (the x-z
//         faces of Fig. 4b), stiffness k', angle theta to n, tan(theta) = a/l
//   9-12  "shear" diagonals crossing in the two faces normal to t1,
//         stiffness k_s (the in-plane figure does not show them; k_s = 0
//         gives the seed's planar system)
// For small displacements, elongation = e_i . (displacement of its b end):
//   axial (dz):      axial links delta = dz, diagonals delta = dz cos(theta)
//                    K_n  = 4k + 4(k' + k_s) cos^2(theta)         (seed Eq. 20)
//   shear (dx):      only x-z diagonals stretch, delta = +-dx sin(theta)
//                    K_t1 = 4 k' sin^2(theta),  K_t2 = 4 k_s sin^2(theta) (Eq. 22)
//                    with the moment about P (shear-bending coupling)
//                    M_2 = -2 k' a sin(theta) cos(theta) dx
//   bending (phi2 about t2 through P): ends at x = +-a/2 move along n by
//                    -+ phi2 a/2, delta = e_n phi2 (-+a/2)
//                    K_b2 = a^2 (k + (k' + k_s) cos^2(theta))     (Eq. 26)
//   (K_b1 likewise with k' and k_s swapped in name only: a^2(k + (k'+k_s) cos^2))
// K_b2 of Eq. 26 is the stiffness against a rotation about P with the shear
// dx held at zero. Where the shear is free to follow (a member in a chain,
// loaded by a moment and the shear that goes with it), the x-z diagonals
// resist no rotation about the point where they cross, mid-gap at
// n = -l/2: a rotation about it leaves every diagonal its length
// (elongation (l sin(theta) - a cos(theta)) phi / 2 = 0). About that point
// the joint is a shear spring K_t1 and a rotational spring
//   K_b2,free = K_b2 - M_2^2 / (K_t1 dx^2) = a^2 (k + k_s cos^2(theta)),
// the stiffness to calibrate against EI / s, with the joint's centre l/2
// from P. A chain calibrated with Eq. 26's K_b2 = EI/s is too flexible by
// about the share of k' cos^2(theta) in it (a segmented-beam probe,
// 2026-11-27: an 80 mm cantilever with l = a deflected 11.5 % more than
// Timoshenko's beam at 64 segments, 2.2 % with l = a / 5).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dem_core/types.h"
#include "joints/spring_law.h"

namespace fq {

struct SpringPointDef {
  Vec3 offset_m = Vec3::Zero();  // (r1, r2, 0) in the joint frame (m)
  bool has_normal = true;
  bool has_shear = true;
  SpringDef normal;  // along n
  SpringDef shear;   // one along t1 and one along t2
};

enum class LinkRole : std::uint8_t { Axial = 0, Diagonal = 1, Shear = 2 };

struct LinkDef {
  Vec3 end_a_m = Vec3::Zero();  // end carried by body a, joint frame (m)
  Vec3 end_b_m = Vec3::Zero();  // end carried by body b, joint frame (m)
  LinkRole role = LinkRole::Axial;
  SpringDef spring;
};

struct JointLayout {
  std::vector<SpringPointDef> points;
  std::vector<LinkDef> links;
};

// One point at the joint origin.
JointLayout single_point_layout(const SpringDef& normal, const SpringDef& shear);
// Four points at (+-c1, +-c2) with c_i = fraction * half_width_i (fraction 1
// = corners of the section; kRadiusOfGyrationFraction puts them at the
// radius of gyration of a rectangle, which matches both EA and EI).
inline constexpr double kRadiusOfGyrationFraction = 0.57735026918962576;  // 1/sqrt(3)
JointLayout four_corner_layout(double half_width_1_m, double half_width_2_m, double fraction, const SpringDef& normal,
                               const SpringDef& shear);

struct LinkSystemDef {
  double side_m = 0.0;  // a (m)
  double gap_m = 0.0;   // l (m)
  SpringDef axial;      // k
  SpringDef diagonal;   // k' (faces normal to t2)
  SpringDef shear;      // k_s (faces normal to t1)
  bool with_shear_links = true;
};
JointLayout link_system_layout(const LinkSystemDef& def);

using Mat6 = Eigen::Matrix<double, 6, 6>;
// K = sum k0_i g_i g_i^T about the joint origin in the joint frame, order
// (t1, t2, n, phi1, phi2, phi_n); units N/m, N, N m/rad.
Mat6 layout_stiffness_matrix(const JointLayout& layout);

struct EffectiveStiffness {
  double axial_Npm = 0.0;
  double shear_1_Npm = 0.0;
  double shear_2_Npm = 0.0;
  double bending_1_Nmprad = 0.0;  // rotation about t1
  double bending_2_Nmprad = 0.0;  // rotation about t2
  double torsion_Nmprad = 0.0;
};
EffectiveStiffness effective_stiffness(const JointLayout& layout);

// Beam calibration (springs get reference_length_m = segment length). A
// chain of rigid elements of length L joined by point springs behaves like a
// Timoshenko beam when each joint carries the
// flexibility of one length L of beam: axial EA/L, shear kappa G A/L,
// bending E I/L, torsion G J/L. With four normal points at
// (+-sqrt(I2/A), +-sqrt(I1/A)) of stiffness k_n = EA/(4L):
//   K_n = EA/L, K_b1 = 4 k_n I1/A = E I1/L, K_b2 = E I2/L;
// with four shear points at radius rho on the diagonals, k_s = kappa G A/(4L):
//   K_t = kappa G A/L, K_tor = 4 k_s rho^2 = G J/L  =>  rho^2 = J/(kappa A).
// I1 = int r2^2 dA (bending about t1), I2 = int r1^2 dA.
// A joint that ends the chain at a fixed base (between the base and the first
// element's centre) carries half a segment: pass segment_length_m = L/2.
struct BeamSection {
  double area_m2 = 0.0;
  double inertia_1_m4 = 0.0;             // about t1
  double inertia_2_m4 = 0.0;             // about t2
  double torsion_m4 = 0.0;               // St Venant J
  double shear_coefficient = 5.0 / 6.0;  // kappa (rectangle)
};
// Rectangle of width b along t1 and depth h along t2; J from the series
// solution J = c d^3 (1/3 - 0.21 (d/c)(1 - d^4/(12 c^4))), c >= d
// (Roark), within 0.5 % of the exact value.
BeamSection rectangular_section(double width_1_m, double depth_2_m);
JointLayout calibrated_beam_layout(const BeamSection& section, double youngs_modulus_Pa, double shear_modulus_Pa,
                                   double segment_length_m, double damping_ratio = 0.0);

}  // namespace fq
