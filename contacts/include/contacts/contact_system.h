// The contacts force provider: broken members fall, collide and come to rest.
//
// One step (inside accumulate_forces, poses at n, velocities at n-1/2):
//   1. broad phase update (rebuilds only past the skin, broad_phase.h)
//   2. narrow phase per candidate pair (collide_box_box) and per box near the
//      ground (collide_box_ground), in parallel over fixed chunks of work
//      items; each chunk writes its own buffer, buffers are joined in chunk
//      order, so the contact list is the same for any thread count
//   3. contact law per point (linear_contact_law.h) with tangential history
//      looked up from the previous step's contact list: the history and
//      the point's velocity in the same pass as 2, item by item, while the
//      pair's data is in cache (a box pair that did not touch keeps its
//      separating axis, which is tested first at the next step:
//      collide_box_box.h); the law itself in a short pass over the points
//      of each chunk right after it (apply_law)
//   4. gather: each body sums the forces of its contacts in contact order
//      (one CSR list per body; on one thread the same sums in one sweep),
//      so forces are bitwise identical for any number of OpenMP threads
//
// Contact order and keys: pairs sorted by (a, b), then ground contacts
// sorted by box; points of one manifold sorted by feature. The key of a
// point is (pair, feature); the list is therefore sorted by key, and the
// history of a point is found by binary search in the previous list.
//
// Tangential history rule: created (zero) when a (pair, feature) first
// touches, carried while it touches at every step, dropped at the first step
// it does not (as LAMMPS does when a pair stops touching). A change of
// reference face or of the kind of contact (face / edge) changes the feature
// and so starts a new history. The elastic energy of a dropped shear spring,
// 1/2 |F_s|^2 / k_t, is lost with it and booked as friction dissipation (and
// the normal spring's 1/2 k_n (d - d0)^2 left at the last touch as viscous),
// so the ledger still balances.
//
// Energy booking (why: energy_ledger.h counts the work of every force as
// dt F_n . v_n with v_n = (v(n-1/2) + v(n+1/2)) / 2; a loss computed inside
// the law from v(n-1/2), the velocity the forces are computed from, misses
// that by a first-order term, zeta w dt of the impact energy). The forces
// stay those of the law at v(n-1/2); only the books change:
//   accumulate_forces (step n) keeps per point the arms p - x_a(n),
//     p - x_b(n), the relative velocity of the point at n-1/2 and the
//     elastic energies E_N(n) = 1/2 k_n (d - d0)^2, E_T(n) = 1/2 |F_s|^2 / k_t
//     and those of the same point at n-1 (zero for a new point; at step 0
//     the values at 0, which the ledger's initial stored energy holds). A
//     new point's energy counts as loaded at its first step: at first touch
//     F_n ~ c_n v >> k_n d, so a sliding point's shear spring is reset to
//     mu c_n v at once, an energy of order 1 in dt that no work put in.
//   finish_step (bodies at v(n+1/2), w(n+1/2)) forms the relative velocity
//     of the point at n, v_rel = (v_rel(n-1/2) + v_rel(n+1/2)) / 2 (the
//     ground does not move), the work of the force pair on the bodies
//     W_N = dt F_n n . v_rel (normal), W_T = dt F_t . v_rel (tangential; F on
//     b, -F on a, both applied at the point, as gather applies them), and
//     books the step's loss as
//       friction = -W_T - (E_T(n) - E_T(n-1))   when the point slides,
//       viscous  = -W_N - (E_N(n) - E_N(n-1))   (+ the tangential term when it sticks).
//     The split is a convention (sliding: the slip takes the tangential
//     loss, dashpot included; sticking: the tangential dashpot); the SUM of
//     the two is exactly -W - dE, so over a contact's life (its springs end
//     empty: see the dropped energies above) the books hold exactly the work
//     the contact did, as the ledger counts it. The contacts leave nothing
//     in the balance error; what remains is the integrator's own (rotation:
//     O(dt^2), test_contact_ledger_order) and that of other providers.
//   report_energy at n follows the ledger's trapezoid (as JointSystem does):
//     work terms count half at step 0 and half at the current step n, so
//     the losses reported are sum_{k<=n} (c_k (-W_k) - dE_k) with c_0 = c_n =
//     1/2, else 1. Consequence: a conservative contact (e = 1, mu = 0) books
//     as "viscous" (either sign) the leapfrog mismatch of its springs and
//     the jumps of stored energy when a box-box manifold switches, which
//     the former booking (in the law, from v(n-1/2)) left in the balance
//     error; the stored energy's growth still shows them.
//
// Pairs released by a joint break (STYLE.md 3.2: contacts switch on in the
// same place the joint breaks): the two members may still overlap where the
// joint held them (a beam end inside a column, a rotated tenon). A contact
// that began at that overlap would push them apart with k d at once,
// energy k d^2 / 2 that no work put in. Such a pair therefore starts from its
// overlap: each of its points takes the depth at first touch as a reference
// depth d0, the normal spring acts on d - d0 only, and d0 follows min(d0, d)
// while the point is carried, so it fades as the members separate and any
// further penetration is resisted in full. A point that appears later (the
// members slid or turned and other features touch) takes min(d, the largest
// d0 of the pair's points at the step before): with its own whole depth
// as d0 the members would sink further into each other at every change of
// features (a box rocking on a box it started in, 2026-11-26, sank 13 times
// its static deflection in 30 steps). The pair leaves this regime once
// it has no contact point at all (DEM codes use the same idea for particles
// generated in overlap).
//
// Pairs that overlap at the start: two bodies not held by a joint that
// overlap by more than kInitialOverlapTolerance_m at the first force
// evaluation (step 0) -- in a case file, a beam end inside a column it is
// not jointed to, an untrimmed brace, blocks placed into each other -- start
// from their overlap in the same way, instead of being thrown apart at the
// first step with energy k d^2 / 2 that no load put in (a 3D frame without
// trims stored 4 J that way and broke its joints within a millisecond).
// initial_overlaps() lists them, deepest first, so that the run can warn.
// The ground is not a pair: a body below the ground surface is refused by
// the case builder instead (io/src/model.cpp).
//
// Per-point stiffness: contact_params.h, scaled by the point's weight s_i
// (contact_manifold.h). Dashpot mass: the pair's reduced mass (m_a m_b /
// (m_a + m_b), or the free body's mass against a fixed body or the ground)
// shared among the touching points in proportion to s_i, so that a flat
// face impact has exactly the damping ratio of the restitution.
//
// Layout: one ContactPoint record per point (array of structs). Every stage
// after the narrow phase reads and writes whole records, so the AoS layout
// costs nothing over SoA and keeps the public view simple.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "contacts/broad_phase.h"
#include "contacts/contact_manifold.h"
#include "contacts/contact_params.h"
#include "dem_core/bonded_pairs.h"
#include "dem_core/force_provider.h"

namespace fq {

// Overlaps below this depth at the start are round-off of the geometry
// (corner heights of rotated boxes, node coordinates written in decimals);
// 1 nm keeps any real mistake (tenths of millimetres and more).
inline constexpr double kInitialOverlapTolerance_m = 1e-9;

// A pair of bodies overlapping at the start (see above).
struct InitialOverlap {
  BodyId body_a = kNoBody, body_b = kNoBody;
  double depth_m = 0.0;  // deepest point's overlap (m)
};

// One current contact point, readable for output.
struct ContactPoint {
  BodyId body_a = kNoBody;  // the ground contact reports the Ground member here (kNoBody if none)
  BodyId body_b = kNoBody;
  std::uint32_t feature = 0;
  Vec3 position_m = Vec3::Zero();      // world (m)
  Vec3 normal = Vec3::UnitZ();         // unit, world, from a to b
  double depth_m = 0.0;                // overlap (m)
  double normal_force_N = 0.0;         // >= 0 (N)
  Vec3 tangential_force_N = Vec3::Zero();  // on b, world (N)
  Vec3 shear_spring_N = Vec3::Zero();  // tangential history (N), world
  // The normal spring's force across the normal (N, world, on b): k (d -
  // d0) times the point's lean (ContactPointGeometry::lean), so that the
  // spring's force is the gradient of its energy where the point slides.
  Vec3 lean_force_N = Vec3::Zero();
  Vec3 lean = Vec3::Zero();  // ContactPointGeometry::lean
  // Overlap the pair had when its joint broke (m): the normal spring acts on
  // depth_m - reference_depth_m only (see ContactSystem).
  double reference_depth_m = 0.0;
  bool sliding = false;
  // Force on b (N, world); a receives the opposite.
  Vec3 force_N() const { return normal_force_N * normal + tangential_force_N + lean_force_N; }

  // Internal bookkeeping (valid during a step).
  std::uint64_t pair_key = 0;
  std::int32_t coeff_index = 0;
  double stiffness_scale = 1.0;
  double effective_mass_kg = 0.0;
  bool history_carried = false;  // set on the previous step's record when this step took its history
  // The law's dashpot coefficients at this step (N s/m; contact_dashpots),
  // and whether they are known: carried from the previous step's record of
  // the point when its share and mass are bitwise the same (apply_law).
  bool dashpots_known = false;
  double normal_dashpot_Nspm = 0.0;
  double tangential_dashpot_Nspm = 0.0;
  double elastic_J = 0.0;              // E_N + E_T at this step (J)
  double elastic_tangential_J = 0.0;   // E_T at this step (J)
  double elastic_prev_J = 0.0;         // E_N + E_T of the same point at the previous step (J, header)
  double elastic_tangential_prev_J = 0.0;
  Vec3 arm_a_m = Vec3::Zero();         // position_m - x_a(n) (m); zero for the ground
  Vec3 arm_b_m = Vec3::Zero();         // position_m - x_b(n) (m)
  Vec3 velocity_prev_mps = Vec3::Zero();  // velocity of the point of b relative to a at n-1/2 (m/s)
  // Losses of this step, set in finish_step (J): -W - dE split as in the
  // header (whole step, before report_energy's trapezoid weights), and
  // their work parts -W alone.
  double viscous_J = 0.0;
  double friction_J = 0.0;
  double viscous_work_loss_J = 0.0;
  double friction_work_loss_J = 0.0;
};

// The largest press of a contact spring during a run, as a fraction of the
// section of the member it moves: the pressed depth (depth_m -
// reference_depth_m) of a point over the smallest half-dimension of the
// thinner free box of its pair (a box against the ground or a fixed body
// is measured alone: the ground and fixed bodies do not bear, pivot or come
// to rest), largest over every point and step (ContactSystem::finish_step).
// A penalty contact lets members sink into each other by this much; where
// they bear, pivot and come to rest moves by about as much, a fraction
// `ratio` of the section. (The deepest press in metres may be another
// point's, on a thicker member.)
struct ContactPressPeak {
  double ratio = 0.0;             // pressed depth / half-dimension
  double depth_m = 0.0;           // pressed depth of that point (m)
  double half_dimension_m = 0.0;  // of the measured box (m)
  double time_s = 0.0;            // t_n of the step
  BodyId body_a = kNoBody;        // kNoBody against the ground
  BodyId body_b = kNoBody;
  BodyId measured = kNoBody;      // the box whose half-dimension it is (a or b)
};

struct ContactSystemSettings {
  // Broad-phase skin (m); <= 0 picks 0.4 x the thinnest box dimension.
  // Trade-off measured on a falling pile of 1e4 boxes 40 mm thick (500
  // steps): skin 8 mm -> 225 rebuilds, 8.5e3 candidate pairs; 16 mm -> 126
  // rebuilds, 1.4e4 pairs (fastest); 32 mm -> 69 rebuilds, 3.3e4 pairs. For
  // the 10 mm members of seed 001 it is 4 mm: at collapse speeds (~1 m/s,
  // dt = 1e-5 s) a member then moves for ~200 steps between rebuilds.
  double skin_m = 0.0;
  // Work below this many items (pairs, contacts, bodies) runs on one thread.
  // A parallel region pays only when each thread gets tens of microseconds
  // of work, and it costs far more than that whenever the host has no idle
  // core for the second thread (its barrier then waits for a time slice).
  // At 128, a 43-body house (about 150 contacts) ran 3.2 s on one thread
  // and 24.1 s on two while another process used a core (geometry probe,
  // 2026-11-27), and a falling pile of 1e3 boxes (617 contacts) was slower
  // on two threads than on one even on an idle host (197 against 160 ns per
  // body-step; validation/results/dev_2core/bench_contact_pile_default_
  // policy_new_host_2026-11-26.txt), while 1e3 pressed columns (8 900
  // contacts) gained 1.7x. 2048 is the joint system's threshold
  // (JointSystemSettings::parallel_min_items); measured in
  // docs/performance_history.md, change 49.
  int parallel_threshold = 2048;
  // Scenes with at least this many bodies run the broad phase (skin check
  // every step, rebuilds) on threads (broad_phase.h). Its per-body work is
  // short, so it pays only for large scenes.
  int broad_phase_parallel_bodies = 4096;
  // false: a body bonded to the ground body (BondedPairs: held by an intact
  // support joint, or through a member at a support node) does not touch
  // the ground until that hold ends, and then starts from the overlap it
  // has (as a released pair, above): seed 001's "continuous medium before
  // the fracture" (contact.intact_nodes: none, io/case_def.h). true keeps
  // a supported foot bearing on the ground.
  bool ground_under_intact_supports = true;
};

// Two surfaces closer than this count as touching for the stable-time-step
// estimate (stiffest_mode): boxes placed "resting" on each other at t = 0
// (m). 0.1 mm is far below any member size and far above round-off.
inline constexpr double kTouchMargin_m = 1e-4;

class ContactSystem : public ForceProvider {
 public:
  // `bonded` may be null (no joints); it must outlive the system.
  explicit ContactSystem(const BondedPairs* bonded, ContactSystemSettings settings = {});

  // Material index of a body (default 0).
  void set_body_material(BodyId body, int material);
  // Parameters of the material pair (i, j), symmetric. Pairs never set use
  // ContactParams{} defaults. Throws std::invalid_argument on bad values.
  void set_pair_params(int material_i, int material_j, const ContactParams& params);
  // Enables the ground half-space z <= level_m with its contact parameters.
  void set_ground(double level_m, const ContactParams& params);

  const char* name() const override { return "contacts"; }
  std::string trial_state_obstacle() const override {
    return "contact shear springs and friction (the case's contact section)";
  }
  void prepare(const BodyStore& bodies) override;
  void accumulate_forces(BodyStore& bodies, const StepInfo& step) override;
  // Books the losses of step n from the work of the contact forces with
  // v_n (header); the bodies hold v(n+1/2) and w(n+1/2).
  void finish_step(const BodyStore& bodies, const StepInfo& step, EventLog& events) override;
  void report_energy(EnergyLedger& ledger) const override;
  void linearised_springs(const BodyStore& bodies, std::vector<LinearisedSpring>& out) const override;
  std::string describe_linearised_spring(const BodyStore& bodies, std::int64_t element) const override;
  StiffestMode later_stiffest_mode(const BodyStore& bodies) const override;
  // Checkpoints (force_provider.h; contact_system_state.cpp): the contact
  // list of the last step (tangential springs, reference depths, energies
  // of each point), the pairs still starting from their overlap, the energy
  // books and the broad phase.
  void save_state(StateWriter& out) const override;
  void load_state(StateReader& in) override;

  // Current contact points (forces of the last evaluation).
  std::span<const ContactPoint> contacts() const { return contacts_; }
  std::size_t contact_count() const { return contacts_.size(); }
  // Sum of the normal forces of ground contacts (N) at the last evaluation.
  double ground_normal_force_N() const;
  // Force the ground and fixed bodies apply through contacts to the free
  // bodies they touch, summed (N, world; from the last force evaluation).
  // Part of the base shear (io: history.csv).
  Vec3 force_from_fixed_bodies_N(const BodyStore& bodies) const;
  std::int64_t broad_phase_rebuilds() const { return broad_.rebuild_count(); }
  std::size_t candidate_pair_count() const { return broad_.pairs().size(); }
  double skin_m() const { return broad_.skin_m(); }
  double elastic_J() const { return elastic_J_; }
  // Pairs of bodies that overlapped at the first force evaluation (step 0)
  // and start from their overlap (header), deepest first; empty before it.
  const std::vector<InitialOverlap>& initial_overlaps() const { return initial_overlaps_; }
  // The largest press of the contact springs so far (ContactPressPeak).
  const ContactPressPeak& press_peak() const { return press_peak_; }
  // Cumulative losses through the current step, as reported to the ledger (J).
  double dissipated_viscous_J() const { return viscous_J_ - viscous_half_J_; }
  double dissipated_friction_J() const { return friction_J_ - friction_half_J_; }
  // The friction losses of whole steps, through the current one (J): the
  // ledger's figure before it takes back the half of the current step's
  // work that falls after t_n. Coulomb sliding only dissipates, so this
  // never decreases (the ledger's figure may dip by that half step where a
  // sliding point's spring gains more than half the step's work).
  double friction_loss_whole_steps_J() const { return friction_J_; }

 private:
  // The stiffest k_n, k_t and largest damping ratio of any coefficient set
  // a contact of the kind that may form later can use (later_stiffest_mode;
  // all zero when no such contact can form; friction unused).
  enum class LaterContact { OnFixedSurface, BoxOnBox };
  ContactCoefficients stiffest_coefficients(const BodyStore& bodies, LaterContact kind) const;
  // The coefficients a contact of a and b uses (a = kNoBody: the ground),
  // from the parameters of their materials' pair (the default pair when
  // none is set) and a body's material (0 until set), before or after prepare.
  ContactCoefficients coefficients_of(BodyId a, BodyId b) const;
  ContactParams material_pair_params(int material_1, int material_2) const;
  int material_of(std::size_t body) const;
  int coeff_index_for(int material_i, int material_j) const;
  // Narrow phase and contact law of every work item (pairs, then boxes near
  // the ground), into contacts_; books the energy of the springs that ended.
  void narrow_phase(const BodyStore& bodies, const StepInfo& step);
  // One work item: writes its points into out[used], out[used + 1], ...
  // (reusing the records left there by an earlier step, appending past
  // the end; `used` advances) with geometry, history and velocities
  // (apply_law adds the forces), and returns how many; `cursor` is the
  // position in previous_ of the history search (see the .cpp);
  // `box_tests` counts the items that got past the cheap bounding test to
  // a full box test.
  std::size_t process_item(const BodyStore& bodies, std::size_t item, std::size_t& cursor,
                           ContactManifold& manifold, std::vector<ContactPoint>& out, std::size_t& used,
                           std::size_t& box_tests);
  // The contact law (linear_contact_law.h) of the records [first, last):
  // forces, shear springs (history in, updated out), energies.
  void apply_law(ContactPoint* first, ContactPoint* last, const StepInfo& step) const;
  void gather(BodyStore& bodies);

  const BondedPairs* bonded_;
  ContactSystemSettings settings_;
  std::vector<int> body_material_;
  std::map<std::pair<int, int>, ContactParams> pair_params_;
  bool ground_enabled_ = false;
  double ground_level_m_ = 0.0;
  ContactParams ground_params_;

  // Built in prepare.
  bool prepared_ = false;
  BodyId ground_body_ = kNoBody;
  std::vector<ContactCoefficients> coeffs_;  // [0] default, then set pairs, last = ground
  std::vector<int> material_coeff_;          // n_materials^2 -> coeffs_ index
  int n_materials_ = 1;
  int ground_coeff_ = 0;
  std::vector<std::uint8_t> participates_;
  std::vector<BodyId> ground_candidates_;    // bodies that may touch the ground
  BroadPhase broad_;
  std::vector<int> pair_coeff_;              // per broad-phase pair
  // Per broad-phase pair: the axis that separated it at its last test (-1:
  // none), tried first at the next (collide_box_box.h). Only a shortcut:
  // the result does not depend on it, so it is not part of the checkpoint.
  std::vector<std::int8_t> pair_separating_axis_;
  std::vector<double> bounding_radius_m_;    // per body: half-diagonal (m)

  // Per step.
  std::vector<std::vector<ContactPoint>> chunk_buffers_;
  std::vector<std::size_t> chunk_offsets_;   // where each chunk's records go in contacts_
  std::vector<double> chunk_cost_;           // narrow-phase cost of each chunk at the last step (kCost* units)
  std::vector<std::int64_t> chunk_runs_;     // first chunk of each thread's run (split_by_cost)
  std::vector<double> sum_terms_;            // terms of the energy sums, in list order
  std::vector<BodyId> contact_bodies_;       // gather: (body_a, body_b) per contact
  ContactManifold manifold_;  // scratch of the one-thread narrow phase
  std::vector<ContactPoint> contacts_;
  std::vector<ContactPoint> previous_;
  // Pairs released by a joint that have not yet separated (pair keys), and
  // how many entries of BondedPairs::released() have been read.
  std::vector<std::uint64_t> soft_start_pairs_;  // sorted
  std::size_t released_read_ = 0;
  std::vector<InitialOverlap> initial_overlaps_;
  // Per body: its smallest half-extent (m); infinite for a fixed body, which
  // a press is not measured against (ContactPressPeak).
  std::vector<double> half_dimension_m_;
  ContactPressPeak press_peak_;
  // Step 0's overlaps found; once per simulation (a checkpoint carries it).
  bool initial_overlaps_checked_ = false;
  // After step 0's narrow phase: pairs overlapping by more than the
  // tolerance join soft_start_pairs_ and initial_overlaps_; true if any did.
  bool soft_start_initial_overlaps_();
  std::vector<std::int32_t> body_start_;     // CSR of contacts per body
  std::vector<std::int32_t> body_entries_;   // contact index * 2 + (0: a side, 1: b side)
  std::vector<Vec3> body_force_N_, body_torque_Nm_;  // one-thread gather: sums per body
  std::vector<std::uint8_t> body_touched_;
  double elastic_J_ = 0.0;
  // Losses booked through the last finished step, its work term in full
  // (step 0's in half), and half the last step's work terms (J), which
  // report_energy takes off (header).
  double viscous_J_ = 0.0;
  double friction_J_ = 0.0;
  double viscous_half_J_ = 0.0;
  double friction_half_J_ = 0.0;
};

}  // namespace fq
