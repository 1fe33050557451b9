// Running a case end to end: case definition -> model -> simulation with its
// force providers -> output folder. Used by the command line, by tests and by
// the comparison and sweep commands, so every way of running a case is the
// same code.
//
// Order of checks: everything a user can get wrong (case values, records, a
// time step above the stable limit) is checked before the output folder is
// touched, so a refused run leaves nothing behind.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem_core/simulation.h"
#include "contacts/contact_system.h"
#include "io/case_def.h"
#include "io/run_output.h"
#include "io/storey_drift.h"
#include "joints/joint_system.h"

namespace fq {


struct CaseRunOptions {
  std::optional<std::filesystem::path> output_folder;  // overrides the case's output.folder
  bool allow_unstable_time_step = false;  // run even if dt exceeds the stable estimate (--force)
  // E.g. the terminal progress display: asked after every step (and at the
  // start and end), so its on_sample must be cheap.
  StepObserver* progress = nullptr;
  const std::atomic<bool>* stop_requested = nullptr;  // set (e.g. by SIGINT) to stop after the current step
  std::optional<Integrator> integrator;   // overrides the case's time.integrator (--integrator)
  // Write OUT/checkpoint.bin (io/checkpoint.h) every so many simulated
  // seconds (> 0, rounded to whole steps), and at the last state of a run
  // that stops; unset = no checkpoints. resume_case keeps the interval of
  // the checkpointed run.
  std::optional<double> checkpoint_every_s;
  // Called with each warning as it arises (the kWarn* checks below): the forced
  // time step before the first step, the ledger's checks after the last.
  // Every warning is also in the report and in summary.json.
  std::function<void(const std::string&)> on_warning;
  // Called before the first step with notes that are not doubts about the
  // results: an output interval rounded to whole steps (the interval used
  // is also in summary.json). Not in the report's warnings.
  std::function<void(const std::string&)> on_note;
};

struct StableTimeStep {
  // factor / omega_max with the integrator's stability factor (integrator.h:
  // 2 for central difference, velocity Verlet, symplectic Euler; 2 sqrt 2 for
  // RK4; 0 for forward Euler, for which no limit is estimated (stable only
  // while dt < 2 zeta / omega on each mode, never on an undamped one);
  // infinite for gsl_rk8pd).
  double dt_crit_s = std::numeric_limits<double>::infinity();
  double omega_max_radps = 0.0;  // stiffest mode over all providers (rad/s)
  std::string stiffest_element;  // where omega_max was found ("" when nothing is stiff)
};

// A simulation assembled from a case, with its providers attached.
struct Scene {
  std::unique_ptr<Simulation> simulation;
  JointSystem* joints = nullptr;      // owned by the simulation; null when the case has no joints
  ContactSystem* contacts = nullptr;  // owned by the simulation; null without a contact section
  std::vector<std::string> joint_labels;  // per joint id: where it is and its type
  std::vector<std::string> joint_types;   // per joint id: its joint type's name
  std::vector<std::string> joint_names;   // per joint id: "node:member_a-member_b" (io/joint_builder.h)
  std::vector<std::string> joint_nodes;   // per joint id: its node's id
  StableTimeStep stable_time_step;
  std::vector<Storey> storeys;  // from the columns; empty without columns (io/storey_drift.h)
};

// Builds bodies, ground motion and force providers; throws InputError for
// problems the model builder finds.
Scene build_scene(const CaseDef& def);

// What a storey did in a run (also in summary.json under "storeys").
struct StoreyOutcome {
  int number = 0;
  double height_m = 0.0;
  StoreyDriftRecord drift;  // peaks, residual, collapse time
  StoreyVerdict verdict = StoreyVerdict::Standing;
};

struct CaseRunReport {
  RunResult result;
  std::filesystem::path output_folder;
  StableTimeStep stable_time_step;
  std::vector<StoreyOutcome> storeys;
  AssessmentDef assessment;
  JointCounts joints;                   // at the end (all zero without joints)
  std::size_t joint_count = 0;
  double first_joint_failure_time_s = std::numeric_limits<double>::quiet_NaN();  // NaN: none
  std::string first_joint_failure;  // its joint's label ("node n2: column c1 - beam b1 (type t)"); "": none
  std::string first_joint_failure_name;  // its joint's name as in events.csv ("n2:c1-b1"); "": none
  // When that joint broke: at the first failure's time (the failure broke
  // it), later (it lost a spring and broke after; studies probe: it read
  // 'lost a spring and held'), or NaN when it never broke.
  double first_joint_failure_break_time_s = std::numeric_limits<double>::quiet_NaN();
  double energy_balance_error_relative = 0.0;
  double peak_ground_acceleration_mps2 = 0.0;  // horizontal PGA: peak of |(a_x, a_y)| of a_g (scaled)
  double wall_s = 0.0;
  // Reasons to doubt a run that ran (the kWarn* checks below); empty for a sound run.
  std::vector<std::string> warnings;
};

// Thresholds of the run's warnings (summary.json "warnings"):
//  - the time step is longer than a record's sample interval as the run
//    plays it (dt x time_scale): the run steps over samples and may miss
//    the peak (ground_motion_sampling_warning);
//  - rk4 with record samples inside its steps, where it is second order,
//    not fourth (runge_kutta_sampling_warning);
//  - the time step exceeds the stable estimate (a run forced with --force);
//  - a node lies inside a member without being one of its ends
//    (nodes_inside_members_warning);
//  - two members' end nodes lie closer than half the thinner section of
//    their members without being one node (near_nodes_warning);
//  - a node is the end of no member (unused_nodes_warning);
//  - a member is held by no joint in a case that has joints
//    (unjoined_members_warning), or a brace at one of its ends
//    (brace_free_ends_warning);
//  - a brace ends at a supported node where another member also ends, so
//    it is joined twice there (brace_on_supported_node_warning);
//  - a joint rule makes no joint (unused_joint_rules_warning);
//  - a member of kind column is horizontal, so it spans no storey
//    (horizontal_columns_warning);
//  - a column of rectangular section is turned by more than
//    kTurnedSectionTolerance_deg against every member framing into it, as
//    in a plan drawn off the axes without roll_deg
//    (turned_column_sections_warning);
//  - a case with members has none of kind column, so it has no storeys,
//    no storey drift and no verdict (no_columns_warning);
//  - a member is more than kSlenderMemberRatio times longer than its
//    section is thin, as when coordinates are typed in mm
//    (slender_members_warning);
//  - a member's section is wider than the member is long, as when section
//    sizes are typed in mm (stout_members_warning);
//  - a record whose header names a vertical component is applied along a
//    horizontal direction, or a horizontal one vertically
//    (ground_motion_direction_warnings);
//  - bodies not held by a joint overlap at the start by more than
//    kInitialOverlapTolerance_m (contacts/contact_system.h), which their
//    contacts then take as their rest state (initial_overlap_warning);
//  - the energy ledger does not close to kWarnBalanceErrorRelative of the
//    largest energy in play: at a stable step it closes to second order in
//    dt, 1.9e-10 to 1.0e-3 in the frame cases, the demos and the amplitude
//    sweeps at dt = 1e-5 s (validation/results/frames_sweep_*, 54 runs to
//    twice the recorded amplitude, collapses with impacts included), and
//    up to 1.5e-3 in the frames forced to twice the estimate; at 2.5 and
//    three times frame A's reaches 1.7e-2 and 3.6e-2 and is warned, though
//    its verdict is still right (validation/results/frames_time_step.md);
//  - the dashpots gained energy, more than kWarnViscousGainRelative of the
//    largest energy in play. A dashpot only dissipates; its discrete force,
//    read from v(n-1/2) and booked with the leapfrog mean velocity, does
//    net positive work only while a damped mode's velocity reverses and
//    grows from step to step, i.e. the mode is unstable at this dt (a
//    unilateral contact can keep such a mode bounded, so the energy guard
//    of the step loop does not fire). Sound runs book +0.04 to +0.84 of the
//    energy in play as viscous loss (the frames at dt = 1e-5 s).
// A warning marks a run not to be trusted; its absence is no proof of a good
// one: frame B forced to four times the estimate collapses where it stands
// below, with neither ledger warning (balance error 4.4e-3, dashpots +0.13;
// docs/speed_accuracy.md; before the sliding change of 2026-11-26 frames B
// and C both did, and before the contact changes earlier that day B alone).
// Only the forced-step warning is certain to cover such a run, which is why
// dt above the estimate is refused unless forced.
constexpr double kWarnBalanceErrorRelative = 1e-2;
constexpr double kWarnViscousGainRelative = 1e-3;
// Without dashpots, the viscous book holds the contact springs'
// discretisation error (the work of their forces over a step against the
// change of their stored energy), either sign. For a resolved contact it is
// the shadow-energy error of central difference, about (omega dt)^2 / 4 of
// the contact's energy: below 0.1 while omega dt < 0.63. A resting slab
// with restitution 1 at 0.81 of its stable estimate gained 93 % of the
// energy in play this way, with a closed balance (stable-step probe:
// contacts switching on and off are not the linear modes the estimate
// bounds); at 0.4 and 0.2 of the estimate its book held 5e-3 and 1.1e-3.
constexpr double kWarnContactDiscretisationRelative = 0.1;

// The ledger's two warnings above for the end of a run (empty when the
// balance closes and the dashpots dissipated). Without dashpots in the
// scene (`has_dashpots` false: no joint spring with a dashpot, no contact
// with restitution below 1 that can happen: the ground's, or a material
// pair's where two bodies of those materials exist) the viscous book holds only the discretisation
// error of the contact springs: its sign is not warned about, its size is
// (kWarnContactDiscretisationRelative); the
// advice of the balance warning names the integrator for forward Euler
// (no dt helps on an undamped mode; on a damped one only dt < 2 zeta / omega).
std::vector<std::string> energy_warnings(const EnergyLedger& ledger, bool has_dashpots = true,
                                         Integrator method = Integrator::CentralDifference);

// True when the case has a dashpot anywhere (see energy_warnings).
bool case_has_dashpots(const CaseDef& def);

// Penalty contacts pressed in by more than this fraction of the thinner
// box's smallest half-dimension (ContactPressPeak) are warned about. A
// member bearing, rocking or coming to rest on a contact bears a pressed
// depth d away from where a rigid one would: a block rocking about its
// corner has its restoring arm, its half-width b, shortened by about d, and
// so its overturning threshold (Housner: tan(alpha) = b / h) lowered by
// about d / b. 5 % is the error an engineer would still read past; the
// rocking probe (2026-11-27) found a block whose base corners sank by 8.5 %
// of its half-width rocking elastically instead of about its corners. The
// remedy, a stiffer contact, also shortens the stable time step (its
// omega grows as sqrt(k)), so the run says so rather than changing it.
constexpr double kWarnContactPressRatio = 0.05;

// The warning for contacts pressed past kWarnContactPressRatio (empty when
// none was): which bodies (by name), how deep and when, against which box's
// half-thickness, and what to do about it; when the two bodies are among
// `initial_overlaps` (they started inside each other), also by how much,
// and that such a press can exceed what the boxes moved.
std::string contact_press_warning(const ContactPressPeak& peak, const BodyStore& bodies,
                                  const std::vector<InitialOverlap>& initial_overlaps = {});

// The warning for bodies overlapping at the start (ContactSystem::
// initial_overlaps: pairs not held by a joint that start inside each other,
// which the contacts then take as their rest state): the count and the
// three deepest pairs by name. Empty when there are none.
std::string initial_overlap_warning(const std::vector<InitialOverlap>& overlaps, const BodyStore& bodies);

// The warning for nodes that lie inside a member without being one of its
// ends (a column drawn through a floor node, a brace ending on a column's
// side): joints join members only at the nodes where they end, so nothing
// holds the members that end there to that member. Inside means strictly
// between the member's end nodes (more than 1 mm from both) and within half
// its thinner section size of its axis. Names the first three, with their
// lines; empty when there are none.
std::string nodes_inside_members_warning(const CaseDef& def);

// The warning for end nodes of members that lie closer together than half
// the thinnest section of the members ending at them without being one node
// (a coordinate typed 2 mm off): joints form only where members share a
// node, so the members ending at them are not joined. Pairs that are the two
// ends of one member are left out. Names the first three pairs with their
// lines and distance; empty when there are none.
std::string near_nodes_warning(const CaseDef& def);

// The warning for members that run between the same two nodes as an
// earlier one (a line copied and not edited; error probe: a doubled beam
// ran with no word, twice the mass and stiffness). Names the first three
// pairs with their lines; empty when there are none.
std::string duplicate_members_warning(const CaseDef& def);

// The warning for nodes that are the end of no member: a node is only a
// place where members end and are joined, so one no member names is a
// leftover, or the end a member was meant to have (its nodes name another).
// Names the first three with their lines; empty when every node is used.
std::string unused_nodes_warning(const CaseDef& def);

// The warning for members more than kSlenderMemberRatio times longer than
// the thinner side of their section: no timber member is (a 4 m brace of
// 30 mm is 133; the shipped cases' members 29-58), and node coordinates
// typed in millimetres against sections in metres give 1000 times that.
// Names the most slender member; empty when there is none.
inline constexpr double kSlenderMemberRatio = 1000.0;
std::string slender_members_warning(const CaseDef& def);

// The warning for members whose section's wider side exceeds their length
// and is 1 m or more (kStoutSectionSide_m, io/case_def.h): section sizes typed in
// millimetres against nodes in metres give sides of 10-200 m on members
// under a metre (a probe's 10 x 20 "m" column was refused for a stable step
// of 1.5e-9 s and told of overlaps, never of its section), where a short
// stub of a real section (20 mm wide, 15 mm long in a 1/10-scale frame;
// review probe) is no mistake, and no timber section is a metre wide.
// Names the stoutest member; empty when there is none.
std::string stout_members_warning(const CaseDef& def);

// The warning for members of kind column that lie nearer horizontal than
// vertical (or whose two ends lie at one height, within
// kStoreyLevelTolerance_m): a flat "column" spans no storey, so the drift
// assessment leaves it out, which it did silently (geometry probe), and a
// slightly sloping one makes a storey as tall as its rise.
// Names the first three; empty when there are none.
std::string horizontal_columns_warning(const CaseDef& def);

// The warning for a case with members but none of kind column: it has no
// storeys, so a run gives no storey drift and no verdict, which it did
// silently (geometry probe: posts given kind other). A case of blocks
// only has no frame to assess and gets none. Empty otherwise.
// The warning for columns of rectangular section (width and depth 1 %
// apart or more) whose section axes lie more than kTurnedSectionTolerance_deg
// from the plan direction of every member (beam, brace, other) ending at
// their nodes: a column's width runs along world x unless roll_deg turns
// it, so a frame drawn at 30 degrees in plan gets columns bending about
// other axes than its beams (torsion probe: peak drift 1.54 times the
// aligned frame's, with no warning). Names up to three with the roll_deg
// that aligns each; empty otherwise.
constexpr double kTurnedSectionTolerance_deg = 5.0;
std::string turned_column_sections_warning(const CaseDef& def, const Scene& scene);

std::string no_columns_warning(const CaseDef& def);

// The warning for a case with a ground body (a `ground` section or a
// support) but no contact with it (no contact.ground) and free bodies that
// no chain of joints holds to a fixed body: they fall through the ground's
// surface, which a probe's blocks did without a word (4.9 m below it after
// 1 s). Names the first such body. Empty otherwise.
std::string ground_without_contact_warning(const CaseDef& def, const Scene& scene);

// The warning for a frame (members) under gravity with no support, no ground
// section, no contact.ground and no fixed block: nothing holds it up, it falls freely from the
// start, and its storey verdicts describe a falling frame (a probe's
// unsupported portal fell 4.9 m in 1 s and read "standing", unwarned).
// Empty otherwise, and for blocks alone (free-fall and impact set-ups).
std::string nothing_holds_the_frame_warning(const CaseDef& def, const Scene& scene);

// The warning for a storey (not collapsed) every joint of whose columns has
// broken: it stands, if at all, on loose posts, and its verdict follows
// their drift, not a frame's. Empty otherwise, and for a column that no
// joint ever held.
std::string loose_columns_warning(const Storey& storey, StoreyVerdict verdict, const JointSystem& joints);

// The warning for joints still holding at the run's end whose two bodies
// have turned more than three quarters of a whole turn against each other
// along their path (JointSystem::relative_turn_rad above 3 pi / 2): near a
// whole turn a joint's half-way frame is undefined, and past it the frame
// is turned half a turn about the relative rotation's axis, so such a
// joint's forces are unreliable (a frame probe, stop 41: an unbreakable
// support spun a whole turn booked a balance error of 8e-3, and a portal
// that swung a whole turn about its feet blew up). Empty when none has.
// Also given for a run that went unstable (the energy guard stops it at a
// finite state).
// `joint_names` per joint id, as in events.csv.
std::string whole_turn_joints_warning(const JointSystem& joints, const BodyStore& bodies,
                                      const std::vector<std::string>& joint_names);

// The joints that hold a storey's columns (a joint with one of the storey's
// column members at either end), and how many of them broke.
struct StoreyColumnJoints {
  std::size_t joints = 0;          // distinct joints
  std::size_t broken = 0;          // of those, broken
  std::size_t broken_holds = 0;    // broken joints counted once per column they hold
  bool every_column_held = false;  // each column has at least one joint
};
StoreyColumnJoints storey_column_joints(const Storey& storey, const JointSystem& joints);

// Storey i's slip warning (StoreyDriftMonitor::slip_warning), told how many
// of the joints holding its columns broke; `joints` null: the case has none.
std::string storey_slip_warning(const StoreyDriftMonitor& storeys, std::size_t i, const JointSystem* joints);

// The warning for members that no joint holds, in a case that has joints (a
// beam drawn 10 mm above the columns it should sit on): they stand only on
// their contacts, or fall through where there are none. Blocks are meant to
// be free and are left out. Names the first three; empty when there are none.
std::string unjoined_members_warning(const CaseDef& def, const Scene& scene);

// The warning for braces joined at one end only, in a case with joints: a
// brace end whose node no other member ends at and no support holds joins
// nothing (a head node typed a few mm off the corner), so the brace hangs
// from its other end and braces nothing, while the run looks like that of a
// braced frame (acceptance probe: frame C with one brace head 12 mm off its
// corner stood "standing" with one column twice the storey's mean). Beams
// and columns may end free (a cantilever, a free post top); a brace is a
// diagonal between two points of the frame. Names the first three.
std::string brace_free_ends_warning(const CaseDef& def, const Scene& scene);

// The warning for braces that end at a supported node where another member
// (a column) also ends: the brace is joined both to that member, with the
// joint type of the hub there, and to the ground, with the support's
// (cases/README.md, "supports"), where a foot of its own gives it the one
// connection meant (a retrofit probe's brace from a column base took the
// old tenon joint twice, with no warning). Names the first three; empty
// otherwise.
std::string brace_on_supported_node_warning(const CaseDef& def, const Scene& scene);

// The warnings above that follow from the case and its scene alone (not the
// run's time step, output folder or start), in the order run and info give
// them: the same for every run of a case, so a study says them once.
std::vector<std::string> case_warnings(const CaseDef& def, const Scene& scene);

// The warning for joint rules (joints.rules) that make no joint: no pair of
// members of the rule's kinds is joined under the hub rule (with hub_kind
// beam, braces join the beam at a node, so a [column, brace] rule never
// applies; retrofit probe), or every such pair has an override. Names each
// with its line; empty when every rule is used or there are none.
std::string unused_joint_rules_warning(const CaseDef& def);

// Warnings for ground-motion components whose record's header names a
// component at odds with the direction it is applied in: a vertical one
// ("UP", "DWN", "UD", "V", "VER", "VERT" as the last field of a PEER
// header's line 2) along a mostly horizontal direction (|d_z| < 0.5), or a
// horizontal one (an azimuth such as "000", "090", "360", or "EW", "NS")
// along a mostly vertical direction. One message per such component; none
// when the header names no component (two-column records).
std::vector<std::string> ground_motion_direction_warnings(const GroundMotion& motion);

// The warning for a time step longer than the finest sample interval of
// the records as the run plays them (record dt x time_scale): forces take
// the motion at t = n dt, so samples between steps are never felt. It
// gives the peak the steps apply against the record's along the axis of
// the record's largest peak (a stable-step probe's 5 m/s^2 spike at 0.01 s
// was never applied at dt = 0.02 s, while summary.json gave its 5 m/s^2
// as the peak). Empty without a ground motion or when dt is short enough.
std::string ground_motion_sampling_warning(const Simulation& sim);

// The warning for rk4 under a record whose samples (the bends of its
// piecewise-linear forcing) or window end fall inside steps: rk4's error is
// then of order dt^2 at each, not dt^4 (tests/joints/test_base_excitation.cpp,
// BaseExcitation.RungeKutta4*: an error 40 times larger at a similar step).
// Names the earliest such sample over all records; suggests the largest
// dt_s up to the case's that puts every played sample on a step boundary
// (record_aligned_step_s) where one exists, and a window_length_s of whole
// samples where a window ends between samples (a window that ends on a
// sample needs only the step).
// Empty for other integrators, without a ground motion, when every bend is
// on a step boundary, or when dt is longer than a sample interval (that is
// ground_motion_sampling_warning's).
std::string runge_kutta_sampling_warning(const Simulation& sim);

// The largest step <= dt_max_s that puts every played sample of every
// component of `motion` on a step boundary from t = 0: a whole number of
// steps in each played sample interval (record dt x time_scale; each
// distinct gap of an unevenly sampled record) and in the time of each
// record's first played sample (not 0 for a window that starts between
// samples). 0 when no step up to a thousandth of the shortest of these
// lengths divides them all (lengths in ratios such as sqrt 2).
double record_aligned_step_s(const GroundMotion& motion, double dt_max_s);

// The checks run_case makes before it writes anything (the scene builds;
// the integrator can serve its force providers; dt is within the stable
// estimate unless options.allow_unstable_time_step), for commands that
// check every case before running any (compare, sweep). Throws InputError.
void check_case_runnable(const CaseDef& def, const CaseRunOptions& options);

// Runs the case and writes its output. Throws InputError (bad case values or
// a time step above the stable limit, nothing written) or OutputError.
CaseRunReport run_case(const CaseDef& def, const CaseRunOptions& options);

// Continues the run whose checkpoint is `folder`/checkpoint.bin: rebuilds
// the scene from the case file named in the checkpoint, refuses a case (or
// ground-motion record) that changed since, loads the state, and carries on
// writing into `folder` as the uninterrupted run would have (history.csv
// and events.csv cut back to the checkpoint and appended, frames after it
// rewritten, summary.json at the end). The result is bitwise identical to
// the uninterrupted run's. output_folder and allow_unstable_time_step of
// `options` are ignored (the folder is `folder`; the check was made when
// the run started). Throws CheckpointError (file missing, damaged,
// truncated, foreign, other version, other case; nothing written),
// InputError (the case file no longer loads) or OutputError.
// `moved_case_file`: the case file's place now, when it was moved since the
// run began (its bytes and its records' must be unchanged); the checkpoints
// written from here on name it.
CaseRunReport resume_case(const std::filesystem::path& folder, const CaseRunOptions& options,
                          const std::optional<std::filesystem::path>& moved_case_file = std::nullopt);

// Human-readable description: bodies, total mass, time step and its stable
// limit, duration, ground motion, output plan; `integrator` replaces the
// case's time.integrator as --integrator does for run. Every reason run
// would refuse the case (an integrator the scene cannot serve, dt above the
// stable limit without --force) is a line of the description, not an error;
// InputError only when the case cannot be described (it does not load, or
// no stable step can be estimated).
// list_joints (info --joints): ends with one line per joint, its id, name
// (io/joint_builder.h), node, members and type.
void describe_case(const CaseDef& def, std::ostream& out, std::optional<Integrator> integrator = std::nullopt,
                   bool list_joints = false);

}  // namespace fq
