// Turns a CaseDef into what the step loop runs on: the bodies, the settings
// and the ground motion. Joints, contacts and output are added by later
// stages from `def` and the body ids recorded here.
#pragma once

#include <vector>

#include "dem_core/body_store.h"
#include "dem_core/ground_motion.h"
#include "dem_core/simulation.h"
#include "io/case_def.h"
#include "io/case_file.h"

namespace fq {

struct Model {
  CaseDef def;  // as loaded; output.folder and name filled in when left empty
  // Body order: the ground body first (id 0, fixed, kind Ground) when the case
  // has supports or a ground section, then the members in file order, then
  // the blocks in file order.
  BodyStore bodies;
  // Fixed box whose top face is at ground.level_m (0 without a ground
  // section), 20 mm thick, covering the structure's footprint (see
  // build_model); kNoBody when the case has neither supports nor ground.
  BodyId ground_body = kNoBody;
  std::vector<BodyId> member_body;  // per def.members[i]
  std::vector<BodyId> block_body;   // per def.blocks[i]
  SimulationSettings settings;      // dt, duration (resolved), gravity
  GroundMotion ground_motion;       // components with scales and window
};

// Builds the bodies (member geometry convention in case_def.h). Checks what a
// CaseDef built in code may get wrong and a file reader has no business
// checking twice: references to unknown nodes, sections and materials,
// coincident member nodes, non-positive sizes and densities, duplicate body
// ids, blocks that start below the ground surface, a duration that is
// neither given nor implied by a ground motion, a case without bodies. Each
// throws fq::InputError naming def.source_file, the item's line and its
// path (e.g. `members[2].nodes`).
Model build_model(const CaseDef& def);

// Orientation (body -> world) of a member from node a at `a_m` to node b at
// `b_m` with section roll `roll_rad`, by the convention in case_def.h. The
// nodes must be distinct.
Quat member_orientation(const Vec3& a_m, const Vec3& b_m, double roll_rad);

// Orientation (body -> world) of a block rotated by `rotation_rad` about
// world x, then world y, then world z: R = Rz Ry Rx.
Quat block_orientation(const Vec3& rotation_rad);

}  // namespace fq
