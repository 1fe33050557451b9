// The lane kernels of the joint system (joint_system.h, "Lane kernel"),
// written once and compiled once per SIMD form (dem_core/lanes.h): by
// joint_lanes_sse2.cpp for the x86-64 baseline, by joint_lanes_avx2.cpp
// with -mavx2 and by joint_lanes_avx512vl.cpp with -mavx512f -mavx512vl.
// FQ_LANE_KERNEL(name) gives each form's member function its own name
// (update_lane_frames_sse2_, ..._avx2_, ..._avx512vl_); JointSystem picks
// one at prepare time (dem_core/lane_isa.h). No include guard: this file is
// the body of those translation units and is included by nothing else.
//
// What the kernels compute is what joint_step_ and update_joint_frame_
// compute, with the same expressions in the same order per point, so every
// result is bitwise the same in both forms (the test JointLanes.* runs
// each form against the general code). What they save: the per-spring law
// path (flags, law batch, parameter lookups) for the springs that stay on
// their initial linear branch, which is most springs at most steps, and the
// loop set-up of the generic point chunks.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <type_traits>

#include "dem_core/quat_lanes.h"
#include "joints/joint_system.h"

#ifndef FQ_LANE_KERNEL
#error "define FQ_LANE_KERNEL(name) before including joint_lane_kernels.h"
#endif

namespace fq {

using lanes::v4d;
using lanes::v4m;

// The frames of the lane joints among [first, last), four joints at a time:
// update_joint_frame_ in lanes (dem_core/quat_lanes.h gives Eigen's bits per lane).
void JointSystem::FQ_LANE_KERNEL(update_lane_frames_)(const BodyStore& bodies, std::size_t first, std::size_t last) {
  std::size_t group[lanes::kWidth];
  int n = 0;
  auto frames = [&]() {
    const Quat *qa[lanes::kWidth], *ja[lanes::kWidth], *qb[lanes::kWidth], *jb[lanes::kWidth];
    for (int k = 0; k < n; ++k) {
      const std::size_t j = group[k];
      qa[k] = &bodies.orientation[joint_body_a_[j]];
      qb[k] = &bodies.orientation[joint_body_b_[j]];
      ja[k] = &joint_frame_a_[j];
      jb[k] = &joint_frame_b_[j];
    }
    const lanes::QuatLanes fa = lanes::product(lanes::load_quats(qa, n), lanes::load_quats(ja, n));
    // The sum of the two, unturned: update_joint_frame_ says why.
    const lanes::QuatLanes fb = lanes::product(lanes::load_quats(qb, n), lanes::load_quats(jb, n));
    v4d m[9];
    lanes::to_rotation_matrix(lanes::normalized({fa.x + fb.x, fa.y + fb.y, fa.z + fb.z, fa.w + fb.w}), m);
    // Lanes back to one matrix per joint: after the two transposes, m[k]
    // holds entries 0-3 of joint k's matrix and m[4 + k] entries 4-7.
    lanes::transpose(m[0], m[1], m[2], m[3]);
    lanes::transpose(m[4], m[5], m[6], m[7]);
    double entry_8[lanes::kWidth];
    lanes::store(entry_8, m[8]);
    for (int k = 0; k < n; ++k) {
      double* frame = joint_frame_world_[group[k]].data();
      lanes::store(frame, m[k]);
      lanes::store(frame + 4, m[4 + k]);
      frame[8] = entry_8[k];
    }
    n = 0;
  };
  for (std::size_t j = first; j < last; ++j) {
    if (!joint_lanes_[j] || joint_broken_[j]) continue;
    group[n++] = j;
    if (n == lanes::kWidth) frames();
  }
  if (n > 0) frames();
}

namespace {

// Up to four consecutive points [first, first + n) of one joint: their
// values in a per-point column as lanes (zeros past n), and back. Full
// (n = 4, known when compiled) loads and stores four wide without a test.
template <bool Full>
struct PointGroup {
  std::size_t first;
  int n;
  [[gnu::always_inline]] v4d in(const std::vector<double>& column) const { return in(column.data()); }
  [[gnu::always_inline]] v4d in(const double* column) const {
    if constexpr (Full) return lanes::load(column + first);
    return lanes::load_partial(column + first, n);
  }
  [[gnu::always_inline]] void out(std::vector<double>& column, v4d v) const {
    if constexpr (Full)
      lanes::store(column.data() + first, v);
    else
      lanes::store_partial(column.data() + first, v, n);
  }
};

// f(PointGroup) for the groups of four points of [first, last): full groups,
// then a partial one if the count is not a multiple of four.
template <class F>
[[gnu::always_inline]] inline void for_each_point_group(std::size_t first, std::size_t last, F&& f) {
  for (std::size_t group = first; group < last; group += lanes::kWidth) {
    const int n = int(std::min<std::size_t>(lanes::kWidth, last - group));
    if (n == lanes::kWidth)
      f(PointGroup<true>{group, n});
    else
      f(PointGroup<false>{group, n});
  }
}

// A spring on the initial linear branch of its law, in lanes: the law
// force F* = k0 delta (trilinear_trial with a zero offset), and in `ok`
// the lanes where it holds: not past the ultimate deformation
// (trilinear_past_ultimate) and inside the hardening bounds
// (TrilinearTrial::inside), with the law's own expressions.
[[gnu::always_inline]] inline v4d initial_branch(const double* law, v4d delta, v4m& ok) {
  // law: k0_t, k0_c, k1_t, k1_c, fy_t, fy_c, dy_t, dy_c, du_t, du_c (LaneLaw)
  const v4m past = (delta > law[8]) | (delta < -law[9]);
  const v4d force = lanes::select(delta >= 0.0, lanes::splat(law[0]), lanes::splat(law[1])) * delta;
  const v4d lower = -law[5] + law[3] * (delta + law[7]);
  const v4d upper = law[4] + law[2] * (delta - law[6]);
  ok = lanes::and_not(ok, past | (force > upper) | (force < lower));
  return force;
}

}  // namespace

// joint_step_ for a lane joint (joint_system.h): the same quantities in the
// same order per point, four points per vector.
void JointSystem::FQ_LANE_KERNEL(joint_step_lanes_)(const BodyStore& bodies, std::size_t j) {
  const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
  // The loop invariants are read where they are used, as broadcasts from
  // the body arrays and the frame (update_lane_frames_). Copies into local
  // arrays cost a load and a store per scalar, about 100 of the 723
  // instructions per joint (callgrind, 1e3-body lattice), for values that a
  // four-point joint uses once or twice. Matrices are column-major (m[3 c +
  // r] is row r of column c), the frame's columns t1, t2, n.
  const double* const Ra = bodies.rotation[a].data();
  const double* const Rb = bodies.rotation[b].data();
  const double* const F = joint_frame_world_[j].data();
  const double* const Xa = bodies.position_m[a].data();
  const double* const Xb = bodies.position_m[b].data();
  const double* const Va = bodies.velocity_mps[a].data();
  const double* const Vb = bodies.velocity_mps[b].data();
  const double* const Wa = bodies.angular_velocity_radps[a].data();
  const double* const Wb = bodies.angular_velocity_radps[b].data();
  // What every joint of its type shares (LaneType, joint_system.h).
  const LaneType& type = lane_types_[std::size_t(joint_lane_type_[j])];
  const double* law_n = &lane_laws_[std::size_t(type.law_n)].k0_t_Npm;
  const double* law_s = &lane_laws_[std::size_t(type.law_s)].k0_t_Npm;
  const double c_n = type.c_n_Nspm, c_s = type.c_s_Nspm;

  const bool strain_limit = type.fracture.criterion == BreakCriterion::StrainLimit;
  JointSpringSummary sum;
  sum.springs = type.springs;
  sum.normal_springs = type.normal_springs;
  bool any_pending = false;
  // Sums over the points, in point order per component: lanes of
  // (F_x, F_y, F_z, T_x) and (T_y, T_z, M_y, M_z) of the force and torque
  // on a and of the dashpot moment about x_a, and (Fd_x, Fd_y, Fd_z, M_x)
  // of the dashpot force.
  v4d sum_force_torque = lanes::splat(0.0), sum_torque_yz = lanes::splat(0.0), sum_dashpot = lanes::splat(0.0);

  const auto first_point = std::size_t(joint_first_point_[j]), last_point = std::size_t(joint_first_point_[j + 1]);
  // The type's attachments, indexed like the joint's point columns.
  const std::ptrdiff_t attach_shift = std::ptrdiff_t(type.first_attach) - std::ptrdiff_t(first_point);
  const double* const la_x = lane_attach_a_m_.x.data() + attach_shift;
  const double* const la_y = lane_attach_a_m_.y.data() + attach_shift;
  const double* const la_z = lane_attach_a_m_.z.data() + attach_shift;
  const double* const lb_x = lane_attach_b_m_.x.data() + attach_shift;
  const double* const lb_y = lane_attach_b_m_.y.data() + attach_shift;
  const double* const lb_z = lane_attach_b_m_.z.data() + attach_shift;
  // One group of up to four points (PointGroup); compiled twice, for a full
  // group (every load and store four wide, no test of n at each) and for
  // the last group of a joint whose point count is not a multiple of four.
  auto group_step = [&](auto points) __attribute__((always_inline)) {
    constexpr bool full = std::is_same_v<decltype(points), PointGroup<true>>;
    const std::size_t group = points.first;
    const int n = full ? lanes::kWidth : points.n;  // a constant for the compiler when full
    // Stage 1: ends, arm of end a, separation d = p_b - p_a, relative
    // velocity, and d and v_rel along the joint axes (joint_step_).
    const v4d la[3] = {points.in(la_x), points.in(la_y), points.in(la_z)};
    const v4d lb[3] = {points.in(lb_x), points.in(lb_y), points.in(lb_z)};
    v4d am[3], bm[3], d[3];
    for (int r = 0; r < 3; ++r) {
      am[r] = Ra[r] * la[0] + Ra[3 + r] * la[1] + Ra[6 + r] * la[2];
      bm[r] = Rb[r] * lb[0] + Rb[3 + r] * lb[1] + Rb[6 + r] * lb[2];
      const v4d pa = Xa[r] + am[r], pb = Xb[r] + bm[r];
      d[r] = pb - pa;
      points.out(r == 0 ? point_end_a_m_.x : r == 1 ? point_end_a_m_.y : point_end_a_m_.z, pa);
      points.out(r == 0 ? point_end_b_m_.x : r == 1 ? point_end_b_m_.y : point_end_b_m_.z, pb);
    }
    const v4d vrel[3] = {
        (Vb[0] + Wb[1] * bm[2] - Wb[2] * bm[1]) - (Va[0] + Wa[1] * am[2] - Wa[2] * am[1]),
        (Vb[1] + Wb[2] * bm[0] - Wb[0] * bm[2]) - (Va[1] + Wa[2] * am[0] - Wa[0] * am[2]),
        (Vb[2] + Wb[0] * bm[1] - Wb[1] * bm[0]) - (Va[2] + Wa[0] * am[1] - Wa[1] * am[0])};
    v4d d_axis[3], v_axis[3];
    for (int c = 0; c < 3; ++c) {
      d_axis[c] = F[3 * c] * d[0] + F[3 * c + 1] * d[1] + F[3 * c + 2] * d[2];
      v_axis[c] = F[3 * c] * vrel[0] + F[3 * c + 1] * vrel[1] + F[3 * c + 2] * vrel[2];
    }

    // Stage 2: the laws. In lanes: the initial branch of each spring (the
    // normal along axis 2, the shear springs along axes 0 and 1), valid
    // where the point is plain and every spring stays on it; the other
    // points run the general spring code.
    v4m ok = lanes::mask(point_plain_[group] != 0, n > 1 && point_plain_[group + 1] != 0,
                         n > 2 && point_plain_[group + 2] != 0, n > 3 && point_plain_[group + 3] != 0);
    const v4d law_force[3] = {initial_branch(law_s, d_axis[0], ok), initial_branch(law_s, d_axis[1], ok),
                              initial_branch(law_n, d_axis[2], ok)};
    const v4d dashpot_force[3] = {c_s * v_axis[0], c_s * v_axis[1], c_n * v_axis[2]};
    // f_axis = 0 + (f_law + f_dashpot), fd_axis = 0 + f_dashpot: the sums
    // of joint_step_ over the one spring per axis.
    v4d fa[3], fda[3];
    for (int c = 0; c < 3; ++c) {
      fa[c] = 0.0 + (law_force[c] + dashpot_force[c]);
      fda[c] = 0.0 + dashpot_force[c];
    }
    if (lanes::all_of(ok) && !strain_limit) {
      // Every point of the group on its initial branches (the usual case;
      // all_of(ok) implies a full group, the mask is false past n): the
      // springs' deformation, rate and law force, normal first, written
      // from the lanes as records of three, and the counts of count_alive_
      // for the whole group at once (this branch is 2-5 % of the joint
      // stage faster than the per-lane one).
      const auto s0 = std::size_t(point_first_[group]);
      lanes::store_interleaved3(delta_m_.data() + s0, d_axis[2], d_axis[0], d_axis[1]);
      lanes::store_interleaved3(rate_mps_.data() + s0, v_axis[2], v_axis[0], v_axis[1]);
      lanes::store_interleaved3(law_force_N_.data() + s0, law_force[2], law_force[0], law_force[1]);
      sum.springs_alive += 3 * lanes::kWidth;
      sum.normal_springs_alive += lanes::kWidth;
    } else {
      double f_axis[3][lanes::kWidth], fd_axis[3][lanes::kWidth];
      double delta_of[3][lanes::kWidth], rate_of[3][lanes::kWidth], law_force_of[3][lanes::kWidth];
      for (int c = 0; c < 3; ++c) {
        lanes::store(f_axis[c], fa[c]);
        lanes::store(fd_axis[c], fda[c]);
        lanes::store(delta_of[c], d_axis[c]);
        lanes::store(rate_of[c], v_axis[c]);
        lanes::store(law_force_of[c], law_force[c]);
      }
      for (int i = 0; i < n; ++i) {
        const std::size_t p = group + std::size_t(i);
        const auto s0 = std::size_t(point_first_[p]);
        if (lanes::lane(ok, i)) {
          for (int k = 0; k < 3; ++k) {
            const int c = k == 0 ? 2 : k - 1;  // normal, shear t1, shear t2
            const std::size_t s = s0 + std::size_t(k);
            delta_m_[s] = delta_of[c][i];
            rate_mps_[s] = rate_of[c][i];
            law_force_N_[s] = law_force_of[c][i];
            count_alive_(sum, s, delta_of[c][i], strain_limit);
          }
        } else {
          const double point_d[3] = {delta_of[0][i], delta_of[1][i], delta_of[2][i]};
          const double point_v[3] = {rate_of[0][i], rate_of[1][i], rate_of[2][i]};
          double point_f[3], point_fd[3];
          point_springs_general_(p, point_d, point_v, point_f, point_fd, sum, strain_limit, any_pending);
          for (int c = 0; c < 3; ++c) f_axis[c][i] = point_f[c], fd_axis[c][i] = point_fd[c];
          refresh_point_plain_(p);
        }
      }
      for (int c = 0; c < 3; ++c) fa[c] = lanes::load(f_axis[c]), fda[c] = lanes::load(fd_axis[c]);
    }

    // Stage 3: world force and dashpot force of each point, and their
    // moments about x_a (joint_step_).
    v4d force[3], dashpot[3];
    for (int r = 0; r < 3; ++r) {
      force[r] = F[r] * fa[0] + F[3 + r] * fa[1] + F[6 + r] * fa[2];
      dashpot[r] = F[r] * fda[0] + F[3 + r] * fda[1] + F[6 + r] * fda[2];
    }
    const v4d m0 = am[0] + 0.5 * d[0], m1 = am[1] + 0.5 * d[1], m2 = am[2] + 0.5 * d[2];
    // Stage 4: sums in point order. The lanes of (F_x, F_y, F_z, T_x),
    // (T_y, T_z, M_y, M_z) and (Fd_x, Fd_y, Fd_z, M_x) transposed into one
    // vector per point, which the three sums add in turn: each component
    // gets ((0 + p0) + p1) + ..., the order of joint_step_.
    v4d point[4] = {force[0], force[1], force[2], m1 * force[2] - m2 * force[1]};
    v4d point_yz[4] = {m2 * force[0] - m0 * force[2], m0 * force[1] - m1 * force[0],
                       m2 * dashpot[0] - m0 * dashpot[2], m0 * dashpot[1] - m1 * dashpot[0]};
    v4d point_dashpot[4] = {dashpot[0], dashpot[1], dashpot[2], m1 * dashpot[2] - m2 * dashpot[1]};
    lanes::transpose(point[0], point[1], point[2], point[3]);
    lanes::transpose(point_yz[0], point_yz[1], point_yz[2], point_yz[3]);
    lanes::transpose(point_dashpot[0], point_dashpot[1], point_dashpot[2], point_dashpot[3]);
    for (int i = 0; i < n; ++i) {
      sum_force_torque = sum_force_torque + point[i];
      sum_torque_yz = sum_torque_yz + point_yz[i];
      sum_dashpot = sum_dashpot + point_dashpot[i];
    }
  };
  for_each_point_group(first_point, last_point, group_step);
  // force_on_a = sums[0..2], torque_on_a = sums[3..5], dashpot moment
  // about x_a = sums[11], sums[6..7]; dashpot force = sums[8..10].
  double sums[3 * lanes::kWidth];
  lanes::store(sums, sum_force_torque);
  lanes::store(sums + lanes::kWidth, sum_torque_yz);
  lanes::store(sums + 2 * lanes::kWidth, sum_dashpot);
  const double dashpot_moment_a[3] = {sums[11], sums[6], sums[7]};
  finish_joint_(j, Xa, Xb, sums, sums + 3, sums + 8, dashpot_moment_a, BodyVelocities{Va, Vb, Wa, Wb},
                type.fracture, sum, any_pending);
}

}  // namespace fq
