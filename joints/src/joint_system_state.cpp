// Checkpoint state of the joint system (joint_system.h, force_provider.h).
// Everything written here is what a step leaves behind for the next one, or
// for the output between steps; definitions (attachments, laws, dashpots,
// fracture rules) are rebuilt from the case and only their sizes are
// checked. A member added to JointSystem that carries history must be
// added here as well.
#include <string>

#include "dem_core/state_io.h"
#include "joints/joint_system.h"

namespace fq {

namespace {

// 2: force slots per joint (were per spring); dashpot books on a point's first spring.
// 3: no copies of what a spring's deformation and law force give (previous
//    values, total and dashpot force, stored energy); dashpot books per point.
// 4: dashpot books per joint (the dashpot resultant, joint_system.h "Energy").
// 5: joints broken in the last step whose books close at the next one
//    (their springs keep the law force of the break until then).
constexpr std::uint32_t kJointStateVersion = 5;

template <class T>
void read_into(StateReader& in, std::vector<T>& out_values, const char* what) {
  out_values = in.vec<T>(what, out_values.size());
}

void read_into(StateReader& in, std::vector<Vec3>& out_values, const char* what) {
  out_values = in.vec3s(what, out_values.size());
}

}  // namespace

void JointSystem::save_state(StateWriter& out) const {
  out.section("joints");
  out.u32(kJointStateVersion);
  out.u64(joint_body_a_.size());
  out.u64(spring_joint_.size());
  out.u64(trilinear_.state.size());
  out.u64(curee_.state.size());
  out.boolean(prepared_);

  out.mat3s(joint_frame_world_);
  out.vec(joint_broken_);
  out.vec(joint_books_open_);
  out.vec(joint_break_pending_);
  out.vec(joint_event_pending_);

  materialise_spring_geometry_();
  out.vec3s(end_a_m_);
  out.vec3s(end_b_m_);
  out.vec3s(direction_);
  out.vec(delta_m_);
  out.vec(rate_mps_);
  out.vec(law_force_N_);
  out.vec(alive_);
  out.vec(yielded_);
  out.vec(pending_);
  out.vec(failure_force_N_);
  out.u64(failure_mode_.size());
  for (const char* mode : failure_mode_) out.str(mode ? mode : "");
  out.vec(has_prev_);
  out.vec(work_J_);
  out.vec(plastic_J_);
  for (const DashpotBooks& books : dashpot_books_) {
    for (double v : books.force_N) out.f64(v);
    for (double v : books.moment_a_Nm) out.f64(v);
    for (double v : books.moment_b_Nm) out.f64(v);
    out.f64(books.power_prev_W);
    out.f64(books.viscous_done_J);
    out.f64(books.viscous_half_J);
  }
  out.vec3s(slot_force_N_);
  out.vec3s(slot_torque_Nm_);

  // Law histories, field by field (no padding bytes in the file).
  for (const TrilinearState& st : trilinear_.state) out.f64(st.plastic_offset_m);
  for (const CureeState& st : curee_.state) {
    out.f64(st.delta_prev_m);
    out.f64(st.force_prev_N);
    out.f64(st.reversal_delta_m);
    out.f64(st.reversal_force_N);
    out.f64(st.dmax_pos_m);
    out.f64(st.dmax_neg_m);
    out.pod(st.direction);
    out.boolean(st.has_reversal);
    out.boolean(st.yielded);
    out.boolean(st.beyond_pinch);
  }
}

void JointSystem::load_state(StateReader& in) {
  in.section("joints");
  const std::uint32_t version = in.u32("joint state version");
  if (version != kJointStateVersion)
    in.fail("joint state version " + std::to_string(version) + ", this build reads " +
            std::to_string(kJointStateVersion));
  auto expect = [&](std::size_t have, const char* what) {
    const std::uint64_t saved = in.u64(what);
    if (saved != have)
      in.fail(std::string("the state has ") + std::to_string(saved) + " " + what + ", this scene " +
              std::to_string(have));
  };
  expect(joint_body_a_.size(), "joints");
  expect(spring_joint_.size(), "springs");
  expect(trilinear_.state.size(), "trilinear springs");
  expect(curee_.state.size(), "CUREE springs");
  const bool prepared = in.boolean("prepared flag");
  if (!prepared) in.fail("the joint state was saved before the joints were prepared");
  if (!prepared_) in.fail("load_state called on joints that are not prepared (initialize the simulation first)");

  // Every array keeps its size (checked by read_into); a failure part-way
  // leaves a half-loaded system, which the caller discards.
  joint_frame_world_ = in.mat3s("joint frames", joint_frame_world_.size());
  read_into(in, joint_broken_, "joint broken flags");
  read_into(in, joint_books_open_, "joint open books flags");
  read_into(in, joint_break_pending_, "joint break flags");
  read_into(in, joint_event_pending_, "joint event flags");

  read_into(in, end_a_m_, "spring ends a");
  read_into(in, end_b_m_, "spring ends b");
  read_into(in, direction_, "spring directions");
  read_into(in, delta_m_, "spring deformations");
  read_into(in, rate_mps_, "spring rates");
  read_into(in, law_force_N_, "spring law forces");
  read_into(in, alive_, "spring alive flags");
  read_into(in, yielded_, "spring yielded flags");
  read_into(in, pending_, "spring pending flags");
  read_into(in, failure_force_N_, "spring failure forces");
  const std::uint64_t modes = in.u64("spring failure modes");
  if (modes != failure_mode_.size()) in.fail("spring failure modes: count differs from the spring count");
  for (const char*& mode : failure_mode_) mode = intern_event_mode(in.str("spring failure mode"));
  read_into(in, has_prev_, "history flags");
  read_into(in, work_J_, "spring work");
  read_into(in, plastic_J_, "spring plastic energy");
  for (DashpotBooks& books : dashpot_books_) {
    for (double& v : books.force_N) v = in.f64("joint dashpot books");
    for (double& v : books.moment_a_Nm) v = in.f64("joint dashpot books");
    for (double& v : books.moment_b_Nm) v = in.f64("joint dashpot books");
    books.power_prev_W = in.f64("joint dashpot books");
    books.viscous_done_J = in.f64("joint dashpot books");
    books.viscous_half_J = in.f64("joint dashpot books");
  }
  read_into(in, slot_force_N_, "joint force slots");
  read_into(in, slot_torque_Nm_, "joint torque slots");
  // Point ends from the springs' (the springs of a point share them).
  for (std::size_t p = 0; p + 1 < point_first_.size(); ++p) {
    point_end_a_m_.set(p, end_a_m_[std::size_t(point_first_[p])]);
    point_end_b_m_.set(p, end_b_m_[std::size_t(point_first_[p])]);
  }
  spring_geometry_current_ = true;
  spring_force_current_ = false;

  for (TrilinearState& st : trilinear_.state) st.plastic_offset_m = in.f64("trilinear plastic offset");
  for (CureeState& st : curee_.state) {
    st.delta_prev_m = in.f64("CUREE state");
    st.force_prev_N = in.f64("CUREE state");
    st.reversal_delta_m = in.f64("CUREE state");
    st.reversal_force_N = in.f64("CUREE state");
    st.dmax_pos_m = in.f64("CUREE state");
    st.dmax_neg_m = in.f64("CUREE state");
    st.direction = in.pod<std::int8_t>("CUREE state");
    st.has_reversal = in.boolean("CUREE state");
    st.yielded = in.boolean("CUREE state");
    st.beyond_pinch = in.boolean("CUREE state");
  }
  // Which points the lane kernel may take follows from the springs' state.
  for (std::size_t p = 0; p < point_plain_.size(); ++p) refresh_point_plain_(p);
}

}  // namespace fq
