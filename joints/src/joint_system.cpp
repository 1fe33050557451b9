#include "joints/joint_system.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "dem_core/parallel_for.h"

namespace fq {

namespace {

constexpr std::uint8_t kPendingYield = 1;
constexpr std::uint8_t kPendingDelete = 2;

std::invalid_argument joint_error(std::size_t joint, const std::string& what) {
  std::ostringstream m;
  m << "joint " << joint << ": " << what;
  return std::invalid_argument(m.str());
}

double reduced_mass(const BodyStore& bodies, BodyId a, BodyId b) {
  const double ia = bodies.inverse_mass_per_kg[a], ib = bodies.inverse_mass_per_kg[b];
  return (ia + ib) > 0.0 ? 1.0 / (ia + ib) : 0.0;
}

}  // namespace

JointSystem::JointSystem(BondedPairs* bonded_pairs, JointSystemSettings settings)
    : bonded_(bonded_pairs), settings_(settings) {
  joint_first_.push_back(0);
}

std::int32_t JointSystem::add_joint(const BodyStore& bodies, const JointDef& def) {
  if (prepared_) throw std::logic_error("JointSystem::add_joint: joints must be added before the first step");
  const std::size_t j = joint_body_a_.size();
  const auto n = BodyId(bodies.size());
  if (def.body_a < 0 || def.body_a >= n) throw joint_error(j, "body_a is not a body id");
  if (def.body_b < 0 || def.body_b >= n) throw joint_error(j, "body_b is not a body id");
  if (def.body_a == def.body_b) throw joint_error(j, "body_a and body_b must differ");
  if (!((def.frame.transpose() * def.frame - Mat3::Identity()).norm() < 1e-9) || !(def.frame.determinant() > 0.0))
    throw joint_error(j, "frame must be a rotation matrix (orthonormal columns t1, t2, n, right-handed)");
  if (def.layout.points.empty() && def.layout.links.empty()) throw joint_error(j, "layout has no springs");
  if (def.fracture.criterion == BreakCriterion::StrainLimit && !(def.fracture.strain_limit > 0.0))
    throw joint_error(j, "fracture.strain_limit must be > 0 for the strain_limit criterion");

  const BodyId a = def.body_a, b = def.body_b;
  const auto jid = std::int32_t(j);
  const Quat qj(def.frame);
  joint_body_a_.push_back(a);
  joint_body_b_.push_back(b);
  joint_frame_a_.push_back((bodies.orientation[a].conjugate() * qj).normalized());
  joint_frame_b_.push_back((bodies.orientation[b].conjugate() * qj).normalized());
  joint_frame_world_.push_back(def.frame);
  joint_break_.push_back(def.fracture);
  joint_broken_.push_back(0);
  joint_break_pending_.push_back(0);
  joint_event_pending_.push_back(0);

  const Mat3 ra = bodies.orientation[a].toRotationMatrix(), rb = bodies.orientation[b].toRotationMatrix();
  const double m_red = reduced_mass(bodies, a, b);
  auto local_a = [&](const Vec3& w) -> Vec3 { return ra.transpose() * (w - bodies.position_m[a]); };
  auto local_b = [&](const Vec3& w) -> Vec3 { return rb.transpose() * (w - bodies.position_m[b]); };
  try {
    for (const SpringPointDef& p : def.layout.points) {
      const Vec3 w = def.origin_m + def.frame * p.offset_m;
      if (p.has_normal) add_spring_(jid, SpringRole::Normal, 2, local_a(w), local_b(w), 0.0, p.normal, m_red);
      if (p.has_shear) {
        add_spring_(jid, SpringRole::Shear, 0, local_a(w), local_b(w), 0.0, p.shear, m_red);
        add_spring_(jid, SpringRole::Shear, 1, local_a(w), local_b(w), 0.0, p.shear, m_red);
      }
    }
    for (const LinkDef& l : def.layout.links) {
      const Vec3 wa = def.origin_m + def.frame * l.end_a_m, wb = def.origin_m + def.frame * l.end_b_m;
      const double len = (wb - wa).norm();
      if (!(len > 0.0)) throw std::invalid_argument("a link has zero rest length");
      add_spring_(jid, SpringRole::Link, std::int8_t(l.role == LinkRole::Axial ? -1 : -2), local_a(wa), local_b(wb),
                  len, l.spring, m_red);
    }
  } catch (const std::invalid_argument& e) {
    throw joint_error(j, e.what());
  }
  joint_first_.push_back(std::int32_t(spring_joint_.size()));
  if (bonded_) bonded_->add(a, b);
  return jid;
}

// axis: 0, 1, 2 joint-frame axis of a point spring; -1 axial link, -2 other link.
void JointSystem::add_spring_(std::int32_t joint, SpringRole role, std::int8_t axis, const Vec3& attach_a_local,
                              const Vec3& attach_b_local, double rest_length_m, const SpringDef& def,
                              double reduced_mass_kg) {
  if (!(def.reference_length_m > 0.0)) throw std::invalid_argument("spring reference_length_m must be > 0 (m)");
  if (!(def.dashpot.coefficient_Nspm >= 0.0) || !(def.dashpot.damping_ratio >= 0.0))
    throw std::invalid_argument("dashpot coefficient_Nspm and damping_ratio must be >= 0");
  const double k0 = initial_stiffness_Npm(def);  // validates the law
  const auto s = std::int32_t(spring_joint_.size());
  spring_joint_.push_back(joint);
  spring_role_.push_back(role);
  spring_axis_.push_back(axis);
  attach_a_local_m_.push_back(attach_a_local);
  attach_b_local_m_.push_back(attach_b_local);
  rest_length_m_.push_back(rest_length_m);
  reference_length_m_.push_back(def.reference_length_m);
  dashpot_Nspm_.push_back(def.dashpot.coefficient_Nspm +
                          2.0 * def.dashpot.damping_ratio * std::sqrt(k0 * reduced_mass_kg));
  stiffness0_Npm_.push_back(k0);
  ultimate_t_m_.push_back(ultimate_deformation_m(def, true));
  ultimate_c_m_.push_back(ultimate_deformation_m(def, false));
  law_kind_.push_back(def.law.kind);
  switch (def.law.kind) {
    case SpringLawKind::LinearElastic:
      linear_.ids.push_back(s);
      linear_.law.push_back(def.law.linear);
      linear_.state.emplace_back();
      break;
    case SpringLawKind::Trilinear:
      trilinear_.ids.push_back(s);
      trilinear_.law.push_back(compile_trilinear(def.law.trilinear, def.reference_length_m));
      trilinear_.state.emplace_back();
      break;
    case SpringLawKind::Curee:
      curee_.ids.push_back(s);
      curee_.law.push_back(compile_curee(def.law.curee));
      curee_.state.emplace_back();
      break;
    case SpringLawKind::Count:
      throw std::invalid_argument("unknown spring law kind");
  }
}

void JointSystem::prepare(const BodyStore& bodies) {
  if (prepared_) return;
  prepared_ = true;
  body_count_ = bodies.size();
  const std::size_t ns = spring_joint_.size();
  end_a_m_.assign(ns, Vec3::Zero());
  end_b_m_.assign(ns, Vec3::Zero());
  direction_.assign(ns, Vec3::UnitZ());
  delta_m_.assign(ns, 0.0);
  rate_mps_.assign(ns, 0.0);
  law_force_N_.assign(ns, 0.0);
  dashpot_force_N_.assign(ns, 0.0);
  force_N_.assign(ns, 0.0);
  alive_.assign(ns, 1);
  yielded_.assign(ns, 0);
  pending_.assign(ns, 0);
  failure_force_N_.assign(ns, 0.0);
  failure_mode_.assign(ns, "");
  delta_prev_m_.assign(ns, 0.0);
  law_force_prev_N_.assign(ns, 0.0);
  dashpot_power_prev_W_.assign(ns, 0.0);
  has_prev_.assign(ns, 0);
  work_J_.assign(ns, 0.0);
  stored_J_.assign(ns, 0.0);
  plastic_J_.assign(ns, 0.0);
  viscous_done_J_.assign(ns, 0.0);
  viscous_half_J_.assign(ns, 0.0);
  // Springs of one point (a normal and two shear springs of a four-corner
  // layout) share their attachments: the geometry and relative velocity of
  // the point are computed once, for the first of them.
  same_point_as_prev_.assign(ns, 0);
  for (std::size_t s = 1; s < ns; ++s)
    same_point_as_prev_[s] = spring_joint_[s] == spring_joint_[s - 1] &&
                             attach_a_local_m_[s] == attach_a_local_m_[s - 1] &&
                             attach_b_local_m_[s] == attach_b_local_m_[s - 1];
  slot_force_N_.assign(2 * ns, Vec3::Zero());
  slot_torque_Nm_.assign(2 * ns, Vec3::Zero());
  // CSR: slots of each body in ascending slot index (= ascending spring).
  body_slot_first_.assign(body_count_ + 1, 0);
  for (std::size_t s = 0; s < ns; ++s) {
    const std::size_t j = std::size_t(spring_joint_[s]);
    ++body_slot_first_[std::size_t(joint_body_a_[j]) + 1];
    ++body_slot_first_[std::size_t(joint_body_b_[j]) + 1];
  }
  for (std::size_t i = 0; i < body_count_; ++i) body_slot_first_[i + 1] += body_slot_first_[i];
  body_slots_.assign(2 * ns, 0);
  std::vector<std::int32_t> fill(body_slot_first_.begin(), body_slot_first_.end() - 1);
  for (std::size_t s = 0; s < ns; ++s) {
    const std::size_t j = std::size_t(spring_joint_[s]);
    body_slots_[std::size_t(fill[std::size_t(joint_body_a_[j])]++)] = std::int32_t(2 * s);
    body_slots_[std::size_t(fill[std::size_t(joint_body_b_[j])]++)] = std::int32_t(2 * s + 1);
  }
}

void JointSystem::accumulate_forces(BodyStore& bodies, const StepInfo& /*step*/) {
  if (!prepared_) prepare(bodies);
  const std::size_t nj = joint_body_a_.size();
  const auto nj_i = std::int64_t(nj);

  // 1. Joint frames and spring geometry.
  const bool parallel = parallel_(spring_joint_.size());
  parallel_for_static(nj_i, parallel, [&](std::int64_t ji) {
    const auto j = std::size_t(ji);
    if (joint_broken_[j]) return;
    const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
    const Quat qa = bodies.orientation[a] * joint_frame_a_[j];
    Quat qb = bodies.orientation[b] * joint_frame_b_[j];
    if (qa.dot(qb) < 0.0) qb.coeffs() = -qb.coeffs();
    Quat qm;
    qm.coeffs() = qa.coeffs() + qb.coeffs();
    qm.normalize();
    const Mat3 frame = qm.toRotationMatrix();
    joint_frame_world_[j] = frame;
    const Mat3 ra = bodies.rotation[a], rb = bodies.rotation[b];
    const Vec3 xa = bodies.position_m[a], xb = bodies.position_m[b];
    const Vec3 va = bodies.velocity_mps[a], vb = bodies.velocity_mps[b];
    const Vec3 wa = bodies.angular_velocity_radps[a], wb = bodies.angular_velocity_radps[b];
    // Raw pointers: see step 3.
    const std::uint8_t* __restrict same_point = same_point_as_prev_.data();
    const std::int8_t* __restrict axis = spring_axis_.data();
    const Vec3* __restrict attach_a = attach_a_local_m_.data();
    const Vec3* __restrict attach_b = attach_b_local_m_.data();
    Vec3* __restrict end_a = end_a_m_.data();
    Vec3* __restrict end_b = end_b_m_.data();
    Vec3* __restrict direction = direction_.data();
    double* __restrict delta_m = delta_m_.data();
    double* __restrict rate_mps = rate_mps_.data();
    Vec3 pa = Vec3::Zero(), pb = Vec3::Zero(), d = Vec3::Zero(), vrel = Vec3::Zero();
    const auto first = std::size_t(joint_first_[j]), last = std::size_t(joint_first_[j + 1]);
    for (std::size_t s = first; s < last; ++s) {
      if (!same_point[s] || s == first) {
        const Vec3 arm_a = ra * attach_a[s], arm_b = rb * attach_b[s];
        pa = xa + arm_a;
        pb = xb + arm_b;
        d = pb - pa;
        vrel = (vb + wb.cross(arm_b)) - (va + wa.cross(arm_a));
      }
      Vec3 e;
      double delta;
      if (axis[s] >= 0) {
        e = frame.col(axis[s]);
        delta = e.dot(d);
      } else {
        const double len = d.norm();
        e = len > 0.0 ? Vec3(d / len) : direction[s];
        delta = len - rest_length_m_[s];
      }
      end_a[s] = pa;
      end_b[s] = pb;
      direction[s] = e;
      delta_m[s] = delta;
      rate_mps[s] = e.dot(vrel);
    }
  });

  // 2. Laws, batch by batch.
  evaluate_laws_();

  // 3. Slots and the fracture test.
  parallel_for_static(nj_i, parallel, [&](std::int64_t ji) {
    const auto j = std::size_t(ji);
    const auto first = std::size_t(joint_first_[j]), last = std::size_t(joint_first_[j + 1]);
    if (joint_broken_[j]) {
      for (std::size_t s = first; s < last; ++s) {
        slot_force_N_[2 * s].setZero();
        slot_force_N_[2 * s + 1].setZero();
        slot_torque_Nm_[2 * s].setZero();
        slot_torque_Nm_[2 * s + 1].setZero();
      }
      return;
    }
    const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
    // Raw pointers: the compiler cannot tell that the vectors' own pointers
    // are not changed by the stores below, and would reload them per spring.
    const double* __restrict force_N = force_N_.data();
    const double* __restrict dashpot_force_N = dashpot_force_N_.data();
    const double* __restrict dashpot_Nspm = dashpot_Nspm_.data();
    const double* __restrict rate_mps = rate_mps_.data();
    const Vec3* __restrict direction = direction_.data();
    const Vec3* __restrict end_a = end_a_m_.data();
    const Vec3* __restrict end_b = end_b_m_.data();
    Vec3* __restrict slot_force = slot_force_N_.data();
    Vec3* __restrict slot_torque = slot_torque_Nm_.data();
    double* __restrict power_prev_W = dashpot_power_prev_W_.data();
    const Vec3 xa = bodies.position_m[a], xb = bodies.position_m[b];
    const Vec3 w_sum = bodies.angular_velocity_radps[a] + bodies.angular_velocity_radps[b];
    const bool strain_limit = joint_break_[j].criterion == BreakCriterion::StrainLimit;
    JointSpringSummary sum;
    bool any_pending = false;
    for (std::size_t s = first; s < last; ++s) {
      const double f = force_N[s];
      const Vec3 e = direction[s];
      const Vec3 force = f * e;  // on a; -force on b (f > 0 = tension pulls b back)
      const Vec3 d = end_b[s] - end_a[s];
      const Vec3 frame_torque = 0.5 * d.cross(force);
      if (dashpot_Nspm[s] > 0.0) {
        // Dissipated power of the dashpot force system at n-1/2: f_d r minus
        // the power of its share of the frame torque (completed in finish_step).
        const Vec3 torque_d = (0.5 * dashpot_force_N[s]) * d.cross(e);
        power_prev_W[s] = dashpot_force_N[s] * rate_mps[s] - torque_d.dot(w_sum);
      }
      slot_force[2 * s] = force;
      slot_torque[2 * s] = (end_a[s] - xa).cross(force) + frame_torque;
      slot_force[2 * s + 1] = -force;
      slot_torque[2 * s + 1] = (end_b[s] - xb).cross(-force) + frame_torque;
      const bool normal = spring_role_[s] == SpringRole::Normal || spring_axis_[s] == -1;
      ++sum.springs;
      if (normal) ++sum.normal_springs;
      if (alive_[s]) {
        ++sum.springs_alive;
        if (normal) ++sum.normal_springs_alive;
        // Only the strain-limit criterion reads it (fracture.h).
        if (strain_limit) sum.max_strain = std::max(sum.max_strain, std::abs(delta_m_[s]) / reference_length_m_[s]);
      }
      any_pending = any_pending || pending_[s] != 0;
    }
    const bool brk = joint_should_break(joint_break_[j], sum);
    joint_break_pending_[j] = brk ? 1 : 0;
    joint_event_pending_[j] = (brk || any_pending) ? 1 : 0;
  });

  // 4. Gather per body in slot order.
  const auto nb_i = std::int64_t(body_count_);
  parallel_for_static(nb_i, parallel, [&](std::int64_t bi) {
    const auto i = std::size_t(bi);
    const auto first = std::size_t(body_slot_first_[i]), last = std::size_t(body_slot_first_[i + 1]);
    if (first == last) return;
    Vec3 f = Vec3::Zero(), t = Vec3::Zero();
    for (std::size_t k = first; k < last; ++k) {
      const auto slot = std::size_t(body_slots_[k]);
      f += slot_force_N_[slot];
      t += slot_torque_Nm_[slot];
    }
    bodies.force_N[i] += f;
    bodies.torque_Nm[i] += t;
  });
}

template <class Law, class State, class Eval>
void JointSystem::run_batch_(Batch<Law, State>& batch, Eval eval, bool tracks_work) {
  const auto n = std::int64_t(batch.ids.size());
  // Raw pointers for the common path (see accumulate_forces, step 3).
  const std::int32_t* __restrict ids = batch.ids.data();
  const Law* __restrict laws = batch.law.data();
  State* __restrict states = batch.state.data();
  const std::uint8_t* __restrict alive = alive_.data();
  const double* __restrict delta_m = delta_m_.data();
  const double* __restrict rate_mps = rate_mps_.data();
  const double* __restrict dashpot_Nspm = dashpot_Nspm_.data();
  double* __restrict law_force_N = law_force_N_.data();
  double* __restrict dashpot_force_N = dashpot_force_N_.data();
  double* __restrict force_N = force_N_.data();
  double* __restrict delta_prev_m = delta_prev_m_.data();
  double* __restrict law_force_prev_N = law_force_prev_N_.data();
  double* __restrict work_J = work_J_.data();
  double* __restrict stored_J = stored_J_.data();
  double* __restrict plastic_J = plastic_J_.data();
  std::uint8_t* __restrict has_prev = has_prev_.data();
  parallel_for_static(n, parallel_(batch.ids.size()), [&](std::int64_t k) {
    const auto s = std::size_t(ids[k]);
    if (!alive[s] || joint_broken_[std::size_t(spring_joint_[s])]) return;
    const double delta = delta_m[s], rate = rate_mps[s];
    const LawOutput out = eval(laws[k], states[k], delta);
    if (out.failed) {
      // Deleted: the force drops to zero now and forever.
      pending_[s] |= kPendingDelete;
      failure_force_N_[s] = law_force_prev_N[s];
      const bool tension = delta > 0.0;
      failure_mode_[s] = spring_role_[s] == SpringRole::Shear ? "shear" : (tension ? "tension" : "compression");
      if (!yielded_[s]) {
        yielded_[s] = 1;
        pending_[s] |= kPendingYield;
      }
      alive_[s] = 0;
      plastic_J[s] += stored_J[s];  // release what was stored
      stored_J[s] = 0.0;
      law_force_N[s] = dashpot_force_N[s] = force_N[s] = 0.0;
      has_prev[s] = 0;
      return;
    }
    if (tracks_work && has_prev[s]) {
      work_J[s] += 0.5 * (law_force_prev_N[s] + out.force_N) * (delta - delta_prev_m[s]);
      plastic_J[s] = work_J[s] - out.stored_J;
    } else if (tracks_work) {
      work_J[s] = out.stored_J;  // first evaluation: the rest state stores what the law says
    }
    stored_J[s] = out.stored_J;
    if (out.inelastic && !yielded_[s]) {
      yielded_[s] = 1;
      pending_[s] |= kPendingYield;
      failure_force_N_[s] = out.force_N;
      failure_mode_[s] = spring_role_[s] == SpringRole::Shear ? "shear" : (delta > 0.0 ? "tension" : "compression");
    }
    const double fd = dashpot_Nspm[s] * rate;
    law_force_N[s] = out.force_N;
    dashpot_force_N[s] = fd;
    force_N[s] = out.force_N + fd;
    delta_prev_m[s] = delta;
    law_force_prev_N[s] = out.force_N;
    has_prev[s] = 1;
  });
}

void JointSystem::evaluate_laws_() {
  run_batch_(
      linear_,
      [](const LinearElasticParams& l, LinearElasticState& st, double d) { return evaluate_linear_elastic(l, st, d); },
      false);
  run_batch_(
      trilinear_, [](const TrilinearLaw& l, TrilinearState& st, double d) { return evaluate_trilinear(l, st, d); },
      true);
  run_batch_(
      curee_, [](const CureeLaw& l, CureeState& st, double d) { return evaluate_curee(l, st, d); }, true);
}

void JointSystem::kill_spring_(std::size_t s) {
  if (!alive_[s]) return;
  alive_[s] = 0;
  plastic_J_[s] += stored_J_[s];
  stored_J_[s] = 0.0;
  law_force_N_[s] = dashpot_force_N_[s] = force_N_[s] = 0.0;
}

void JointSystem::finish_step(const BodyStore& bodies, const StepInfo& step, EventLog& events) {
  const std::size_t nj = joint_body_a_.size();
  // Dashpot dissipation of step n, as the ledger counts work: dt P(v_n) with
  // v_n = (v(n-1/2) + v(n+1/2)) / 2 on the geometry of step n. The bodies now
  // hold v(n+1/2) and x(n+1) = x(n) + dt v(n+1/2), so the arms of step n are
  // end_n - (x(n+1) - dt v(n+1/2)).
  const auto nj_i = std::int64_t(nj);
  const double dt = step.dt_s;
  parallel_for_static(nj_i, parallel_(spring_joint_.size()), [&](std::int64_t ji) {
    const auto j = std::size_t(ji);
    if (joint_broken_[j]) {  // its last dashpot term is now complete
      for (auto s = std::size_t(joint_first_[j]); s < std::size_t(joint_first_[j + 1]); ++s) viscous_half_J_[s] = 0.0;
      return;
    }
    const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
    const Vec3 xa = bodies.position_m[a] - dt * bodies.velocity_mps[a];
    const Vec3 xb = bodies.position_m[b] - dt * bodies.velocity_mps[b];
    const Vec3& wa = bodies.angular_velocity_radps[a];
    const Vec3& wb = bodies.angular_velocity_radps[b];
    const Vec3 w_sum = wa + wb;
    Vec3 vrel = Vec3::Zero();
    bool vrel_valid = false;  // vrel belongs to the current point
    for (auto s = std::size_t(joint_first_[j]); s < std::size_t(joint_first_[j + 1]); ++s) {
      if (!same_point_as_prev_[s]) vrel_valid = false;
      if (!(dashpot_Nspm_[s] > 0.0) || dashpot_force_N_[s] == 0.0) {
        viscous_half_J_[s] = 0.0;
        continue;
      }
      if (!vrel_valid) {
        vrel = (bodies.velocity_mps[b] + wb.cross(end_b_m_[s] - xb)) -
               (bodies.velocity_mps[a] + wa.cross(end_a_m_[s] - xa));
        vrel_valid = true;
      }
      const Vec3& e = direction_[s];
      const Vec3 torque_d = (0.5 * dashpot_force_N_[s]) * (end_b_m_[s] - end_a_m_[s]).cross(e);
      const double power_next = dashpot_force_N_[s] * e.dot(vrel) - torque_d.dot(w_sum);
      const double term = dt * 0.5 * (dashpot_power_prev_W_[s] + power_next);
      // The ledger's kinetic energy at n is KE_0 + (t_0/2 + t_1 + ... +
      // t_{n-1} + t_n/2) (the start shifts v back half a step), so the
      // first step counts half.
      viscous_done_J_[s] += step.step == 0 ? 0.5 * term : term;
      viscous_half_J_[s] = 0.5 * term;
    }
  });
  for (std::size_t j = 0; j < nj; ++j) {
    if (!joint_event_pending_[j]) continue;
    joint_event_pending_[j] = 0;
    const auto first = std::size_t(joint_first_[j]), last = std::size_t(joint_first_[j + 1]);
    Event e;
    e.time_s = step.time_s;
    e.step = step.step;
    e.joint_id = std::int32_t(j);
    e.body_a = joint_body_a_[j];
    e.body_b = joint_body_b_[j];
    for (std::size_t s = first; s < last; ++s) {
      if (!pending_[s]) continue;
      e.spring_index = std::int32_t(s - first);
      e.position_m = 0.5 * (end_a_m_[s] + end_b_m_[s]);
      e.mode = failure_mode_[s];
      e.force_N = failure_force_N_[s];
      if (pending_[s] & kPendingYield) {
        e.kind = EventKind::SpringYielded;
        if (pending_[s] & kPendingDelete) e.force_N = law_force_prev_N_[s];
        events.add(e);
      }
      if (pending_[s] & kPendingDelete) {
        e.kind = EventKind::SpringDeleted;
        e.force_N = failure_force_N_[s];
        events.add(e);
      }
      pending_[s] = 0;
    }
    if (joint_break_pending_[j] && !joint_broken_[j]) {
      joint_break_pending_[j] = 0;
      e.kind = EventKind::JointBroken;
      e.spring_index = -1;
      // Force at failure: magnitude of the resultant the joint carried.
      Vec3 resultant = Vec3::Zero(), where = Vec3::Zero();
      for (std::size_t s = first; s < last; ++s) {
        resultant += slot_force_N_[2 * s];
        where += 0.5 * (end_a_m_[s] + end_b_m_[s]);
      }
      e.force_N = resultant.norm();
      e.position_m = where / double(last - first);
      bool any_normal_dead = false;
      for (std::size_t s = first; s < last; ++s)
        if (!alive_[s] && (spring_role_[s] == SpringRole::Normal || spring_axis_[s] == -1)) any_normal_dead = true;
      e.mode = joint_break_[j].criterion == BreakCriterion::StrainLimit ? "strain_limit"
               : any_normal_dead                                        ? "normal_springs_deleted"
                                                                        : "springs_deleted";
      events.add(e);
      joint_broken_[j] = 1;
      for (std::size_t s = first; s < last; ++s) kill_spring_(s);
      if (bonded_) bonded_->release(joint_body_a_[j], joint_body_b_[j]);
    }
  }
}

void JointSystem::report_energy(EnergyLedger& ledger) const {
  double elastic = 0.0, plastic = 0.0, viscous = 0.0;
  for (std::size_t s = 0; s < spring_joint_.size(); ++s) {
    elastic += stored_J_[s];
    plastic += plastic_J_[s];
    viscous += viscous_done_J_[s] - viscous_half_J_[s];  // through n: all of step n-1, half of step n
  }
  ledger.elastic_J += elastic;
  ledger.dissipated_plastic_J += plastic;
  ledger.dissipated_viscous_J += viscous;
}

StiffestMode JointSystem::stiffest_mode(const BodyStore& bodies) const {
  // Stable time step of the linearised joint network at the current pose.
  // omega^2 = largest eigenvalue of M^-1/2 K M^-1/2, with K = sum_s k0_s
  // c_s c_s^T, c_s the spring's deformation gradient (-g_a on body a, +g_b on
  // body b, g = (e, arm x e)), M the bodies' masses and world inertia
  // tensors; lambda_C the largest eigenvalue of M^-1/2 C M^-1/2 for the
  // dashpots (C = sum_s c_s^dashpot c_s c_s^T, 1/s). Both are found
  // matrix-free by power iteration with the Rayleigh quotient, which
  // converges from below; 400 iterations bring it within a fraction of a
  // percent for joint networks, where the top modes are well separated.
  // Central difference with a dashpot reading v(n-1/2) is stable for
  // dt <= (2 / omega)(sqrt(1 + zeta^2) - zeta) in a mode of damping ratio
  // zeta; with zeta <= lambda_C / (2 omega) this gives
  //   dt_crit = 2 / (sqrt(omega^2 + lambda_C^2 / 4) + lambda_C / 2),
  // reported as omega_eff = 2 / dt_crit. Dashpots matter: a spring-level
  // ratio of 0.3 can overdamp a light rotational mode (zeta > 1) and halve
  // the stable step. Fixed bodies have zero inverse mass and drop out.
  const std::size_t nb = bodies.size();
  const std::size_t ns = spring_joint_.size();
  struct Row {
    BodyId a, b;
    double k, c;                         // stiffness (N/m), dashpot (N s/m)
    Eigen::Matrix<double, 6, 1> ca, cb;  // mass-scaled gradient blocks
  };
  std::vector<Row> rows;
  rows.reserve(ns);
  auto block = [&](BodyId i, const Vec3& arm, const Vec3& e) {
    Eigen::Matrix<double, 6, 1> g;
    const double inv_m = bodies.inverse_mass_per_kg[i];
    g.head<3>() = e * std::sqrt(inv_m);
    const Mat3& r = bodies.rotation[i];
    const Vec3 inv_sqrt_inertia = bodies.inverse_inertia_per_kgm2[i].cwiseSqrt();
    g.tail<3>() = r * inv_sqrt_inertia.cwiseProduct(r.transpose() * arm.cross(e));
    return g;
  };
  for (std::size_t s = 0; s < ns; ++s) {
    const auto j = std::size_t(spring_joint_[s]);
    if (joint_broken_[j] || (!alive_.empty() && !alive_[s])) continue;
    const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
    const Vec3 arm_a = bodies.rotation[a] * attach_a_local_m_[s], arm_b = bodies.rotation[b] * attach_b_local_m_[s];
    Vec3 e;
    if (spring_axis_[s] >= 0) {
      const Quat qa = bodies.orientation[a] * joint_frame_a_[j];
      e = qa.toRotationMatrix().col(spring_axis_[s]);
    } else {
      e = ((bodies.position_m[b] + arm_b) - (bodies.position_m[a] + arm_a)).normalized();
    }
    rows.push_back({a, b, stiffness0_Npm_[s], dashpot_Nspm_[s], -block(a, arm_a, e), block(b, arm_b, e)});
  }
  StiffestMode mode;
  if (rows.empty()) return mode;

  using Vec6 = Eigen::Matrix<double, 6, 1>;
  std::vector<Vec6> x(nb), y(nb);
  // Largest eigenvalue of sum_rows coef(row) c c^T; leaves its vector in x.
  auto top_eigenvalue = [&](auto coef) {
    // Deterministic start vector with a component along every degree of freedom.
    for (std::size_t i = 0; i < nb; ++i)
      for (int d = 0; d < 6; ++d) x[i][d] = 1.0 + 0.1 * std::sin(double(7 * i + d + 1));
    double lambda = 0.0;
    for (int it = 0; it < 400; ++it) {
      for (Vec6& v : y) v.setZero();
      for (const Row& r : rows) {
        const double proj = r.ca.dot(x[std::size_t(r.a)]) + r.cb.dot(x[std::size_t(r.b)]);
        y[std::size_t(r.a)] += (coef(r) * proj) * r.ca;
        y[std::size_t(r.b)] += (coef(r) * proj) * r.cb;
      }
      double xy = 0.0, yy = 0.0, xx = 0.0;
      for (std::size_t i = 0; i < nb; ++i) {
        xy += x[i].dot(y[i]);
        yy += y[i].squaredNorm();
        xx += x[i].squaredNorm();
      }
      if (!(yy > 0.0)) return 0.0;
      lambda = xy / xx;
      const double scale = 1.0 / std::sqrt(yy);
      for (std::size_t i = 0; i < nb; ++i) x[i] = y[i] * scale;
    }
    return std::max(0.0, lambda);
  };
  const double lambda_c = top_eigenvalue([](const Row& r) { return r.c; });
  const double omega2 = top_eigenvalue([](const Row& r) { return r.k; });  // x: top stiffness mode
  if (!(omega2 > 0.0)) return mode;
  // The spring storing most energy in the top mode names where it lives.
  std::size_t best = 0;
  double best_energy = -1.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& r = rows[k];
    const double proj = r.ca.dot(x[std::size_t(r.a)]) + r.cb.dot(x[std::size_t(r.b)]);
    if (r.k * proj * proj > best_energy) {
      best_energy = r.k * proj * proj;
      best = k;
    }
  }
  std::size_t joint = 0;
  for (std::size_t s = 0, k = 0; s < ns; ++s) {
    const auto j = std::size_t(spring_joint_[s]);
    if (joint_broken_[j] || (!alive_.empty() && !alive_[s])) continue;
    if (k++ == best) {
      joint = j;
      break;
    }
  }
  mode.omega_radps = std::sqrt(omega2 + 0.25 * lambda_c * lambda_c) + 0.5 * lambda_c;
  std::ostringstream m;
  m << "joint " << joint << " (bodies " << joint_body_a_[joint] << " '" << bodies.info[joint_body_a_[joint]].name
    << "' - " << joint_body_b_[joint] << " '" << bodies.info[joint_body_b_[joint]].name << "')";
  mode.where = m.str();
  return mode;
}

bool JointSystem::supports_trial_states() const {
  if (!trilinear_.ids.empty() || !curee_.ids.empty()) return false;
  for (const JointBreakDef& b : joint_break_)
    if (b.criterion == BreakCriterion::StrainLimit) return false;
  return true;
}

SpringStatus JointSystem::spring_status(std::size_t s) const {
  if (alive_.empty()) return SpringStatus::Elastic;
  if (!alive_[s]) return SpringStatus::Deleted;
  return yielded_[s] ? SpringStatus::Yielded : SpringStatus::Elastic;
}

double JointSystem::spring_strain_ratio(std::size_t s) const {
  const double d = delta_m_.empty() ? 0.0 : delta_m_[s];
  const double u = d >= 0.0 ? ultimate_t_m_[s] : ultimate_c_m_[s];
  return std::isfinite(u) ? std::abs(d) / u : 0.0;
}

JointStatus JointSystem::joint_status(std::size_t j) const {
  if (joint_broken_[j]) return JointStatus::Broken;
  if (alive_.empty()) return JointStatus::Intact;
  for (auto s = std::size_t(joint_first_[j]); s < std::size_t(joint_first_[j + 1]); ++s)
    if (yielded_[s] || !alive_[s]) return JointStatus::Yielded;
  return JointStatus::Intact;
}

JointCounts JointSystem::counts() const {
  JointCounts c;
  for (std::size_t j = 0; j < joint_body_a_.size(); ++j) {
    switch (joint_status(j)) {
      case JointStatus::Intact:
        ++c.intact;
        break;
      case JointStatus::Yielded:
        ++c.yielded;
        break;
      case JointStatus::Broken:
        ++c.broken;
        break;
    }
  }
  return c;
}

}  // namespace fq
