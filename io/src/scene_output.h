// What joints (and, later, contacts) add to a run's output: spring line
// cells in every frame, joint counts in history.csv and summary.json.
#pragma once

#include "contacts/contact_system.h"
#include "io/run_output.h"
#include "io/storey_drift.h"
#include "joints/joint_system.h"

namespace fq {

// Springs as VTK line cells (ends on body a and body b at the frame's
// poses; the arrays are the last force evaluation's, one step before) with arrays
// spring_force_N, strain_ratio (|delta| / ultimate, 1 = deletion),
// spring_state (0 elastic, 1 yielded, 2 deleted, 3 gone with its broken
// joint without failing itself: SpringStatus), spring_role (0 normal,
// 1 shear, 2 link), joint_id and joint_broken (0/1); history columns
// joints_intact_count, joints_yielded_count, joints_broken_count. Also sets
// damage_state on the body cells from the members' joints (0 intact,
// 1 yielded, 2 damaged: some joint broken, 3 detached: all joints broken).
// Field data joint_names and joint_nodes (strings, one per joint id: the
// joint's name "node:member_a-member_b" and its node id, io/joint_builder.h)
// say which joint a joint_id is; `nodes` and `names` (Scene::joint_nodes,
// joint_names) also fill events.csv's node and joint_name columns.
void attach_joint_output(RunOutput& output, const JointSystem& joints, const std::vector<std::string>& nodes,
                         const std::vector<std::string>& names);

// Summary fields: joint counts at the end and the time of the first joint
// failure (first spring deletion or joint break; null when none).
// `labels`: each joint's label (Scene::joint_labels), for naming the first
// joint to fail (first_joint_failure); `names`: each joint's name
// (Scene::joint_names) for first_joint_failure_joint_name, with its id in
// first_joint_failure_joint_id (both null when no joint failed).
void add_joint_summary(RunOutput& output, const JointSystem& joints, const EventLog& events,
                       const std::vector<std::string>& labels, const std::vector<std::string>& names);

// Summary field contact_press_peak: the largest press of the contact
// springs as a fraction of a section (ContactPressPeak) -- its depth (m),
// the measured box's half-thickness (m), their ratio, the time, the two
// bodies by name ("ground" for the ground) and the measured one; null when
// no contact was pressed.
void add_contact_summary(RunOutput& output, const ContactSystem& contacts, const BodyStore& bodies);

// Joint id of the first spring deletion or joint break (-1 when none).
std::int32_t first_joint_failure_id(const EventLog& events);
// Time of the first spring deletion or joint break (NaN when none).
double first_joint_failure_time_s(const EventLog& events);
// The label of the first joint to fail (a spring deleted or the joint
// broken), "" when none failed: where a frame is weakest.
std::string first_joint_failure_label(const EventLog& events, const std::vector<std::string>& labels);
// When the first failure's joint broke (its joint_broken event, at or after
// the failure; at its time when the failure broke it); NaN when it never broke.
double first_joint_failure_break_time_s(const EventLog& events);

// History columns storeyK_drift_{x,y}_m and storeyK_drift_ratio_{x,y}_rad
// per storey; each row samples the monitor first (it ignores repeats).
void attach_storey_output(RunOutput& output, StoreyDriftMonitor& monitor);
// Summary fields "storeys" (per storey: height, peaks, residual, collapse
// time, verdict) and "assessment" (the limits and the criterion in words).
// A run that became unstable is not assessed: its storeys' verdict is
// "not_assessed" (its drifts are those of the blow-up, or of the steps
// before it), as in compare's and sweep's tables.
void add_storey_summary(RunOutput& output, const StoreyDriftMonitor& monitor, bool assessed = true);

// Contact points as VTK vertex cells with contact_force_N (force on body b,
// 3 components), contact_normal (unit, a to b), contact_depth_m and
// contact_sliding (0/1); history columns contact_points_count and
// ground_normal_force_N.
void attach_contact_output(RunOutput& output, const ContactSystem& contacts);

// History columns base_shear_x_N, base_shear_y_N and base_reaction_z_N: the
// force the ground and fixed bodies apply to the structure through support
// joints and contacts (N, world; + along the axis, so + z carries the
// weight). At rest under gravity the reaction is the weight; moving with a
// ground acceleration a_g the base shear is the mass times a_g.
void attach_base_force_output(RunOutput& output, const JointSystem* joints, const ContactSystem* contacts);

}  // namespace fq
