// Joints of a case: where members share a node, and where a supported node
// meets the ground (rules in case_def.h, JointsDef). Produces the joints'
// definitions in the joints module's terms; build_scene adds them to a
// JointSystem.
#pragma once

#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "io/model.h"
#include "joints/joint_system.h"

namespace fq {

struct PlannedJoint {
  JointDef def;
  std::string label;     // e.g. "node n5: column c1 - beam b2 (type tenon_weak)"
  std::string name;      // e.g. "n5:c1-b2", "se0:ground-c3" (joint_name below)
  std::string node;      // node id
  std::string type;      // joint type name
  std::string member_a;  // member id on side a ("ground" for supports)
  std::string member_b;  // member id on side b
  int line = 0;          // line of the rule, override, support or node that made it
  int rule = -1;         // index into joints.rules of the rule that gave its type; -1: none did
};

// A joint's name in the outputs (events.csv joint_name, the frames'
// joint_names and joint_name, summary.json, info --joints): its node id and
// the ids of its two members, side a first ("ground" for a support), as
// "node:member_a-member_b". Built from the case file's own ids, so it stays
// the same when joints are added or removed elsewhere in the case, unlike
// the joint id (the joint's place in the order the joints are planned).
std::string joint_name(const std::string& node, const std::string& member_a, const std::string& member_b);

// Plans every joint of the case; throws InputError when members meet at a
// node and no joint type applies, or a support has no joint type.
std::vector<PlannedJoint> plan_joints(const Model& model);

// A note naming the nodes where the file's order of members chose the hub
// among members of different directions (two beams meeting at a corner
// under hub_kind: beam, two columns of a bent post): the hub runs through
// the node and the others are joined to it, so listing the other member
// first changes which members are joined and the joints' frames, and with
// them the frame's stiffness (geometry probe 2026-11-27: storey 1 of a
// four-column frame peaked at 0.030 rad with its x beams listed first and
// at 0.075 rad with its y beams first). "" when no such node exists.
std::string hub_choice_note(const CaseDef& def);

// Which member ends plan_joints joins to another member, without planning
// the joints (so without its errors): member m ending at node n is held
// there when the case has joint types or overrides and either joints are
// automatic and two or more members end at n (each is the hub or joined to
// it), or an override at n names m. Supports are not counted. find_storeys
// asks it which members carry a floor at a column's top.
class JoinedMemberEnds {
 public:
  explicit JoinedMemberEnds(const CaseDef& def);
  // member and node: indices into def.members and def.nodes.
  bool joined(std::size_t member, std::size_t node) const;

 private:
  const CaseDef* def_;
  bool any_joints_ = false;
  std::vector<int> ends_at_;  // per node, the member ends there
  std::unordered_map<std::string_view, std::vector<const JointOverrideDef*>> overrides_at_;
};

// Builds the spring layout of joint type `type` for a member with section
// width_m (along the joint frame's t1) and depth_m (along t2).
JointLayout layout_for(const JointTypeDef& type, double width_m, double depth_m);

}  // namespace fq
