// Small helpers shared by the joints tests: a fixed body and a free body
// joined at the world origin (joint frame = world axes, n = z), driven by
// prescribing the free body's pose and reading the force on it.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "dem_core/body_store.h"
#include "dem_core/bonded_pairs.h"
#include "dem_core/simulation.h"
#include "joints/curee_law.h"
#include "joints/joint_system.h"

namespace fq::test {

// A CUREE timber connection (Folz & Filiatrault's shape ratios r1-r4,
// alpha, beta) at the given initial stiffness (N/m), force intercepts (N)
// and ultimate displacement (m).
inline CureeParams timber_curee(double K0_Npm, double F0_N, double F1_N, double delta_u_m) {
  CureeParams c;
  c.K0_Npm = K0_Npm;
  c.F0_N = F0_N;
  c.F1_N = F1_N;
  c.r1 = 0.05;
  c.r2 = -0.1;
  c.r3 = 1.1;
  c.r4 = 0.02;
  c.delta_u_m = delta_u_m;
  c.alpha = 0.8;
  c.beta = 1.1;
  return c;
}

inline BodyStore two_boxes(double edge_m = 0.1, double density = 500.0) {
  BodyStore store;
  BoxBodyDef a;
  a.name = "fixed";
  a.size_m = Vec3::Constant(edge_m);
  a.density_kg_per_m3 = density;
  a.position_m = Vec3(0, 0, -0.5 * edge_m);
  a.fixed = true;
  store.add_box(a);
  BoxBodyDef b = a;
  b.name = "free";
  b.fixed = false;
  b.position_m = Vec3(0, 0, 0.5 * edge_m);
  store.add_box(b);
  store.update_rotations();
  return store;
}

// Places body `b` at rest pose + translation `disp_m` and rotation `phi_rad`
// (rotation vector) about the world point `centre_m`, evaluates the joint
// forces and returns (force on b, torque on b about centre_m).
struct Wrench {
  Vec3 force_N = Vec3::Zero();
  Vec3 torque_Nm = Vec3::Zero();
};
inline Wrench drive(JointSystem& js, BodyStore& store, BodyId b, const Vec3& rest_pos, const Quat& rest_q,
                    const Vec3& disp_m, const Vec3& phi_rad = Vec3::Zero(), const Vec3& centre_m = Vec3::Zero(),
                    std::int64_t step = 0, double dt_s = 1e-3) {
  const double angle = phi_rad.norm();
  const Quat dq = angle > 0.0 ? Quat(Eigen::AngleAxisd(angle, phi_rad / angle)) : Quat::Identity();
  store.position_m[b] = centre_m + dq * (rest_pos - centre_m) + disp_m;
  store.orientation[b] = (dq * rest_q).normalized();
  store.update_rotations();
  for (std::size_t i = 0; i < store.size(); ++i) {
    store.force_N[i].setZero();
    store.torque_Nm[i].setZero();
  }
  StepInfo info{step, double(step) * dt_s, dt_s};
  js.accumulate_forces(store, info);
  Wrench w;
  w.force_N = store.force_N[b];
  w.torque_Nm = store.torque_Nm[b] + (store.position_m[b] - centre_m).cross(store.force_N[b]);
  return w;
}

// Area enclosed by a sampled closed F-delta path (shoelace formula), positive
// when the loop runs clockwise in the (delta, F) plane, as a dissipative
// force-deformation loop does.
inline double shoelace_area(const std::vector<double>& x, const std::vector<double>& y) {
  double a = 0.0;
  const std::size_t n = x.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = (i + 1) % n;
    a += x[i] * y[k] - x[k] * y[i];
  }
  return -0.5 * a;
}

}  // namespace fq::test

namespace fq::test {

// A vertical chain: a fixed base block below z = 0 and n rigid boxes of
// section b x h (b along x) and length L = length/n stacked along z, joined
// by joints with the given layouts (joint 0 at the base, z = 0; joint i at
// z = i L). Joint frames: t1 = x, t2 = y, n = z.
struct ChainSpec {
  int n = 10;
  double length_m = 1.0;
  double width_m = 0.02;  // b, along x
  double depth_m = 0.02;  // h, along y
  double density_kg_per_m3 = 500.0;
};
inline BodyStore chain_bodies(const ChainSpec& c) {
  BodyStore store;
  BoxBodyDef base;
  base.name = "base";
  base.size_m = Vec3(c.width_m, c.depth_m, 0.02);
  base.position_m = Vec3(0, 0, -0.01);
  base.fixed = true;
  base.density_kg_per_m3 = c.density_kg_per_m3;
  store.add_box(base);
  const double l = c.length_m / c.n;
  for (int i = 0; i < c.n; ++i) {
    BoxBodyDef e;
    e.name = "element";
    e.size_m = Vec3(c.width_m, c.depth_m, l);
    e.position_m = Vec3(0, 0, (i + 0.5) * l);
    e.density_kg_per_m3 = c.density_kg_per_m3;
    store.add_box(e);
  }
  store.update_rotations();
  return store;
}
// layout_of(i) gives the layout of joint i (0 = base joint).
template <class LayoutOf>
void add_chain_joints(JointSystem& js, const BodyStore& store, const ChainSpec& c, LayoutOf layout_of,
                      JointBreakDef fracture = {}) {
  const double l = c.length_m / c.n;
  for (int i = 0; i < c.n; ++i) {
    JointDef d;
    d.body_a = i;  // base is body 0, element i is body i + 1
    d.body_b = i + 1;
    d.origin_m = Vec3(0, 0, i * l);
    d.layout = layout_of(i);
    d.fracture = fracture;
    js.add_joint(store, d);
  }
}

// An irregular vertical chain for stable-time-step studies: a fixed base
// and `links` boxes whose proportions change from link to link (so that no
// two modes coincide), joined by four-corner linear joints whose normal
// stiffness grows along the chain (2e4 N/m times the joint number; shear
// 5e4 N/m) with the given damping ratio.
inline BodyStore irregular_chain_bodies(int links) {
  BodyStore store;
  BoxBodyDef base;
  base.name = "base";
  base.size_m = Vec3(0.05, 0.05, 0.02);
  base.density_kg_per_m3 = 500;
  base.position_m = Vec3(0, 0, -0.01);
  base.fixed = true;
  store.add_box(base);
  double z = 0.0;
  for (int i = 0; i < links; ++i) {
    BoxBodyDef b;
    b.name = "link_" + std::to_string(i);
    const double h = 0.1 + 0.02 * i;
    b.size_m = Vec3(0.02 + 0.002 * i, 0.03, h);
    b.density_kg_per_m3 = 500;
    b.position_m = Vec3(0, 0, z + 0.5 * h);
    z += h;
    store.add_box(b);
  }
  store.update_rotations();
  return store;
}
inline void add_irregular_chain_joints(JointSystem& js, const BodyStore& store, double damping_ratio = 0.0) {
  double z = 0.0;
  for (BodyId b = 1; b < BodyId(store.size()); ++b) {
    JointDef d;
    d.body_a = b - 1;
    d.body_b = b;
    d.origin_m = Vec3(0, 0, z);
    d.layout = four_corner_layout(0.01, 0.015, 1.0, linear_spring(2e4 * double(b), damping_ratio),
                                  linear_spring(5e4, damping_ratio));
    js.add_joint(store, d);
    z += 2.0 * store.half_extents_m[b].z();
  }
}
// Small random velocities and spins of every free body (fixed seed), to
// excite all modes of a scene at once.
inline void set_small_random_motion(BodyStore& store) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (BodyId b = 0; b < BodyId(store.size()); ++b) {
    if (store.is_fixed[b]) continue;
    store.velocity_mps[b] = 1e-4 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 w = 1e-3 * Vec3(u(rng), u(rng), u(rng));
    const Mat3& r = store.rotation[b];
    store.angular_velocity_radps[b] = w;
    store.angular_momentum_Nms[b] = r * store.principal_inertia_kgm2[b].asDiagonal() * (r.transpose() * w);
  }
}

// Largest distance (m) of a body centre from where it stood before the
// first of up to `steps` steps of `sim`; returns early once it passes
// stop_m, and infinity when the step loop stops as unstable.
inline double largest_displacement(Simulation& sim, int steps, double stop_m = 1.0) {
  const std::vector<Vec3> start = sim.bodies().position_m;
  double amplitude = 0.0;
  for (int s = 0; s < steps; ++s) {
    if (!sim.step()) return std::numeric_limits<double>::infinity();
    for (std::size_t b = 0; b < start.size(); ++b)
      amplitude = std::max(amplitude, (sim.bodies().position_m[b] - start[b]).norm());
    if (amplitude > stop_m) return amplitude;
  }
  return amplitude;
}

// `steps` central-difference steps of dt_s without gravity.
inline SimulationSettings weightless_steps(double dt_s, int steps) {
  SimulationSettings settings;
  settings.dt_s = dt_s;
  settings.duration_s = dt_s * steps;
  settings.gravity_mps2 = Vec3::Zero();
  return settings;
}

// The 5-box irregular chain (no gravity) with small random velocities
// (set_small_random_motion) and the given spring-level damping ratio, run
// `steps` central-difference steps at dt_s: largest_displacement.
inline double chain_amplitude(double dt_s, int steps, double damping_ratio = 0.0) {
  BodyStore store = irregular_chain_bodies(5);
  set_small_random_motion(store);
  Simulation sim(std::move(store), weightless_steps(dt_s, steps));
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs());
  add_irregular_chain_joints(*js, sim.bodies(), damping_ratio);
  sim.add_force_provider(std::move(js));
  return largest_displacement(sim, steps);
}

// Finite-difference stiffness (-dQ/du) of all free bodies, Q = (force,
// torque about the centre of mass), u = (translation, world rotation vector);
// central differences with steps h_m, h_rad.
inline Eigen::MatrixXd system_stiffness(JointSystem& js, BodyStore& store, double h_m, double h_rad) {
  std::vector<BodyId> free;
  for (std::size_t i = 0; i < store.size(); ++i)
    if (!store.is_fixed[i]) free.push_back(BodyId(i));
  const auto n = Eigen::Index(6 * free.size());
  Eigen::MatrixXd k(n, n);
  const std::vector<Vec3> pos0 = store.position_m;
  const std::vector<Quat> q0 = store.orientation;
  auto eval = [&](Eigen::VectorXd& out) {
    store.update_rotations();
    for (std::size_t i = 0; i < store.size(); ++i) {
      store.force_N[i].setZero();
      store.torque_Nm[i].setZero();
    }
    js.accumulate_forces(store, StepInfo{0, 0.0, 1e-3});
    for (std::size_t f = 0; f < free.size(); ++f) {
      out.segment<3>(Eigen::Index(6 * f)) = store.force_N[free[f]];
      out.segment<3>(Eigen::Index(6 * f + 3)) = store.torque_Nm[free[f]];
    }
  };
  Eigen::VectorXd qp(n), qm(n);
  for (Eigen::Index c = 0; c < n; ++c) {
    const BodyId b = free[std::size_t(c / 6)];
    const int dof = int(c % 6);
    for (int sgn : {1, -1}) {
      store.position_m = pos0;
      store.orientation = q0;
      if (dof < 3) {
        store.position_m[b][dof] += sgn * h_m;
      } else {
        Vec3 axis = Vec3::Zero();
        axis[dof - 3] = 1.0;
        store.orientation[b] = (Quat(Eigen::AngleAxisd(sgn * h_rad, axis)) * q0[b]).normalized();
      }
      eval(sgn > 0 ? qp : qm);
    }
    k.col(c) = -(qp - qm) / (2.0 * (dof < 3 ? h_m : h_rad));
  }
  store.position_m = pos0;
  store.orientation = q0;
  store.update_rotations();
  return k;
}

}  // namespace fq::test

namespace fq::test {

// What a run with joints leaves behind, for tests that require two runs to
// agree bit for bit (thread counts, the lane kernel against the general code).
struct JointRunOutcome {
  std::vector<Event> events;
  std::vector<Vec3> position, velocity, angular_velocity;
  std::vector<Quat> orientation;
  std::vector<double> spring_delta, spring_force;
  std::vector<double> joint_viscous_J;  // per joint: a total hides a last-bit change of one term
  std::vector<SpringStatus> spring_status;
  double elastic_J = 0.0, plastic_J = 0.0, viscous_J = 0.0;
  JointCounts counts;
};

inline JointRunOutcome capture_outcome(const Simulation& sim, const JointSystem& joints) {
  JointRunOutcome o;
  o.events = sim.events().all();
  o.position = sim.bodies().position_m;
  o.velocity = sim.bodies().velocity_mps;
  o.angular_velocity = sim.bodies().angular_velocity_radps;
  o.orientation = sim.bodies().orientation;
  o.spring_delta = joints.spring_deformation_m();
  o.spring_force = joints.spring_force_N();
  for (std::size_t s = 0; s < joints.spring_count(); ++s) o.spring_status.push_back(joints.spring_status(s));
  for (std::size_t j = 0; j < joints.joint_count(); ++j) o.joint_viscous_J.push_back(joints.joint_viscous_J(j));
  EnergyLedger books;
  joints.report_energy(books);
  o.elastic_J = books.elastic_J;
  o.plastic_J = books.dissipated_plastic_J;
  o.viscous_J = books.dissipated_viscous_J;
  o.counts = joints.counts();
  return o;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(T) * a.size()) == 0;
}
inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// Same events (every field), body states, spring states and energy books, bit for bit.
inline void expect_identical(const JointRunOutcome& a, const JointRunOutcome& b) {
  ASSERT_EQ(a.events.size(), b.events.size());
  for (std::size_t i = 0; i < a.events.size(); ++i) {
    const Event &x = a.events[i], &y = b.events[i];
    EXPECT_EQ(x.step, y.step);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.joint_id, y.joint_id);
    EXPECT_EQ(x.spring_index, y.spring_index);
    EXPECT_STREQ(x.mode, y.mode);
    EXPECT_TRUE(same_bits(x.force_N, y.force_N)) << "event " << i;
    EXPECT_EQ(std::memcmp(x.position_m.data(), y.position_m.data(), sizeof(double) * 3), 0) << "event " << i;
  }
  EXPECT_TRUE(same_bits(a.position, b.position));
  EXPECT_TRUE(same_bits(a.velocity, b.velocity));
  EXPECT_TRUE(same_bits(a.angular_velocity, b.angular_velocity));
  EXPECT_TRUE(same_bits(a.orientation, b.orientation));
  EXPECT_TRUE(same_bits(a.spring_delta, b.spring_delta));
  EXPECT_TRUE(same_bits(a.spring_force, b.spring_force));
  EXPECT_TRUE(a.spring_status == b.spring_status);
  EXPECT_TRUE(same_bits(a.elastic_J, b.elastic_J));
  EXPECT_TRUE(same_bits(a.plastic_J, b.plastic_J));
  EXPECT_TRUE(same_bits(a.viscous_J, b.viscous_J));
  EXPECT_TRUE(same_bits(a.joint_viscous_J, b.joint_viscous_J));
  EXPECT_EQ(a.counts.broken, b.counts.broken);
  EXPECT_EQ(a.counts.yielded, b.counts.yielded);
}

}  // namespace fq::test
