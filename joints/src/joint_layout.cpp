#include "joints/joint_layout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fq {

JointLayout single_point_layout(const SpringDef& normal, const SpringDef& shear) {
  JointLayout l;
  SpringPointDef p;
  p.normal = normal;
  p.shear = shear;
  l.points.push_back(p);
  return l;
}

JointLayout four_corner_layout(double half_width_1_m, double half_width_2_m, double fraction, const SpringDef& normal,
                               const SpringDef& shear) {
  if (!(half_width_1_m > 0.0) || !(half_width_2_m > 0.0) || !(fraction > 0.0))
    throw std::invalid_argument("four_corner_layout: half widths (m) and fraction must be positive");
  JointLayout l;
  const double c1 = fraction * half_width_1_m, c2 = fraction * half_width_2_m;
  for (int i = 0; i < 4; ++i) {
    SpringPointDef p;
    p.offset_m = Vec3((i & 1) ? c1 : -c1, (i & 2) ? c2 : -c2, 0.0);
    p.normal = normal;
    p.shear = shear;
    l.points.push_back(p);
  }
  return l;
}

JointLayout link_system_layout(const LinkSystemDef& def) {
  if (!(def.side_m > 0.0) || !(def.gap_m > 0.0))
    throw std::invalid_argument("link_system_layout: side_m and gap_m must be positive lengths (m)");
  JointLayout l;
  const double h = 0.5 * def.side_m, g = def.gap_m;
  auto add = [&](Vec3 a, Vec3 b, LinkRole role, const SpringDef& s) {
    LinkDef link;
    link.end_a_m = a;
    link.end_b_m = b;
    link.role = role;
    link.spring = s;
    l.links.push_back(link);
  };
  // 1-4 axial: corner to corner.
  for (int i = 0; i < 4; ++i) {
    const double x = (i & 1) ? h : -h, y = (i & 2) ? h : -h;
    add(Vec3(x, y, -g), Vec3(x, y, 0.0), LinkRole::Axial, def.axial);
  }
  // 5-8 diagonals crossing in the faces y = +-h (normal to t2).
  for (double y : {-h, h}) {
    add(Vec3(-h, y, -g), Vec3(h, y, 0.0), LinkRole::Diagonal, def.diagonal);
    add(Vec3(h, y, -g), Vec3(-h, y, 0.0), LinkRole::Diagonal, def.diagonal);
  }
  // 9-12 diagonals crossing in the faces x = +-h (normal to t1).
  if (def.with_shear_links) {
    for (double x : {-h, h}) {
      add(Vec3(x, -h, -g), Vec3(x, h, 0.0), LinkRole::Shear, def.shear);
      add(Vec3(x, h, -g), Vec3(x, -h, 0.0), LinkRole::Shear, def.shear);
    }
  }
  return l;
}

namespace {

void add_rank_one(Mat6& k, double stiffness, const Vec3& e, const Vec3& r) {
  Eigen::Matrix<double, 6, 1> g;
  g.head<3>() = e;
  g.tail<3>() = r.cross(e);
  k += stiffness * g * g.transpose();
}

}  // namespace

Mat6 layout_stiffness_matrix(const JointLayout& layout) {
  Mat6 k = Mat6::Zero();
  for (const SpringPointDef& p : layout.points) {
    if (p.has_normal) add_rank_one(k, initial_stiffness_Npm(p.normal), Vec3::UnitZ(), p.offset_m);
    if (p.has_shear) {
      const double ks = initial_stiffness_Npm(p.shear);
      add_rank_one(k, ks, Vec3::UnitX(), p.offset_m);
      add_rank_one(k, ks, Vec3::UnitY(), p.offset_m);
    }
  }
  for (const LinkDef& l : layout.links) {
    const Vec3 d = l.end_b_m - l.end_a_m;
    add_rank_one(k, initial_stiffness_Npm(l.spring), d.normalized(), l.end_b_m);
  }
  return k;
}

EffectiveStiffness effective_stiffness(const JointLayout& layout) {
  const Mat6 k = layout_stiffness_matrix(layout);
  EffectiveStiffness s;
  s.shear_1_Npm = k(0, 0);
  s.shear_2_Npm = k(1, 1);
  s.axial_Npm = k(2, 2);
  s.bending_1_Nmprad = k(3, 3);
  s.bending_2_Nmprad = k(4, 4);
  s.torsion_Nmprad = k(5, 5);
  return s;
}

BeamSection rectangular_section(double width_1_m, double depth_2_m) {
  if (!(width_1_m > 0.0) || !(depth_2_m > 0.0))
    throw std::invalid_argument("rectangular_section: width and depth must be positive lengths (m)");
  BeamSection s;
  const double b = width_1_m, h = depth_2_m;
  s.area_m2 = b * h;
  s.inertia_1_m4 = b * h * h * h / 12.0;
  s.inertia_2_m4 = h * b * b * b / 12.0;
  const double c = std::max(b, h), d = std::min(b, h);
  s.torsion_m4 = c * d * d * d * (1.0 / 3.0 - 0.21 * (d / c) * (1.0 - std::pow(d / c, 4) / 12.0));
  return s;
}

JointLayout calibrated_beam_layout(const BeamSection& s, double e_Pa, double g_Pa, double segment_length_m,
                                   double damping_ratio) {
  if (!(s.area_m2 > 0.0) || !(s.inertia_1_m4 > 0.0) || !(s.inertia_2_m4 > 0.0) || !(s.torsion_m4 > 0.0) ||
      !(s.shear_coefficient > 0.0))
    throw std::invalid_argument(
        "calibrated_beam_layout: section area, inertias, torsion constant and kappa must be > 0");
  if (!(e_Pa > 0.0) || !(g_Pa > 0.0) || !(segment_length_m > 0.0))
    throw std::invalid_argument("calibrated_beam_layout: E (Pa), G (Pa) and segment_length_m must be > 0");
  const double l = segment_length_m;
  // Strains (for the strain-limit fracture criterion and the output ratio)
  // refer to the segment the joint stands for.
  SpringDef normal = linear_spring(e_Pa * s.area_m2 / (4.0 * l), damping_ratio);
  SpringDef shear = linear_spring(s.shear_coefficient * g_Pa * s.area_m2 / (4.0 * l), damping_ratio);
  normal.reference_length_m = shear.reference_length_m = l;
  const double c1 = std::sqrt(s.inertia_2_m4 / s.area_m2), c2 = std::sqrt(s.inertia_1_m4 / s.area_m2);
  const double rho = std::sqrt(s.torsion_m4 / (s.shear_coefficient * s.area_m2));
  const double q = rho / std::sqrt(2.0);
  JointLayout layout;
  for (int i = 0; i < 4; ++i) {
    SpringPointDef p;
    p.offset_m = Vec3((i & 1) ? c1 : -c1, (i & 2) ? c2 : -c2, 0.0);
    p.has_shear = false;
    p.normal = normal;
    layout.points.push_back(p);
  }
  for (int i = 0; i < 4; ++i) {
    SpringPointDef p;
    p.offset_m = Vec3((i & 1) ? q : -q, (i & 2) ? q : -q, 0.0);
    p.has_normal = false;
    p.shear = shear;
    layout.points.push_back(p);
  }
  return layout;
}

}  // namespace fq
