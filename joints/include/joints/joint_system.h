// fq::JointSystem: every joint of a scene as one force provider.
//
// Data layout (structures of arrays; springs are stored joint by joint and,
// within a joint, point by point, so a spring's global index orders (joint,
// point, spring)). A "point" is one pair of attachments: the normal and two
// shear springs of a four-corner point share it, a link has its own. One
// step is ONE pass per joint (parallel over joints for large scenes):
//   joint frame from the two bodies' orientations; per point its world ends,
//   separation d and relative velocity; per spring its deformation and rate,
//   its law (a switch on the law kind, no virtual call), dashpot force,
//   energy books, deletion and yield flags; the point's springs summed into
//   one force F applied at the mid-point of the two ends; the joint's sums
//   written to its two slots (body a, body b); the fracture test.
// Joints of the four-corner shape run the same pass four points at a time,
// their laws' initial linear branch included (the lane kernel, below).
// Then per body (parallel) its joints' slots are gathered in a fixed order
// (CSR, joint id ascending). Every write goes to a slot owned by one loop
// index and every sum runs in a fixed order, so results are bitwise identical
// for any thread count. Nothing is allocated per step.
//
// Joint frame (objective, carried by the bodies): the rest frame is stored
// relative to each body (q_ja = q_a^-1 q_j0, q_jb = q_b^-1 q_j0); the
// current frame is the half-way rotation between q_a q_ja and q_b q_jb,
// which for unit quaternions is exactly normalise(q1 + q2) (same
// hemisphere). It is read from BodyStore::orientation (the quaternion the
// rotation matrices come from); end points use BodyStore::rotation.
//
// Point springs: the force pair f e (on a, at p_a) and -f e (on b, at p_b) is
// not collinear when p_b != p_a; the frame's dependence on the rotations
// adds the torque (1/2) d x F to each body (d = p_b - p_a, F = f e), the
// exact derivative of the spring energy through the mean-rotation frame to
// first order. With it the pair conserves angular momentum exactly. The
// pair plus that torque is the force F on a and -F on b, both acting at the
// mid-point m = (p_a + p_b)/2: torque (m - x_a) x F on a, -(m - x_b) x F on
// b. The springs of a point share p_a and p_b, so their forces are summed
// first and the torques formed once per point.
//
// Energy: elastic = sum of stored energy, a function of the law force (or,
// for a linear spring, of the deformation; for a CUREE spring below its
// delta_p, of the deformation and its state) formed when someone asks;
// plastic = work done minus stored (work by the trapezoid rule on each
// step's deformation increment, kept only once a spring has left its initial
// linear branch -- until then work equals stored exactly) plus energy
// released at deletion/breaking: what the spring stored at the last step it
// acted, plus the work of that last force over the next deformation
// increment by the trapezoid with the 0 that follows (the dynamics applied
// it for that whole step; for a joint's break booked at the next
// evaluation, close_broken_joint_books_; joints/README.md "Fracture book");
// viscous = sum over steps of dt P_d(v_n), P_d the power the dashpot forces
// (and their share of the frame torque) take from the bodies, evaluated on
// the geometry of step n with v_n = (v(n-1/2) + v(n+1/2))/2 -- exactly the
// work the ledger's leapfrog bookkeeping sees (completed in finish_step,
// when v(n+1/2) is known). Per point, with F_d the sum of its dashpot
// forces: P_d = F_d . v_rel - (1/2)(d x F_d) . (w_a + w_b). Written with the
// mid-point m = (p_a + p_b)/2 where the point's forces act, v_rel = (v_b +
// w_b x (p_b - x_b)) - (v_a + w_a x (p_a - x_a)) and d = p_b - p_a, this
// is P_d = F_d . (v_b - v_a) + w_b . ((m - x_b) x F_d) - w_a . ((m - x_a) x
// F_d): the power of the dashpot forces taking part in the rigid motions of
// a and b. Summed over the points it needs only the joint's dashpot
// resultant -- the force sum F and its moments M_a, M_b about x_a and x_b
// (DashpotBooks) -- so the books are kept per joint: P = F . (v_b - v_a) +
// w_b . M_b - w_a . M_a. Reported through step n as t_0/2 + t_1 + ... +
// t_{n-1} + t_n/2: the ledger's kinetic energy at n equals KE_0 plus exactly
// that trapezoid sum of the work terms, because the start shifts v back
// half a step.
//
// Stable step: linearised_springs gives every live spring at its initial
// stiffness with its dashpot; ForceProvider's stiffest_mode (and io's
// estimate of the whole scene) find the limit of that network
// (dem_core/linearised_network.h), naming the joint of the spring that
// stores most energy in the mode that sets it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dem_core/bonded_pairs.h"
#include "dem_core/force_provider.h"
#include "dem_core/lane_isa.h"
#include "joints/fracture.h"
#include "joints/joint_layout.h"

namespace fq {

struct JointDef {
  BodyId body_a = kNoBody;
  BodyId body_b = kNoBody;
  Vec3 origin_m = Vec3::Zero();   // connection point, world, at rest (m)
  Mat3 frame = Mat3::Identity();  // columns t1, t2, n in world (orthonormal, right-handed)
  JointLayout layout;
  JointBreakDef fracture;
};

// Deleted: the spring's own law failed it (a spring_deleted event);
// JointBroken: it was alive when its joint broke and went with the joint
// (no spring_deleted event of its own).
enum class SpringStatus : std::uint8_t { Elastic = 0, Yielded = 1, Deleted = 2, JointBroken = 3 };
enum class JointStatus : std::uint8_t { Intact = 0, Yielded = 1, Broken = 2 };
enum class SpringRole : std::uint8_t { Normal = 0, Shear = 1, Link = 2 };

struct JointCounts {
  int intact = 0;   // intact and every spring still elastic
  int yielded = 0;  // intact with at least one spring yielded or deleted
  int broken = 0;
};

struct JointSystemSettings {
  // Loops run on OpenMP threads only when they have at least this many
  // items: a 16-body frame must not pay for thread start-up (DESIGN.md).
  int parallel_min_items = 2048;
  // Joints of the right shape run the lane kernel ("Lane kernel" below);
  // false sends every joint through the general code (tests compare the two).
  bool lane_kernel = true;
};

class JointSystem final : public ForceProvider {
 public:
  explicit JointSystem(BondedPairs* bonded_pairs, JointSystemSettings settings = {});

  // Adds a joint whose rest state is the bodies' current pose; registers the
  // pair as bonded. Returns the joint id (0, 1, ...). Throws
  // std::invalid_argument naming the joint and field on bad data. Must be
  // called before the first step.
  std::int32_t add_joint(const BodyStore& bodies, const JointDef& def);
  // Holds the two bodies that joints joint_1 and joint_2 join to one common
  // body (the hub of a node: two columns tenoned into the same beam) as a
  // bonded pair while both joints are intact, so that contacts skip them
  // until one of the joints breaks (contact.intact_nodes, io/case_def.h).
  // Throws std::invalid_argument unless the joints exist and share exactly
  // one body. Must be called before the first step; a checkpoint keeps the
  // bonded pairs, and the joints' broken flags say which holds have ended.
  void hold_pair_through(std::size_t joint_1, std::size_t joint_2);

  const char* name() const override { return "joints"; }
  void prepare(const BodyStore& bodies) override;
  void accumulate_forces(BodyStore& bodies, const StepInfo& step) override;
  void finish_step(const BodyStore& bodies, const StepInfo& step, EventLog& events) override;
  void report_energy(EnergyLedger& ledger) const override;
  void linearised_springs(const BodyStore& bodies, std::vector<LinearisedSpring>& out) const override;
  std::string describe_linearised_spring(const BodyStore& bodies, std::int64_t element) const override;
  // Trial states (rk4, gsl_rk8pd) are supported when every spring is linear
  // elastic (no history, never fails) and no joint has a strain limit (which
  // could break it at a trial state). Dashpot books are then approximate.
  bool supports_trial_states() const override;
  std::string trial_state_obstacle() const override;
  // Checkpoints (force_provider.h; joint_system_state.cpp): broken and
  // pending flags, every spring's deformation, rate and law force (the
  // previous values of the next step), history (law states, alive/yielded,
  // failure force and mode), work books, the joints' dashpot books, and the
  // force slots.
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override;

  // Read-only view for output (valid after a force evaluation).
  std::size_t joint_count() const { return joint_body_a_.size(); }
  std::size_t spring_count() const { return spring_joint_.size(); }
  const std::vector<Vec3>& spring_end_a_m() const;  // world (m)
  const std::vector<Vec3>& spring_end_b_m() const;  // world (m)
  // Ends of spring s on its two bodies at their current poses (m, world):
  // spring_end_*_m() are those of the last force evaluation, one step
  // before the poses an output frame draws.
  std::pair<Vec3, Vec3> spring_ends_now_m(const BodyStore& bodies, std::size_t s) const {
    const std::size_t j = std::size_t(spring_joint_[s]);
    const BodyId a = joint_body_a_[j], b = joint_body_b_[j];
    return {bodies.position_m[a] + bodies.rotation[a] * attach_a_local_m_[s],
            bodies.position_m[b] + bodies.rotation[b] * attach_b_local_m_[s]};
  }
  const std::vector<double>& spring_force_N() const;  // law + dashpot, + = tension (N)
  const std::vector<double>& spring_deformation_m() const { return delta_m_; }
  const std::vector<std::int32_t>& spring_joint() const { return spring_joint_; }
  const std::vector<SpringRole>& spring_role() const { return spring_role_; }
  SpringStatus spring_status(std::size_t s) const;
  // |delta| / ultimate deformation on the side of delta (0 for laws that never fail),
  // at the spring's last evaluation. A deleted spring of a joint that still
  // holds is still evaluated for its deformation (it carries no force), so
  // its ratio follows the gap past 1; once the joint breaks, every spring of
  // it keeps the value of the step the joint broke (docs/paraview.md).
  double spring_strain_ratio(std::size_t s) const;
  JointStatus joint_status(std::size_t j) const;
  // How far joint j's two bodies have turned against each other along the
  // path their orientation quaternions took (rad, 0 to 2 pi): 2 acos of the
  // dot product of the joint frames' quaternions, whose sum gives the
  // half-way frame (joint_frame_now_). Near 2 pi, a whole turn, that sum
  // vanishes and the frame is undefined (joints/README.md, Large rotations).
  double relative_turn_rad(const BodyStore& bodies, std::size_t j) const;
  BodyId joint_body_a(std::size_t j) const { return joint_body_a_[j]; }
  BodyId joint_body_b(std::size_t j) const { return joint_body_b_[j]; }
  std::size_t joint_first_spring(std::size_t j) const { return std::size_t(joint_first_[j]); }
  std::size_t joint_spring_count(std::size_t j) const { return std::size_t(joint_first_[j + 1] - joint_first_[j]); }
  JointCounts counts() const;
  // Force that joints to fixed bodies (supports) apply to the free bodies
  // they hold, summed (N, world; from the last force evaluation; broken
  // joints apply none). Part of the base shear (io: history.csv).
  Vec3 force_from_fixed_bodies_N(const BodyStore& bodies) const;
  // Joints that run the lane kernel (known after the first step).
  std::size_t lane_joint_count() const;
  // Stored / dissipated energy of one spring (J).
  double spring_elastic_J(std::size_t s) const;
  double spring_plastic_J(std::size_t s) const { return plastic_J_[s]; }
  // Energy dissipated by joint j's dashpots so far (J), as report_energy
  // counts it (through the last step: all of the steps before, half of it).
  double joint_viscous_J(std::size_t j) const;

 private:
  void add_spring_(std::int32_t joint, SpringRole role, std::int8_t axis, const Vec3& attach_a_local,
                   const Vec3& attach_b_local, double rest_length_m, const SpringDef& def, double reduced_mass_kg);
  void joint_step_(const BodyStore& bodies, std::size_t j);
  // The current frame of joint j (stored in joint_frame_world_ and returned).
  Mat3 update_joint_frame_(const BodyStore& bodies, std::size_t j);
  // The same frame, not stored.
  Mat3 joint_frame_now_(const BodyStore& bodies, std::size_t j) const;
  // Joint j's frame quaternions on its two bodies now (q_a q_ja, q_b q_jb),
  // whose sum is the half-way frame and whose dot product the turn.
  std::pair<Quat, Quat> joint_frame_quaternions_(const BodyStore& bodies, std::size_t j) const {
    return {bodies.orientation[joint_body_a_[j]] * joint_frame_a_[j],
            bodies.orientation[joint_body_b_[j]] * joint_frame_b_[j]};
  }
  // Books of the springs joint j's break took out, at the first evaluation
  // after it (joint_books_open_): their last force's work over that step.
  void close_broken_joint_books_(const BodyStore& bodies, std::size_t j);
  // The end of a joint's step: its summed force and torque on a (about x_a)
  // into its two slots, the fracture test and the event flag.
  // With it, the joint's dashpot resultant (force sum on a and its moment
  // about x_a, summed over points like the force) into its books, with the
  // dashpot power at n-1/2 (velocities va, vb, wa, wb).
  struct BodyVelocities {
    const double *va, *vb, *wa, *wb;  // (m/s), (rad/s), world
  };
  [[gnu::always_inline]] inline void finish_joint_(std::size_t j, const double xa[3], const double xb[3],
                                                   const double force_on_a[3], const double torque_on_a[3],
                                                   const double dashpot_force_on_a[3],
                                                   const double dashpot_moment_a[3], const BodyVelocities& v,
                                                   const JointBreakDef& fracture, const JointSpringSummary& sum,
                                                   bool any_event);
  // Law of spring s (alive) at deformation delta and rate: stores delta,
  // rate and the law force, keeps the books and flags, and returns the law
  // and dashpot forces (N). Returns false when the spring was deleted now;
  // sets any_event when it raised a yield or deletion event.
  bool evaluate_spring_(std::size_t s, double delta, double rate, double& law_force_N, double& dashpot_force_N,
                        bool& any_event);
  // Stored energy of live spring s at its last law force (deformation for
  // linear springs; deformation and state for a CUREE spring below its
  // delta_p) (J): the same expression the law evaluates.
  double stored_energy_J_(std::size_t s, double law_force_N, double delta_m) const;
  void kill_spring_(std::size_t s);
  // Per-spring ends and directions from the per-point ones (output, checkpoints).
  void materialise_spring_geometry_() const;
  bool parallel_(std::size_t n) const { return n >= std::size_t(settings_.parallel_min_items); }

  // Lane kernel (joint_lanes.cpp, joint_lane_kernels.h). A joint whose points each carry a normal
  // spring and two shear springs (in that order), with one law and one
  // dashpot for all its normal springs and one for all its shear springs,
  // trilinear or linear elastic, runs its points four at a time in SIMD
  // lanes, laws included: a point whose three springs are "plain" (alive,
  // evaluated before, never yielded, no plastic offset; point_plain_) and
  // stay on their initial linear branch this step gets force = k0 delta in
  // its lane, with the bits the scalar law gives; any other point runs the
  // general spring code (point_springs_general_) for its lane. Other joints
  // (links, mixed laws, CUREE springs) run joint_step_.
  struct LaneLaw {  // a trilinear law's initial branch; a linear law has infinite bounds
    double k0_t_Npm, k0_c_Npm, k1_t_Npm, k1_c_Npm, fy_t_N, fy_c_N, dy_t_m, dy_c_m, du_t_m, du_c_m;
  };
  void prepare_lanes_();
  // The frames of the lane joints among [first, last), before their joint_step_lanes_.
  void update_lane_frames_(const BodyStore& bodies, std::size_t first, std::size_t last);
  void joint_step_lanes_(const BodyStore& bodies, std::size_t j);
  // The two above in each SIMD form (joint_lane_kernels.h); they call the
  // form prepare_lanes_ chose (dem_core/lane_isa.h): the same bits in every form.
  void update_lane_frames_sse2_(const BodyStore& bodies, std::size_t first, std::size_t last);
  void joint_step_lanes_sse2_(const BodyStore& bodies, std::size_t j);
  void update_lane_frames_avx2_(const BodyStore& bodies, std::size_t first, std::size_t last);
  void joint_step_lanes_avx2_(const BodyStore& bodies, std::size_t j);
  void update_lane_frames_avx512vl_(const BodyStore& bodies, std::size_t first, std::size_t last);
  void joint_step_lanes_avx512vl_(const BodyStore& bodies, std::size_t j);
  bool spring_is_plain_(std::size_t s) const;
  void refresh_point_plain_(std::size_t p);
  // Stage 2 of joint_step_ for point p (its springs along the joint axes):
  // deformations d_axis[c] and rates v_axis[c] along axis c in, the point's
  // total and dashpot forces along the axes out.
  void point_springs_general_(std::size_t p, const double d_axis[3], const double v_axis[3], double f_axis[3],
                              double fd_axis[3], JointSpringSummary& sum, bool strain_limit, bool& any_event);
  // Live spring s at deformation delta (m) into the joint's summary (fracture.h).
  // (Always inlined: the AVX2 and AVX-512VL kernels must not emit a shared
  // copy, CMake's check_avx2_objects.)
  [[gnu::always_inline]] void count_alive_(JointSpringSummary& sum, std::size_t s, double delta,
                                           bool strain_limit) const {
    ++sum.springs_alive;
    if (spring_is_normal_[s]) ++sum.normal_springs_alive;
    // Only the strain-limit criterion reads it.
    if (strain_limit) sum.max_strain = std::max(sum.max_strain, std::abs(delta) / reference_length_m_[s]);
  }
  std::vector<std::uint8_t> joint_lanes_;  // joint j runs joint_step_lanes_
  // What the lane kernel reads of a joint that is the same for every joint
  // of its type (layout, laws, dashpots, fracture rule, body geometry at the
  // attachments) is stored once per distinct set, compared bit for bit, and
  // a joint holds the index of its set: at 1e5 joints the kernel then reads
  // 4 bytes per joint instead of 240 (two law indices, two dashpot
  // coefficients, the fracture rule and spring counts, 48 bytes; six
  // attachment coordinates per point, 192 bytes for four points), bytes
  // that came from memory at every step (performance_history.md, change 52).
  struct LaneType {
    std::int32_t law_n, law_s;  // lane_laws_ of its normal and shear springs
    double c_n_Nspm, c_s_Nspm;  // dashpot coefficients (N s/m)
    JointBreakDef fracture;
    std::int32_t springs, normal_springs;
    std::int32_t first_attach;  // its points' attachments: lane_attach_*_m_[first_attach + k]
  };
  std::vector<LaneType> lane_types_;
  std::vector<std::int32_t> joint_lane_type_;  // lane_types_ of joint j (-1: not a lane joint)
  std::vector<LaneLaw> lane_laws_;
  std::vector<std::uint8_t> point_plain_;  // every spring of point p is plain (see above)
  LaneIsa lane_form_ = LaneIsa::Sse2;      // the SIMD form of the kernels that runs (prepare_lanes_)

  BondedPairs* bonded_;
  // Pairs held through a common body (hold_pair_through): released when the
  // first of the two joints breaks.
  struct HeldThrough {
    std::int32_t joint_1, joint_2;
    BodyId body_1, body_2;
  };
  std::vector<HeldThrough> held_through_;
  std::vector<std::vector<std::int32_t>> held_through_of_joint_;  // indices into held_through_, per joint
  JointSystemSettings settings_;
  bool prepared_ = false;
  std::size_t body_count_ = 0;

  // Joints.
  std::vector<BodyId> joint_body_a_, joint_body_b_;
  std::vector<Quat> joint_frame_a_, joint_frame_b_;  // rest frame relative to body a / b
  std::vector<Mat3> joint_frame_world_;              // current frame (columns t1, t2, n)
  std::vector<std::int32_t> joint_first_;            // springs [first[j], first[j+1])
  std::vector<JointBreakDef> joint_break_;
  std::vector<std::uint8_t> joint_broken_;
  // Broken in the last finish_step; its springs' law forces of that step
  // wait for close_broken_joint_books_.
  std::vector<std::uint8_t> joint_books_open_;
  std::vector<std::uint8_t> joint_break_pending_;
  std::vector<std::uint8_t> joint_event_pending_;  // any spring event or break to emit

  // Springs: definition.
  std::vector<std::int32_t> spring_joint_;
  std::vector<SpringRole> spring_role_;
  std::vector<std::int8_t> spring_axis_;                   // 0, 1, 2 joint-frame axis; -1 for links
  std::vector<Vec3> attach_a_local_m_, attach_b_local_m_;  // body frames (m)
  std::vector<std::uint8_t> spring_is_normal_;            // normal spring of a point, or axial link
  std::vector<std::int32_t> spring_point_;
  std::vector<std::int32_t> law_index_;  // index into the batch of its law kind
  std::vector<double> rest_length_m_;                      // links (m)
  std::vector<double> reference_length_m_;
  std::vector<double> dashpot_Nspm_;
  std::vector<double> stiffness0_Npm_;
  std::vector<double> ultimate_t_m_, ultimate_c_m_;
  std::vector<SpringLawKind> law_kind_;
  // Points: springs [point_first_[p], point_first_[p+1]); joint j owns
  // points [joint_first_point_[j], joint_first_point_[j+1]).
  std::vector<std::int32_t> point_first_, joint_first_point_;
  // Per-point vectors as three columns of doubles, so that the point loops
  // of joint_step_ run in SIMD lanes.
  struct Vec3Columns {
    std::vector<double> x, y, z;
    void assign(std::size_t n) { x.assign(n, 0.0), y.assign(n, 0.0), z.assign(n, 0.0); }
    void push_back(const Vec3& v) { x.push_back(v.x()), y.push_back(v.y()), z.push_back(v.z()); }
    Vec3 operator[](std::size_t i) const { return Vec3(x[i], y[i], z[i]); }
    void set(std::size_t i, const Vec3& v) { x[i] = v.x(), y[i] = v.y(), z[i] = v.z(); }
    std::size_t size() const { return x.size(); }
  };
  Vec3Columns point_attach_a_m_, point_attach_b_m_;  // body frames (m)
  Vec3Columns lane_attach_a_m_, lane_attach_b_m_;    // the same per LaneType (lane kernel)
  Vec3Columns point_end_a_m_, point_end_b_m_;        // world, this step (m)
  // Dashpot books per joint (see Energy above): the dashpot resultant of
  // step n -- force on a (N, world) and its moments about x_a and x_b (N m),
  // the forces acting at the points' mid-points -- its power at v(n-1/2)
  // (W), and the trapezoid sums (J). One record per joint, read together.
  struct DashpotBooks {
    double force_N[3], moment_a_Nm[3], moment_b_Nm[3];
    double power_prev_W, viscous_done_J, viscous_half_J;
  };
  std::vector<DashpotBooks> dashpot_books_;
  // P = F . (v_b - v_a) + w_b . M_b - w_a . M_a (W): the dashpot power of
  // a joint at the given velocities, the same expression at n-1/2 and n+1/2.
  [[gnu::always_inline]] static inline double dashpot_power_W_(const DashpotBooks& books, const double va[3],
                                                                const double vb[3], const double wa[3],
                                                                const double wb[3]);
  std::vector<std::int32_t> joint_spring_count_, joint_normal_count_;
  // Springs: per step. Ends and directions of springs are filled from the
  // points on demand (mutable cache), except link directions (their
  // fallback when the ends coincide); so is the total force law + dashpot.
  mutable std::vector<Vec3> end_a_m_, end_b_m_, direction_;
  mutable bool spring_geometry_current_ = false;
  mutable std::vector<double> force_N_;
  mutable bool spring_force_current_ = false;
  // Deformation, rate and law force of the last evaluation; at the next one
  // they are the previous step's values the work books need.
  std::vector<double> delta_m_, rate_mps_, law_force_N_;
  // Springs: history and books.
  std::vector<std::uint8_t> alive_, yielded_;
  std::vector<std::uint8_t> pending_;  // bit 1: yielded now, bit 2: deleted now
  std::vector<double> failure_force_N_;
  std::vector<const char*> failure_mode_;
  std::vector<std::uint8_t> has_prev_;
  // Work done on a spring (J), kept once it has left its initial linear
  // branch (CUREE springs always); plastic = work - stored, plus what was
  // stored when the spring was deleted.
  std::vector<double> work_J_, plastic_J_;
  // Slots: 2 j for body a, 2 j + 1 for body b of joint j.
  std::vector<Vec3> slot_force_N_, slot_torque_Nm_;
  std::vector<std::int32_t> body_slot_first_, body_slots_;

  // Law batches: the springs of each kind with their states (member k of a
  // batch is spring ids[k]) and the distinct parameter sets they use
  // (law[law_of[k]]): a scene has a few joint types but may have 1e6
  // springs, and one shared parameter set stays in cache.
  template <class Law, class State>
  struct Batch {
    std::vector<std::int32_t> ids;
    std::vector<std::int32_t> law_of;
    std::vector<Law> law;
    std::vector<State> state;
    std::unordered_map<std::string, std::int32_t> law_lookup;  // bytes of a parameter set -> index
    // Adds spring s with parameters l; returns its member index k.
    std::int32_t add(std::int32_t s, const Law& l) {
      const std::string key(reinterpret_cast<const char*>(&l), sizeof(Law));
      const auto [it, added] = law_lookup.emplace(key, std::int32_t(law.size()));
      if (added) law.push_back(l);
      ids.push_back(s);
      law_of.push_back(it->second);
      state.emplace_back();
      return std::int32_t(ids.size() - 1);
    }
  };
  Batch<LinearElasticParams, LinearElasticState> linear_;
  Batch<TrilinearLaw, TrilinearState> trilinear_;
  Batch<CureeLaw, CureeState> curee_;
};

inline double JointSystem::dashpot_power_W_(const DashpotBooks& books, const double va[3], const double vb[3],
                                           const double wa[3], const double wb[3]) {
  const double* f = books.force_N;
  const double *ma = books.moment_a_Nm, *mb = books.moment_b_Nm;
  return (f[0] * (vb[0] - va[0]) + f[1] * (vb[1] - va[1]) + f[2] * (vb[2] - va[2])) +
         (wb[0] * mb[0] + wb[1] * mb[1] + wb[2] * mb[2]) - (wa[0] * ma[0] + wa[1] * ma[1] + wa[2] * ma[2]);
}

// Inline: called once per joint from joint_step_ and the lane kernels, for
// some 30 instructions whose call and argument copies cost as many again.
inline void JointSystem::finish_joint_(std::size_t j, const double xa[3], const double xb[3], const double force_on_a[3],
                                       const double torque_on_a[3], const double dashpot_force_on_a[3],
                                       const double dashpot_moment_a[3], const BodyVelocities& v,
                                       const JointBreakDef& fracture, const JointSpringSummary& sum,
                                       bool any_event) {
  // Torque on b: -(m - x_b) x F = -(m - x_a) x F + (x_b - x_a) x F, summed over points.
  const double* f = force_on_a;
  const double ab[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
  const double ab_x_f[3] = {ab[1] * f[2] - ab[2] * f[1], ab[2] * f[0] - ab[0] * f[2], ab[0] * f[1] - ab[1] * f[0]};
  double* slot_fa = slot_force_N_[2 * j].data();
  double* slot_fb = slot_force_N_[2 * j + 1].data();
  double* slot_ta = slot_torque_Nm_[2 * j].data();
  double* slot_tb = slot_torque_Nm_[2 * j + 1].data();
  // Component by component, not in a loop: GCC vectorises such a loop
  // behind some twenty instructions of run-time alias checks.
  slot_fa[0] = f[0], slot_fa[1] = f[1], slot_fa[2] = f[2];
  slot_fb[0] = -f[0], slot_fb[1] = -f[1], slot_fb[2] = -f[2];
  slot_ta[0] = torque_on_a[0], slot_ta[1] = torque_on_a[1], slot_ta[2] = torque_on_a[2];
  slot_tb[0] = ab_x_f[0] - torque_on_a[0], slot_tb[1] = ab_x_f[1] - torque_on_a[1];
  slot_tb[2] = ab_x_f[2] - torque_on_a[2];
  // The dashpot resultant the same way: M_b = M_a - (x_b - x_a) x F.
  DashpotBooks& books = dashpot_books_[j];
  const double* fd = dashpot_force_on_a;
  books.force_N[0] = fd[0], books.force_N[1] = fd[1], books.force_N[2] = fd[2];
  books.moment_a_Nm[0] = dashpot_moment_a[0], books.moment_a_Nm[1] = dashpot_moment_a[1];
  books.moment_a_Nm[2] = dashpot_moment_a[2];
  books.moment_b_Nm[0] = dashpot_moment_a[0] - (ab[1] * fd[2] - ab[2] * fd[1]);
  books.moment_b_Nm[1] = dashpot_moment_a[1] - (ab[2] * fd[0] - ab[0] * fd[2]);
  books.moment_b_Nm[2] = dashpot_moment_a[2] - (ab[0] * fd[1] - ab[1] * fd[0]);
  books.power_prev_W = dashpot_power_W_(books, v.va, v.vb, v.wa, v.wb);
  const bool brk = joint_should_break(fracture, sum);
  joint_break_pending_[j] = brk ? 1 : 0;
  // Kept until finish_step emits the events (an evaluation without a
  // finish_step in between must not lose them).
  if (brk || any_event) joint_event_pending_[j] = 1;
}

}  // namespace fq
