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
  joint_books_open_.push_back(0);
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

void JointSystem::hold_pair_through(std::size_t joint_1, std::size_t joint_2) {
  if (prepared_) throw std::logic_error("JointSystem::hold_pair_through: pairs must be held before the first step");
  const std::size_t n = joint_body_a_.size();
  if (joint_1 >= n || joint_2 >= n || joint_1 == joint_2)
    throw std::invalid_argument("hold_pair_through: two different joints expected");
  const BodyId a1 = joint_body_a_[joint_1], b1 = joint_body_b_[joint_1];
  const BodyId a2 = joint_body_a_[joint_2], b2 = joint_body_b_[joint_2];
  // The common body, and the other body of each joint.
  BodyId hub = kNoBody, body_1 = kNoBody, body_2 = kNoBody;
  for (const BodyId c : {a1, b1})
    if (c == a2 || c == b2) {
      if (hub != kNoBody) throw std::invalid_argument("hold_pair_through: the joints join the same two bodies");
      hub = c;
    }
  if (hub == kNoBody) throw std::invalid_argument("hold_pair_through: the joints share no body");
  body_1 = a1 == hub ? b1 : a1;
  body_2 = a2 == hub ? b2 : a2;
  if (held_through_of_joint_.size() < n) held_through_of_joint_.resize(n);
  for (const std::size_t j : {joint_1, joint_2}) held_through_of_joint_[j].push_back(std::int32_t(held_through_.size()));
  held_through_.push_back({std::int32_t(joint_1), std::int32_t(joint_2), body_1, body_2});
  if (bonded_) bonded_->add(body_1, body_2);
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
      law_index_.push_back(linear_.add(s, def.law.linear));
      break;
    case SpringLawKind::Trilinear:
      law_index_.push_back(trilinear_.add(s, compile_trilinear(def.law.trilinear, def.reference_length_m)));
      break;
    case SpringLawKind::Curee:
      law_index_.push_back(curee_.add(s, compile_curee(def.law.curee)));
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
  force_N_.assign(ns, 0.0);
  spring_force_current_ = false;
  alive_.assign(ns, 1);
  yielded_.assign(ns, 0);
  pending_.assign(ns, 0);
  failure_force_N_.assign(ns, 0.0);
  failure_mode_.assign(ns, "");
  has_prev_.assign(ns, 0);
  work_J_.assign(ns, 0.0);
  plastic_J_.assign(ns, 0.0);
  // Points: consecutive springs of one joint with the same attachments (the
  // normal and two shear springs of a four-corner point) share their ends,
  // separation and relative velocity.
  const std::size_t nj = joint_body_a_.size();
  point_first_.clear();
  joint_first_point_.assign(1, 0);
  point_attach_a_m_ = Vec3Columns{};
  point_attach_b_m_ = Vec3Columns{};
  spring_point_.assign(ns, 0);
  spring_is_normal_.assign(ns, 0);
  joint_spring_count_.assign(nj, 0);
  joint_normal_count_.assign(nj, 0);
  for (std::size_t j = 0; j < nj; ++j) {
    for (auto s = std::size_t(joint_first_[j]); s < std::size_t(joint_first_[j + 1]); ++s) {
      const bool same_point = s > std::size_t(joint_first_[j]) && spring_axis_[s] >= 0 && spring_axis_[s - 1] >= 0 &&
                              attach_a_local_m_[s] == attach_a_local_m_[s - 1] &&
                              attach_b_local_m_[s] == attach_b_local_m_[s - 1];
      if (!same_point) {
        point_first_.push_back(std::int32_t(s));
        point_attach_a_m_.push_back(attach_a_local_m_[s]);
        point_attach_b_m_.push_back(attach_b_local_m_[s]);
      }
      spring_point_[s] = std::int32_t(point_first_.size() - 1);
      spring_is_normal_[s] = spring_role_[s] == SpringRole::Normal || spring_axis_[s] == -1;
      ++joint_spring_count_[j];
      if (spring_is_normal_[s]) ++joint_normal_count_[j];
    }
    joint_first_point_.push_back(std::int32_t(point_first_.size()));
  }
  point_first_.push_back(std::int32_t(ns));
  const std::size_t np = point_attach_a_m_.size();
  point_end_a_m_.assign(np);
  point_end_b_m_.assign(np);
  dashpot_books_.assign(nj, DashpotBooks{});
  spring_geometry_current_ = false;
  slot_force_N_.assign(2 * nj, Vec3::Zero());
  slot_torque_Nm_.assign(2 * nj, Vec3::Zero());
  // CSR: slots of each body in ascending slot index (= ascending joint).
  body_slot_first_.assign(body_count_ + 1, 0);
  for (std::size_t j = 0; j < nj; ++j) {
    ++body_slot_first_[std::size_t(joint_body_a_[j]) + 1];
    ++body_slot_first_[std::size_t(joint_body_b_[j]) + 1];
  }
  for (std::size_t i = 0; i < body_count_; ++i) body_slot_first_[i + 1] += body_slot_first_[i];
  body_slots_.assign(2 * nj, 0);
  std::vector<std::int32_t> fill(body_slot_first_.begin(), body_slot_first_.end() - 1);
  for (std::size_t j = 0; j < nj; ++j) {
    body_slots_[std::size_t(fill[std::size_t(joint_body_a_[j])]++)] = std::int32_t(2 * j);
    body_slots_[std::size_t(fill[std::size_t(joint_body_b_[j])]++)] = std::int32_t(2 * j + 1);
  }
  prepare_lanes_();
}

void JointSystem::accumulate_forces(BodyStore& bodies, const StepInfo& /*step*/) {
  if (!prepared_) prepare(bodies);
  const bool parallel = parallel_(spring_joint_.size());
  // Joints in runs of at most about kJointsPerRun, one run per loop index: a
  // run first updates the frames of its lane joints (four at a time), then
  // steps its joints, so both happen in one parallel region and on one core.
  // The runs are of equal size (a multiple of four), as many as a multiple
  // of the threads, so that the static schedule gives every thread the same
  // number of joints: with runs of exactly 1024 the last one was short, and
  // at 1e4 joints one thread had 5 % more work than the other. How the
  // joints are grouped changes no result (each joint writes only its own
  // data; a lane of the frame groups computes its joint alone).
  constexpr std::size_t kJointsPerRun = 1024;
  const std::size_t nj = joint_body_a_.size();
  const std::size_t threads = parallel ? std::size_t(std::max(1, worker_count())) : 1;
  std::size_t runs = (nj + kJointsPerRun - 1) / kJointsPerRun;
  runs = (runs + threads - 1) / threads * threads;
  const std::size_t per_run = runs == 0 ? 0 : ((nj + runs - 1) / runs + 3) / 4 * 4;
  if (per_run > 0) runs = (nj + per_run - 1) / per_run;
  parallel_for_static(std::int64_t(runs), parallel, [&](std::int64_t run) {
    const std::size_t first = std::size_t(run) * per_run, last = std::min(nj, first + per_run);
    update_lane_frames_(bodies, first, last);
    for (std::size_t j = first; j < last; ++j) {
      if (joint_lanes_[j] && !joint_broken_[j])
        joint_step_lanes_(bodies, j);
      else
        joint_step_(bodies, j);
    }
  });
  spring_geometry_current_ = false;
  spring_force_current_ = false;

  // Gather per body in slot order.
  parallel_for_static(std::int64_t(body_count_), parallel, [&](std::int64_t bi) {
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

double JointSystem::stored_energy_J_(std::size_t s, double law_force_N, double delta_m) const {
  const auto k = std::size_t(law_index_[s]);
  switch (law_kind_[s]) {
    case SpringLawKind::Trilinear:
      return trilinear_stored_energy_J(trilinear_.law[std::size_t(trilinear_.law_of[k])], law_force_N);
    case SpringLawKind::LinearElastic:
      return linear_elastic_stored_energy_J(linear_.law[std::size_t(linear_.law_of[k])], delta_m);
    case SpringLawKind::Curee:
      return curee_stored_energy_J(curee_.law[std::size_t(curee_.law_of[k])], curee_.state[k], law_force_N, delta_m);
    case SpringLawKind::Count:
      break;
  }
  return 0.0;
}

double JointSystem::spring_elastic_J(std::size_t s) const {
  if (alive_.empty() || !alive_[s] || !has_prev_[s]) return 0.0;
  return stored_energy_J_(s, law_force_N_[s], delta_m_[s]);
}

// Inlined into joint_step_, its only caller on the hot path. Per spring and
// step it writes the deformation, rate and law force and nothing else while
// the spring stays on its initial linear branch.
[[gnu::always_inline]] inline bool JointSystem::evaluate_spring_(std::size_t s, double delta, double rate,
                                                                double& law_force_N, double& dashpot_force_N,
                                                                bool& any_event) {
  // Most springs of a frame stay on their initial linear branch for most of
  // a run. For a trilinear spring that has not yielded and stays on that
  // branch this step, the general path below reduces to force = k0 delta,
  // with no books and no flags. It is computed here by the law's own
  // functions (trilinear_law.h), so with the same bits, without the switch,
  // the law's output record and the work-book tests.
  if (law_kind_[s] == SpringLawKind::Trilinear && !yielded_[s] && has_prev_[s]) {
    const auto k = std::size_t(law_index_[s]);
    const TrilinearLaw& law = trilinear_.law[std::size_t(trilinear_.law_of[k])];
    const double offset = trilinear_.state[k].plastic_offset_m;
    if (offset == 0.0 && !trilinear_past_ultimate(law, delta)) {
      const TrilinearTrial trial = trilinear_trial(law, offset, delta);
      if (trial.inside()) {
        delta_m_[s] = delta;
        rate_mps_[s] = rate;
        law_force_N_[s] = trial.force_N;
        law_force_N = trial.force_N;
        dashpot_force_N = dashpot_Nspm_[s] * rate;
        return true;
      }
    }
  }
  // The previous evaluation's values, read before they are overwritten.
  const double delta_prev = delta_m_[s];
  const double law_force_prev = law_force_N_[s];
  delta_m_[s] = delta;
  rate_mps_[s] = rate;
  const auto k = std::size_t(law_index_[s]);
  LawOutput out;
  // Work books: a trilinear spring on its initial linear branch, and a
  // linear spring always, store exactly the work done on them (work =
  // stored), so the trapezoid sum starts when a trilinear spring first
  // yields; a CUREE spring keeps it from its first step.
  bool tracks_work = true, tracked_before = true;
  switch (law_kind_[s]) {
    case SpringLawKind::Trilinear:
      out = evaluate_trilinear(trilinear_.law[std::size_t(trilinear_.law_of[k])], trilinear_.state[k], delta);
      tracked_before = yielded_[s] != 0;
      tracks_work = tracked_before || out.inelastic;
      break;
    case SpringLawKind::LinearElastic:
      out = evaluate_linear_elastic(linear_.law[std::size_t(linear_.law_of[k])], linear_.state[k], delta);
      tracks_work = false;
      break;
    case SpringLawKind::Curee:
      out = evaluate_curee(curee_.law[std::size_t(curee_.law_of[k])], curee_.state[k], delta);
      break;
    case SpringLawKind::Count:
      break;
  }
  if (out.failed) {
    // Deleted: the force drops to zero now and forever. Released as plastic
    // work: what it stored at the last step, plus its work over this step's
    // increment by the trapezoid of the forces the dynamics applied, that
    // last force and now 0 (it acted for the whole last step; the ledger's
    // kinetic energy counts that step's work up to here: without this term
    // the ledger lost f v dt / 2 per spring, tests/joints/test_fracture_energy.cpp).
    pending_[s] |= kPendingDelete;
    failure_force_N_[s] = law_force_prev;
    const bool tension = delta > 0.0;
    failure_mode_[s] = spring_role_[s] == SpringRole::Shear ? "shear" : (tension ? "tension" : "compression");
    if (!yielded_[s]) {
      yielded_[s] = 1;
      pending_[s] |= kPendingYield;
    }
    if (has_prev_[s])
      plastic_J_[s] += stored_energy_J_(s, law_force_prev, delta_prev) + 0.5 * law_force_prev * (delta - delta_prev);
    alive_[s] = 0;
    law_force_N_[s] = 0.0;
    has_prev_[s] = 0;  // also tells spring_status a deletion from a joint's break
    any_event = true;
    return false;
  }
  if (tracks_work) {
    if (has_prev_[s]) {
      // Leaving the linear branch now: the work so far is what it stored.
      if (!tracked_before) work_J_[s] = stored_energy_J_(s, law_force_prev, delta_prev);
      work_J_[s] += 0.5 * (law_force_prev + out.force_N) * (delta - delta_prev);
      plastic_J_[s] = work_J_[s] - out.stored_J;
    } else {
      work_J_[s] = out.stored_J;  // first evaluation: the rest state stores what the law says
    }
  }
  if (out.inelastic && !yielded_[s]) {
    yielded_[s] = 1;
    pending_[s] |= kPendingYield;
    failure_force_N_[s] = out.force_N;
    failure_mode_[s] = spring_role_[s] == SpringRole::Shear ? "shear" : (delta > 0.0 ? "tension" : "compression");
    any_event = true;
  }
  law_force_N = out.force_N;
  dashpot_force_N = dashpot_Nspm_[s] * rate;
  law_force_N_[s] = out.force_N;
  has_prev_[s] = 1;
  return true;
}

void JointSystem::point_springs_general_(std::size_t p, const double d_axis[3], const double v_axis[3],
                                         double f_axis[3], double fd_axis[3], JointSpringSummary& sum,
                                         bool strain_limit, bool& any_event) {
  for (int c = 0; c < 3; ++c) f_axis[c] = fd_axis[c] = 0.0;
  const auto first = std::size_t(point_first_[p]), last = std::size_t(point_first_[p + 1]);
  for (std::size_t s = first; s < last; ++s) {
    const int ax = spring_axis_[s];
    const double delta = d_axis[ax], rate = v_axis[ax];
    double f_law, f_dashpot;
    if (!alive_[s]) {
      delta_m_[s] = delta;
      rate_mps_[s] = rate;
    } else if (evaluate_spring_(s, delta, rate, f_law, f_dashpot, any_event)) {
      f_axis[ax] += f_law + f_dashpot;
      fd_axis[ax] += f_dashpot;
      count_alive_(sum, s, delta, strain_limit);
    }
  }
}

Mat3 JointSystem::update_joint_frame_(const BodyStore& bodies, std::size_t j) {
  // qa and qb start equal (add_joint) and each follows its body's
  // orientation quaternion, which the integrator moves continuously, so
  // their sum is continuous in time: its rotation is the half-way frame,
  // and it stays continuous through a half turn of the two bodies against
  // each other. (Turning qb to the hemisphere of qa, as before, jumped the
  // frame by half a turn there, flipping the normal and a shear axis: a
  // spring stiffer in compression than in tension, or a joint left with
  // one-sided springs, jumped its force and energy.) The sum vanishes only
  // at a whole relative turn, where its rotation is continuous up to that
  // one instant (q and -q are the same rotation).
  const Mat3 frame = joint_frame_now_(bodies, j);
  joint_frame_world_[j] = frame;
  return frame;
}

Mat3 JointSystem::joint_frame_now_(const BodyStore& bodies, std::size_t j) const {
  const auto [qa, qb] = joint_frame_quaternions_(bodies, j);
  Quat qm;
  qm.coeffs() = qa.coeffs() + qb.coeffs();
  qm.normalize();
  return qm.toRotationMatrix();
}

// The springs a break took out (finish_step, kill_spring_) acted with their
// law force of the breaking step n for that whole step; their books hold
// what they stored at n. At n + 1, the first evaluation after the break,
// the trapezoid of that force and the 0 that follows over the increment
// delta(n+1) - delta(n) completes them, as for a spring its law deletes
// (evaluate_spring_). delta(n+1) by joint_step_'s geometry (half-way frame,
// ends on the bodies), kept local: the springs' deformations, ends and the
// joint's frame stay those of the break for the output.
void JointSystem::close_broken_joint_books_(const BodyStore& bodies, std::size_t j) {
  joint_books_open_[j] = 0;
  const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
  const Mat3 frame = joint_frame_now_(bodies, j);
  for (auto s = std::size_t(joint_first_[j]); s < std::size_t(joint_first_[j + 1]); ++s) {
    const double f = law_force_N_[s];
    if (f == 0.0) continue;  // deleted earlier by its law (force already 0), or nothing to book
    law_force_N_[s] = 0.0;
    const Vec3 d = (bodies.position_m[b] + bodies.rotation[b] * attach_b_local_m_[s]) -
                   (bodies.position_m[a] + bodies.rotation[a] * attach_a_local_m_[s]);
    const double delta = spring_axis_[s] >= 0 ? frame.col(spring_axis_[s]).dot(d) : d.norm() - rest_length_m_[s];
    plastic_J_[s] += 0.5 * f * (delta - delta_m_[s]);
  }
}

// One joint, one pass (joint_system.h). Writes only what joint j owns: its
// springs, its points, its two slots and its flags.
void JointSystem::joint_step_(const BodyStore& bodies, std::size_t j) {
  if (joint_broken_[j]) {
    slot_force_N_[2 * j].setZero();
    slot_force_N_[2 * j + 1].setZero();
    slot_torque_Nm_[2 * j].setZero();
    slot_torque_Nm_[2 * j + 1].setZero();
    if (joint_books_open_[j]) close_broken_joint_books_(bodies, j);
    return;
  }
  const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
  const Mat3 frame = update_joint_frame_(bodies, j);
  const Mat3 ra = bodies.rotation[a], rb = bodies.rotation[b];
  const Vec3 xa = bodies.position_m[a], xb = bodies.position_m[b];
  const Vec3 va = bodies.velocity_mps[a], vb = bodies.velocity_mps[b];
  const Vec3 wa = bodies.angular_velocity_radps[a], wb = bodies.angular_velocity_radps[b];
  const std::int32_t* __restrict point_first = point_first_.data();
  const std::int8_t* __restrict axis = spring_axis_.data();
  // Written by evaluate_spring_ as well: no __restrict.
  const std::uint8_t* alive = alive_.data();
  double* delta_m = delta_m_.data();
  double* rate_mps = rate_mps_.data();

  const bool strain_limit = joint_break_[j].criterion == BreakCriterion::StrainLimit;
  JointSpringSummary sum;
  sum.springs = joint_spring_count_[j];
  sum.normal_springs = joint_normal_count_[j];
  bool any_pending = false;
  // Matrices are column-major: m[3 c + r] is row r of column c.
  const double* ra_m = ra.data();
  const double* rb_m = rb.data();
  const double* fr = frame.data();  // columns t1, t2, n
  double force_on_a[3] = {0.0, 0.0, 0.0}, torque_on_a[3] = {0.0, 0.0, 0.0};
  double dashpot_on_a[3] = {0.0, 0.0, 0.0}, dashpot_moment_a[3] = {0.0, 0.0, 0.0};

  // The joint's points in chunks. Stages 1 and 3 are loops over points with
  // no branch, on columns of doubles (structures of arrays), which the
  // compiler turns into SIMD code: every lane does the same operations in
  // the same order as one scalar point would, so results do not depend on
  // the vector width. Stage 2 runs the springs' laws point by point; stage 4
  // sums the points' forces and torques in point order.
  constexpr std::size_t kChunk = 8;
  const auto first_point = std::size_t(joint_first_point_[j]), last_point = std::size_t(joint_first_point_[j + 1]);
  for (std::size_t chunk = first_point; chunk < last_point; chunk += kChunk) {
    const std::size_t n = std::min(kChunk, last_point - chunk);
    // Per point of the chunk: arm of end a (m), separation d = p_b - p_a
    // (m), relative velocity (m/s), and d and v_rel along the joint axes.
    double arm_a[3][kChunk], d[3][kChunk], vrel[3][kChunk], d_axis[3][kChunk], v_axis[3][kChunk];
    {
      const double* __restrict la_x = point_attach_a_m_.x.data() + chunk;
      const double* __restrict la_y = point_attach_a_m_.y.data() + chunk;
      const double* __restrict la_z = point_attach_a_m_.z.data() + chunk;
      const double* __restrict lb_x = point_attach_b_m_.x.data() + chunk;
      const double* __restrict lb_y = point_attach_b_m_.y.data() + chunk;
      const double* __restrict lb_z = point_attach_b_m_.z.data() + chunk;
      double* __restrict pa_x = point_end_a_m_.x.data() + chunk;
      double* __restrict pa_y = point_end_a_m_.y.data() + chunk;
      double* __restrict pa_z = point_end_a_m_.z.data() + chunk;
      double* __restrict pb_x = point_end_b_m_.x.data() + chunk;
      double* __restrict pb_y = point_end_b_m_.y.data() + chunk;
      double* __restrict pb_z = point_end_b_m_.z.data() + chunk;
      // Loop invariants as plain scalars (the vectoriser does not see
      // through loads from the Eigen objects).
      double Ra[9], Rb[9], F[9], Xa[3], Xb[3], Va[3], Vb[3], Wa[3], Wb[3];
      for (int k = 0; k < 9; ++k) Ra[k] = ra_m[k], Rb[k] = rb_m[k], F[k] = fr[k];
      for (int k = 0; k < 3; ++k) Xa[k] = xa[k], Xb[k] = xb[k], Va[k] = va[k], Vb[k] = vb[k], Wa[k] = wa[k], Wb[k] = wb[k];
      // No column written here is read here by another point.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC ivdep
#endif
      for (std::size_t i = 0; i < n; ++i) {
        double am[3], bm[3], pa[3], pb[3];
        for (int r = 0; r < 3; ++r) {
          am[r] = Ra[r] * la_x[i] + Ra[3 + r] * la_y[i] + Ra[6 + r] * la_z[i];
          bm[r] = Rb[r] * lb_x[i] + Rb[3 + r] * lb_y[i] + Rb[6 + r] * lb_z[i];
          pa[r] = Xa[r] + am[r];
          pb[r] = Xb[r] + bm[r];
          d[r][i] = pb[r] - pa[r];
          arm_a[r][i] = am[r];
        }
        pa_x[i] = pa[0];
        pa_y[i] = pa[1];
        pa_z[i] = pa[2];
        pb_x[i] = pb[0];
        pb_y[i] = pb[1];
        pb_z[i] = pb[2];
        // v_rel = (v_b + w_b x arm_b) - (v_a + w_a x arm_a)
        const double v0 = (Vb[0] + Wb[1] * bm[2] - Wb[2] * bm[1]) - (Va[0] + Wa[1] * am[2] - Wa[2] * am[1]);
        const double v1 = (Vb[1] + Wb[2] * bm[0] - Wb[0] * bm[2]) - (Va[1] + Wa[2] * am[0] - Wa[0] * am[2]);
        const double v2 = (Vb[2] + Wb[0] * bm[1] - Wb[1] * bm[0]) - (Va[2] + Wa[0] * am[1] - Wa[1] * am[0]);
        vrel[0][i] = v0;
        vrel[1][i] = v1;
        vrel[2][i] = v2;
        for (int c = 0; c < 3; ++c) {
          d_axis[c][i] = F[3 * c] * d[0][i] + F[3 * c + 1] * d[1][i] + F[3 * c + 2] * d[2][i];
          v_axis[c][i] = F[3 * c] * v0 + F[3 * c + 1] * v1 + F[3 * c + 2] * v2;
        }
      }
    }

    // Stage 2: the springs of each point. Point springs give their force
    // along the joint axes (f_axis, fd_axis: total and dashpot part); a link
    // gives it along its own direction, in world components (link_force).
    double f_axis[3][kChunk], fd_axis[3][kChunk];
    double link_force[3][kChunk], link_dashpot[3][kChunk];
    bool any_link = false;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t p = chunk + i;
      const auto first = std::size_t(point_first[p]);
      for (int c = 0; c < 3; ++c) f_axis[c][i] = fd_axis[c][i] = 0.0;
      if (axis[first] >= 0) {
        const double point_d[3] = {d_axis[0][i], d_axis[1][i], d_axis[2][i]};
        const double point_v[3] = {v_axis[0][i], v_axis[1][i], v_axis[2][i]};
        double point_f[3], point_fd[3];
        point_springs_general_(p, point_d, point_v, point_f, point_fd, sum, strain_limit, any_pending);
        for (int c = 0; c < 3; ++c) f_axis[c][i] = point_f[c], fd_axis[c][i] = point_fd[c];
      } else {
        // A link (its own point): along its current direction.
        any_link = true;
        const std::size_t s = first;
        const double len = std::sqrt(d[0][i] * d[0][i] + d[1][i] * d[1][i] + d[2][i] * d[2][i]);
        const Vec3 e = len > 0.0 ? Vec3(Vec3(d[0][i], d[1][i], d[2][i]) / len) : direction_[s];
        direction_[s] = e;
        const double delta = len - rest_length_m_[s];
        const double rate = e[0] * vrel[0][i] + e[1] * vrel[1][i] + e[2] * vrel[2][i];
        double f = 0.0, fd = 0.0, f_law, f_dashpot;
        if (!alive[s]) {
          delta_m[s] = delta;
          rate_mps[s] = rate;
        } else if (evaluate_spring_(s, delta, rate, f_law, f_dashpot, any_pending)) {
          f = f_law + f_dashpot;
          fd = f_dashpot;
          count_alive_(sum, s, delta, strain_limit);
        }
        for (int r = 0; r < 3; ++r) {
          link_force[r][i] = f * e[r];
          link_dashpot[r][i] = fd * e[r];
        }
      }
    }

    // Stage 3: per point its world force F (on a) and dashpot force F_d,
    // and their moments about x_a: F on a and -F on b both act at the
    // mid-point (joint_system.h), so the torque is (arm_a + d/2) x F. The
    // dashpot's go to the joint's books (the power at n-1/2 and n+1/2).
    double force[3][kChunk], dashpot[3][kChunk], torque[3][kChunk], dashpot_moment[3][kChunk];
    for (std::size_t i = 0; i < n; ++i)
      for (int r = 0; r < 3; ++r) {
        force[r][i] = fr[r] * f_axis[0][i] + fr[3 + r] * f_axis[1][i] + fr[6 + r] * f_axis[2][i];
        dashpot[r][i] = fr[r] * fd_axis[0][i] + fr[3 + r] * fd_axis[1][i] + fr[6 + r] * fd_axis[2][i];
      }
    if (any_link)
      for (std::size_t i = 0; i < n; ++i)
        if (axis[std::size_t(point_first[chunk + i])] < 0)
          for (int r = 0; r < 3; ++r) {
            force[r][i] = link_force[r][i];
            dashpot[r][i] = link_dashpot[r][i];
          }
    for (std::size_t i = 0; i < n; ++i) {
      const double m0 = arm_a[0][i] + 0.5 * d[0][i], m1 = arm_a[1][i] + 0.5 * d[1][i], m2 = arm_a[2][i] + 0.5 * d[2][i];
      torque[0][i] = m1 * force[2][i] - m2 * force[1][i];
      torque[1][i] = m2 * force[0][i] - m0 * force[2][i];
      torque[2][i] = m0 * force[1][i] - m1 * force[0][i];
      dashpot_moment[0][i] = m1 * dashpot[2][i] - m2 * dashpot[1][i];
      dashpot_moment[1][i] = m2 * dashpot[0][i] - m0 * dashpot[2][i];
      dashpot_moment[2][i] = m0 * dashpot[1][i] - m1 * dashpot[0][i];
    }
    // Stage 4: sums in point order.
    for (std::size_t i = 0; i < n; ++i)
      for (int r = 0; r < 3; ++r) {
        force_on_a[r] += force[r][i];
        torque_on_a[r] += torque[r][i];
        dashpot_on_a[r] += dashpot[r][i];
        dashpot_moment_a[r] += dashpot_moment[r][i];
      }
  }
  finish_joint_(j, xa.data(), xb.data(), force_on_a, torque_on_a, dashpot_on_a, dashpot_moment_a,
                BodyVelocities{va.data(), vb.data(), wa.data(), wb.data()}, joint_break_[j], sum, any_pending);
}

void JointSystem::materialise_spring_geometry_() const {
  if (spring_geometry_current_) return;
  const std::size_t ns = spring_joint_.size();
  end_a_m_.resize(ns, Vec3::Zero());
  end_b_m_.resize(ns, Vec3::Zero());
  direction_.resize(ns, Vec3::UnitZ());
  for (std::size_t s = 0; s < ns && !point_first_.empty(); ++s) {
    const auto p = std::size_t(spring_point_[s]);
    end_a_m_[s] = point_end_a_m_[p];
    end_b_m_[s] = point_end_b_m_[p];
    if (spring_axis_[s] >= 0) direction_[s] = joint_frame_world_[std::size_t(spring_joint_[s])].col(spring_axis_[s]);
  }
  spring_geometry_current_ = true;
}

const std::vector<double>& JointSystem::spring_force_N() const {
  if (!spring_force_current_) {
    force_N_.resize(spring_joint_.size(), 0.0);
    for (std::size_t s = 0; s < force_N_.size() && !alive_.empty(); ++s)
      force_N_[s] = alive_[s] ? law_force_N_[s] + dashpot_Nspm_[s] * rate_mps_[s] : 0.0;
    spring_force_current_ = true;
  }
  return force_N_;
}

const std::vector<Vec3>& JointSystem::spring_end_a_m() const {
  materialise_spring_geometry_();
  return end_a_m_;
}

const std::vector<Vec3>& JointSystem::spring_end_b_m() const {
  materialise_spring_geometry_();
  return end_b_m_;
}

void JointSystem::kill_spring_(std::size_t s) {
  if (!alive_[s]) return;
  // has_prev_ stays set: spring_status reports the spring as JointBroken.
  // law_force_N_ keeps the force of this last step until the next
  // evaluation books its work over the step (close_broken_joint_books_);
  // nothing reads a dead spring's law force as a force.
  plastic_J_[s] += spring_elastic_J(s);
  alive_[s] = 0;
  spring_force_current_ = false;
  point_plain_[std::size_t(spring_point_[s])] = 0;
}

void JointSystem::finish_step(const BodyStore& bodies, const StepInfo& step, EventLog& events) {
  const std::size_t nj = joint_body_a_.size();
  // Dashpot dissipation of step n, as the ledger counts work: dt P(v_n) with
  // v_n = (v(n-1/2) + v(n+1/2)) / 2 on the geometry of step n, that is the
  // trapezoid of the resultant's power at n-1/2 (the force pass) and at
  // n+1/2 (the velocities the bodies now hold).
  const double half_dt = 0.5 * step.dt_s;
  // The ledger's kinetic energy at n is KE_0 + (t_0/2 + t_1 + ... +
  // t_{n-1} + t_n/2) (the start shifts v back half a step), so the first
  // step counts half.
  const double first_step_share = step.step == 0 ? 0.5 : 1.0;
  parallel_for_static(std::int64_t(nj), parallel_(spring_joint_.size()), [&](std::int64_t ji) {
    const auto j = std::size_t(ji);
    DashpotBooks& books = dashpot_books_[j];
    if (joint_broken_[j]) {  // its last dashpot term is now complete
      books.viscous_half_J = 0.0;
      return;
    }
    const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
    const double power_next = dashpot_power_W_(books, bodies.velocity_mps[a].data(), bodies.velocity_mps[b].data(),
                                               bodies.angular_velocity_radps[a].data(),
                                               bodies.angular_velocity_radps[b].data());
    const double term = half_dt * (books.power_prev_W + power_next);
    books.viscous_done_J += first_step_share * term;
    books.viscous_half_J = 0.5 * term;
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
    // The force on a of the springs deleted in this step, at their last
    // law force: this step's resultant (the slot) no longer has them.
    Vec3 released_on_a_N = Vec3::Zero();
    for (std::size_t s = first; s < last; ++s) {
      if (!pending_[s]) continue;
      if (pending_[s] & kPendingDelete) {
        const auto p = std::size_t(spring_point_[s]);
        const Vec3 along = spring_axis_[s] >= 0 ? Vec3(joint_frame_world_[j].col(spring_axis_[s]))
                                                : Vec3((point_end_b_m_[p] - point_end_a_m_[p]).normalized());
        released_on_a_N += failure_force_N_[s] * along;  // tension (+) pulls a towards b
      }
      const auto p = std::size_t(spring_point_[s]);
      e.spring_index = std::int32_t(s - first);
      e.position_m = 0.5 * (point_end_a_m_[p] + point_end_b_m_[p]);
      e.mode = failure_mode_[s];
      e.force_N = failure_force_N_[s];
      if (pending_[s] & kPendingYield) {
        e.kind = EventKind::SpringYielded;
        // Deleted in the same step: the force before deletion (= failure force).
        if (pending_[s] & kPendingDelete) e.force_N = failure_force_N_[s];
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
      // Force at failure: magnitude of the resultant the joint carried, with
      // the springs whose deletion broke it (the resultant without them,
      // 11 times the carried load in a probe's cantilever, is what the
      // survivors push with for the one step they still act).
      Vec3 where = Vec3::Zero();
      for (std::size_t s = first; s < last; ++s) {
        const auto p = std::size_t(spring_point_[s]);
        where += 0.5 * (point_end_a_m_[p] + point_end_b_m_[p]);
      }
      e.force_N = (slot_force_N_[2 * j] + released_on_a_N).norm();
      e.position_m = where / double(last - first);
      bool any_normal_dead = false;
      for (std::size_t s = first; s < last; ++s)
        if (!alive_[s] && spring_is_normal_[s]) any_normal_dead = true;
      // How it failed, whatever the criterion: past its strain limit, or by
      // deleted springs, among them a normal one (the tenon pulled out or
      // crushed), or shear springs only (it slid or twisted out).
      e.mode = joint_break_[j].criterion == BreakCriterion::StrainLimit ? "strain_limit"
               : any_normal_dead                                        ? "normal_spring_deleted"
                                                                        : "shear_spring_deleted";
      events.add(e);
      joint_broken_[j] = 1;
      joint_books_open_[j] = 1;
      for (std::size_t s = first; s < last; ++s) kill_spring_(s);
      if (bonded_) {
        bonded_->release(joint_body_a_[j], joint_body_b_[j]);
        // Pairs held through this joint and another still intact end now
        // (when the other broke first, they ended then).
        const std::size_t holds = j < held_through_of_joint_.size() ? held_through_of_joint_[j].size() : 0;
        for (std::size_t i = 0; i < holds; ++i) {
          const HeldThrough& h = held_through_[std::size_t(held_through_of_joint_[j][i])];
          const auto other = std::size_t(h.joint_1 == std::int32_t(j) ? h.joint_2 : h.joint_1);
          if (!joint_broken_[other]) bonded_->release(h.body_1, h.body_2);
        }
      }
    }
  }
}

double JointSystem::joint_viscous_J(std::size_t j) const {
  if (j >= dashpot_books_.size()) return 0.0;  // not prepared yet: no step, no dissipation
  return dashpot_books_[j].viscous_done_J - dashpot_books_[j].viscous_half_J;
}

void JointSystem::report_energy(EnergyLedger& ledger) const {
  double elastic = 0.0, plastic = 0.0, viscous = 0.0;
  for (std::size_t s = 0; s < spring_joint_.size(); ++s) {
    elastic += spring_elastic_J(s);
    plastic += plastic_J_[s];
  }
  // Through n: all of step n-1, half of step n.
  for (std::size_t j = 0; j < dashpot_books_.size(); ++j) viscous += joint_viscous_J(j);
  ledger.elastic_J += elastic;
  ledger.dissipated_plastic_J += plastic;
  ledger.dissipated_viscous_J += viscous;
}

void JointSystem::linearised_springs(const BodyStore& bodies, std::vector<LinearisedSpring>& out) const {
  // Each live spring at its initial stiffness k0 (the stiffest branch of
  // its law: spring_law.h, initial_stiffness_Npm) and its dashpot, along
  // its current direction: a joint axis of the frame body a carries, or the
  // line between its ends for a spring without one. Element: the joint.
  // Dashpots matter to the limit (linearised_network.h): a spring-level
  // ratio of 0.3 can overdamp a light rotational mode (zeta > 1) and halve
  // the stable step. Fixed bodies have zero inverse mass and drop out.
  const std::size_t ns = spring_joint_.size();
  out.reserve(out.size() + ns);
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
    LinearisedSpring r;
    r.a = a;
    r.b = b;
    r.k_Npm = stiffness0_Npm_[s];
    r.c_Nspm = dashpot_Nspm_[s];
    r.ga = -mass_scaled_gradient(bodies, a, arm_a, e);
    r.gb = mass_scaled_gradient(bodies, b, arm_b, e);
    r.element = std::int64_t(j);
    out.push_back(r);
  }
}

std::string JointSystem::describe_linearised_spring(const BodyStore& bodies, std::int64_t element) const {
  const auto j = std::size_t(element);
  std::ostringstream m;
  m << "joint " << j << " (bodies " << joint_body_a_[j] << " '" << bodies.info[joint_body_a_[j]].name << "' - "
    << joint_body_b_[j] << " '" << bodies.info[joint_body_b_[j]].name << "')";
  return m.str();
}

bool JointSystem::supports_trial_states() const {
  if (!trilinear_.ids.empty() || !curee_.ids.empty()) return false;
  for (const JointBreakDef& b : joint_break_)
    if (b.criterion == BreakCriterion::StrainLimit) return false;
  return true;
}

std::string JointSystem::trial_state_obstacle() const {
  std::string what;
  auto add = [&what](const std::string& item) { what += (what.empty() ? "" : ", ") + item; };
  auto count = [](std::size_t n, const char* one, const char* many) { return std::to_string(n) + (n == 1 ? one : many); };
  if (!trilinear_.ids.empty()) add(count(trilinear_.ids.size(), " spring", " springs") + " of law trilinear");
  if (!curee_.ids.empty()) add(count(curee_.ids.size(), " spring", " springs") + " of law curee");
  std::size_t strain_limit = 0;
  for (const JointBreakDef& b : joint_break_) strain_limit += b.criterion == BreakCriterion::StrainLimit;
  if (strain_limit > 0) add(count(strain_limit, " joint", " joints") + " with fracture: strain_limit");
  return what;
}

SpringStatus JointSystem::spring_status(std::size_t s) const {
  if (alive_.empty()) return SpringStatus::Elastic;
  if (!alive_[s]) {
    // Deleted by its own law, or taken out with its broken joint (kill_spring_)?
    // A law's deletion clears has_prev_ (evaluate_spring_), and nothing sets
    // it again; kill_spring_ leaves it set, and every spring alive at a break
    // has been evaluated (has_prev_ 1) in the pass that broke the joint.
    // has_prev_ is in the checkpoint, so the distinction survives a resume.
    if (joint_broken_[std::size_t(spring_joint_[s])] && has_prev_[s]) return SpringStatus::JointBroken;
    return SpringStatus::Deleted;
  }
  return yielded_[s] ? SpringStatus::Yielded : SpringStatus::Elastic;
}

double JointSystem::spring_strain_ratio(std::size_t s) const {
  const double d = delta_m_.empty() ? 0.0 : delta_m_[s];
  const double u = d >= 0.0 ? ultimate_t_m_[s] : ultimate_c_m_[s];
  return std::isfinite(u) ? std::abs(d) / u : 0.0;
}

double JointSystem::relative_turn_rad(const BodyStore& bodies, std::size_t j) const {
  const auto [qa, qb] = joint_frame_quaternions_(bodies, j);
  const double c = qa.coeffs().dot(qb.coeffs()) / (qa.norm() * qb.norm());
  return 2.0 * std::acos(std::clamp(c, -1.0, 1.0));
}

JointStatus JointSystem::joint_status(std::size_t j) const {
  if (joint_broken_[j]) return JointStatus::Broken;
  if (alive_.empty()) return JointStatus::Intact;
  for (auto s = std::size_t(joint_first_[j]); s < std::size_t(joint_first_[j + 1]); ++s)
    if (yielded_[s] || !alive_[s]) return JointStatus::Yielded;
  return JointStatus::Intact;
}

Vec3 JointSystem::force_from_fixed_bodies_N(const BodyStore& bodies) const {
  Vec3 sum = Vec3::Zero();
  if (slot_force_N_.size() < 2 * joint_count()) return sum;  // before the first force evaluation
  for (std::size_t j = 0; j < joint_count(); ++j) {
    if (joint_broken_[j]) continue;
    const bool fixed_a = bodies.is_fixed[std::size_t(joint_body_a_[j])] != 0;
    const bool fixed_b = bodies.is_fixed[std::size_t(joint_body_b_[j])] != 0;
    if (fixed_a && !fixed_b) sum += slot_force_N_[2 * j + 1];
    if (fixed_b && !fixed_a) sum += slot_force_N_[2 * j];
  }
  return sum;
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
