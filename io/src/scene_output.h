// What joints (and, later, contacts) add to a run's output: spring line
// cells in every frame, joint counts in history.csv and summary.json.
#pragma once

#include "contacts/contact_system.h"
#include "io/run_output.h"
#include "joints/joint_system.h"

namespace fq {

// Springs as VTK line cells (ends on body a and body b) with arrays
// spring_force_N, strain_ratio (|delta| / ultimate, 1 = deletion),
// spring_state (0 elastic, 1 yielded, 2 deleted), spring_role (0 normal,
// 1 shear, 2 link), joint_id and joint_broken (0/1); history columns
// joints_intact_count, joints_yielded_count, joints_broken_count. Also sets
// damage_state on the body cells from the members' joints (0 intact,
// 1 yielded, 2 damaged: some joint broken, 3 detached: all joints broken).
void attach_joint_output(RunOutput& output, const JointSystem& joints);

// Summary fields: joint counts at the end and the time of the first joint
// failure (first spring deletion or joint break; null when none).
void add_joint_summary(RunOutput& output, const JointSystem& joints, const EventLog& events);

// Contact points as VTK vertex cells with contact_force_N (force on body b,
// 3 components), contact_normal (unit, a to b), contact_depth_m and
// contact_sliding (0/1); history columns contact_points_count and
// ground_normal_force_N.
void attach_contact_output(RunOutput& output, const ContactSystem& contacts);

}  // namespace fq
