// Joints of a case: where members share a node, and where a supported node
// meets the ground (rules in case_def.h, JointsDef). Produces the joints'
// definitions in the joints module's terms; build_scene adds them to a
// JointSystem.
#pragma once

#include <string>
#include <vector>

#include "io/model.h"
#include "joints/joint_system.h"

namespace fq {

struct PlannedJoint {
  JointDef def;
  std::string label;     // e.g. "node n5: column c1 - beam b2 (type tenon_weak)"
  std::string node;      // node id
  std::string type;      // joint type name
  std::string member_a;  // member id on side a ("ground" for supports)
  std::string member_b;  // member id on side b
  int line = 0;          // line of the rule, override, support or node that made it
};

// Plans every joint of the case; throws InputError when members meet at a
// node and no joint type applies, or a support has no joint type.
std::vector<PlannedJoint> plan_joints(const Model& model);

// Builds the spring layout of joint type `type` for a member with section
// width_m (along the joint frame's t1) and depth_m (along t2).
JointLayout layout_for(const JointTypeDef& type, double width_m, double depth_m);

}  // namespace fq
