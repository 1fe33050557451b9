#include "io/joint_builder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "io/input_error.h"

namespace fq {

const char* joint_layout_kind_name(JointLayoutKind kind) {
  switch (kind) {
    case JointLayoutKind::SinglePoint: return "single_point";
    case JointLayoutKind::FourCorner: return "four_corner";
    case JointLayoutKind::LinkSystem: return "link_system";
  }
  return "unknown";
}

JointLayout layout_for(const JointTypeDef& type, double width_m, double depth_m) {
  switch (type.layout) {
    case JointLayoutKind::SinglePoint: {
      JointLayout l = single_point_layout(type.normal, type.shear);
      if (!type.has_shear)
        for (SpringPointDef& p : l.points) p.has_shear = false;
      return l;
    }
    case JointLayoutKind::FourCorner: {
      JointLayout l = four_corner_layout(0.5 * width_m, 0.5 * depth_m, type.corner_fraction, type.normal, type.shear);
      if (!type.has_shear)
        for (SpringPointDef& p : l.points) p.has_shear = false;
      return l;
    }
    case JointLayoutKind::LinkSystem: {
      LinkSystemDef d;
      d.side_m = type.side_m > 0.0 ? type.side_m : std::min(width_m, depth_m);
      d.gap_m = type.gap_m;
      d.axial = type.axial;
      d.diagonal = type.diagonal;
      d.shear = type.shear_link;
      d.with_shear_links = type.with_shear_links;
      return link_system_layout(d);
    }
  }
  return {};
}

namespace {

struct MemberEnd {
  int member = -1;
  bool at_a = true;  // the member's node_a is this node
};

// Joint between `body_a` and member `m` at its end `end` (node position
// `node_m`): frame n = into member m, t1 = m's local y, t2 = n x t1.
JointDef joint_for_member_end(const Model& model, BodyId body_a, int m, const MemberEnd& end, const Vec3& node_m,
                              const JointTypeDef& type) {
  const CaseDef& def = model.def;
  const MemberDef& md = def.members[std::size_t(m)];
  const SectionDef& sec = def.sections[std::size_t(def.section_index(md.section))];
  const BodyId body_b = model.member_body[std::size_t(m)];
  const Mat3& r = model.bodies.rotation[body_b];
  const Vec3 n = end.at_a ? Vec3(r.col(0)) : Vec3(-r.col(0));
  const Vec3 t1 = r.col(1);
  const Vec3 t2 = n.cross(t1);
  JointDef j;
  j.body_a = body_a;
  j.body_b = body_b;
  j.origin_m = node_m;
  j.frame.col(0) = t1;
  j.frame.col(1) = t2;
  j.frame.col(2) = n;
  j.layout = layout_for(type, sec.width_m, sec.depth_m);
  j.fracture = type.fracture;
  return j;
}

}  // namespace

std::string joint_name(const std::string& node, const std::string& member_a, const std::string& member_b) {
  return node + ":" + member_a + "-" + member_b;
}

JoinedMemberEnds::JoinedMemberEnds(const CaseDef& def)
    : def_(&def), any_joints_(!def.joint_types.empty() || !def.joints.overrides.empty()), ends_at_(def.nodes.size(), 0) {
  const NameIndex node_ids(def.nodes, &NodeDef::id);
  for (const MemberDef& m : def.members)
    for (const std::string* node : {&m.node_a, &m.node_b})
      if (const int n = node_ids.find(*node); n >= 0) ++ends_at_[std::size_t(n)];
  for (const JointOverrideDef& o : def.joints.overrides) overrides_at_[o.node].push_back(&o);
}

bool JoinedMemberEnds::joined(std::size_t member, std::size_t node) const {
  if (!any_joints_) return false;
  // plan_joints: automatic joints pair every member ending at a node of two
  // or more ends with the node's hub.
  if (def_->joints.automatic && ends_at_[node] >= 2) return true;
  // plan_joints: an override adds the pair it names at its node.
  const auto at = overrides_at_.find(def_->nodes[node].id);
  if (at == overrides_at_.end()) return false;
  const std::string& id = def_->members[member].id;
  for (const JointOverrideDef* o : at->second)
    if (o->member_1 == id || o->member_2 == id) return true;
  return false;
}

std::vector<PlannedJoint> plan_joints(const Model& model) {
  const CaseDef& def = model.def;
  const std::string file = def.source_file.string();
  std::vector<PlannedJoint> out;
  if (def.joint_types.empty() && def.joints.overrides.empty()) {
    // Without joint types nothing can be joined; members that meet are then
    // independent bodies and supports are refused (they would hold nothing).
    if (!def.supports.empty()) {
      const SupportDef& s = def.supports.front();
      throw InputError(file, s.line, "supports[0].joint_type",
                       "support at node '" + s.node +
                           "' needs a joint type to tie it to the ground: define joint_types and give joint_type "
                           "here or joints.support_type");
    }
    return out;
  }

  // Member ends per node, in member file order.
  std::map<std::string, std::vector<MemberEnd>> ends;
  for (std::size_t i = 0; i < def.members.size(); ++i) {
    ends[def.members[i].node_a].push_back({int(i), true});
    ends[def.members[i].node_b].push_back({int(i), false});
  }
  auto type_named = [&](const std::string& name) -> const JointTypeDef& {
    return def.joint_types[std::size_t(def.joint_type_index(name))];
  };
  // Overrides by node, in file order (the first that fits wins): asked per
  // pair of members at a node, a scan of all of them grew with the case.
  std::unordered_map<std::string_view, std::vector<const JointOverrideDef*>> overrides_at;
  for (const JointOverrideDef& o : def.joints.overrides) overrides_at[o.node].push_back(&o);
  auto override_for = [&](const std::string& node, const std::string& m1,
                          const std::string& m2) -> const JointOverrideDef* {
    const auto at = overrides_at.find(node);
    if (at == overrides_at.end()) return nullptr;
    for (const JointOverrideDef* o : at->second)
      if ((o->member_1 == m1 && o->member_2 == m2) || (o->member_1 == m2 && o->member_2 == m1)) return o;
    return nullptr;
  };
  auto rule_for = [&](MemberKind k1, MemberKind k2) -> const JointRuleDef* {
    for (const JointRuleDef& r : def.joints.rules)
      if ((r.kind_1 == k1 && r.kind_2 == k2) || (r.kind_1 == k2 && r.kind_2 == k1)) return &r;
    return nullptr;
  };

  for (const NodeDef& node : def.nodes) {
    const auto it = ends.find(node.id);
    if (it == ends.end() || it->second.size() < 2) continue;
    const std::vector<MemberEnd>& here = it->second;
    std::vector<std::pair<int, int>> pairs;  // indices into `here`
    if (def.joints.automatic) {
      int hub = 0;
      for (std::size_t k = 0; k < here.size(); ++k)
        if (def.members[std::size_t(here[k].member)].kind == def.joints.hub_kind) {
          hub = int(k);
          break;
        }
      for (std::size_t k = 0; k < here.size(); ++k)
        if (int(k) != hub) pairs.emplace_back(hub, int(k));
    }
    // Overrides for pairs the hub rule did not produce add joints of their own.
    for (const JointOverrideDef& o : def.joints.overrides) {
      if (o.node != node.id) continue;
      int k1 = -1, k2 = -1;
      for (std::size_t k = 0; k < here.size(); ++k) {
        const std::string& id = def.members[std::size_t(here[k].member)].id;
        if (id == o.member_1) k1 = int(k);
        if (id == o.member_2) k2 = int(k);
      }
      const bool present = std::any_of(pairs.begin(), pairs.end(), [&](const auto& p) {
        return (p.first == k1 && p.second == k2) || (p.first == k2 && p.second == k1);
      });
      if (!present) pairs.emplace_back(k1, k2);
    }
    for (const auto& [ka, kb] : pairs) {
      const MemberDef& ma = def.members[std::size_t(here[std::size_t(ka)].member)];
      const MemberDef& mb = def.members[std::size_t(here[std::size_t(kb)].member)];
      std::string type;
      int line = node.line;
      int rule = -1;
      if (const JointOverrideDef* o = override_for(node.id, ma.id, mb.id)) {
        type = o->type;
        line = o->line;
      } else if (const JointRuleDef* r = rule_for(ma.kind, mb.kind)) {
        type = r->type;
        line = r->line;
        rule = int(r - def.joints.rules.data());
      } else if (!def.joints.default_type.empty()) {
        type = def.joints.default_type;
        line = def.joints.line;
      } else {
        throw InputError(file, node.line, "nodes[" + std::to_string(def.node_index(node.id)) + "]",
                         std::string("members '") + ma.id + "' (" + member_kind_name(ma.kind) + ") and '" + mb.id +
                             "' (" + member_kind_name(mb.kind) + ") meet at node '" + node.id +
                             "' but no joint type applies: add joints.default_type, a rule for kinds [" +
                             member_kind_name(ma.kind) + ", " + member_kind_name(mb.kind) + "] or an override");
      }
      PlannedJoint p;
      p.def = joint_for_member_end(model, model.member_body[std::size_t(here[std::size_t(ka)].member)],
                                   here[std::size_t(kb)].member, here[std::size_t(kb)], node.xyz_m, type_named(type));
      p.node = node.id;
      p.type = type;
      p.member_a = ma.id;
      p.member_b = mb.id;
      p.line = line;
      p.rule = rule;
      p.name = joint_name(p.node, p.member_a, p.member_b);
      p.label = "node " + node.id + ": " + member_kind_name(ma.kind) + " " + ma.id + " - " +
                member_kind_name(mb.kind) + " " + mb.id + " (type " + type + ")";
      out.push_back(std::move(p));
    }
  }

  const NameIndex node_ids(def.nodes, &NodeDef::id);
  for (std::size_t si = 0; si < def.supports.size(); ++si) {
    const SupportDef& s = def.supports[si];
    const std::string type = !s.joint_type.empty() ? s.joint_type : def.joints.support_type;
    if (type.empty())
      throw InputError(file, s.line, "supports[" + std::to_string(si) + "].joint_type",
                       "support at node '" + s.node + "' has no joint type: give joint_type here or joints.support_type");
    const NodeDef& node = def.nodes[std::size_t(node_ids.find(s.node))];
    for (const MemberEnd& e : ends[s.node]) {
      const MemberDef& m = def.members[std::size_t(e.member)];
      PlannedJoint p;
      p.def = joint_for_member_end(model, model.ground_body, e.member, e, node.xyz_m, type_named(type));
      p.node = node.id;
      p.type = type;
      p.member_a = "ground";
      p.member_b = m.id;
      p.line = s.line;
      p.name = joint_name(p.node, p.member_a, p.member_b);
      p.label = "support " + node.id + ": ground - " + member_kind_name(m.kind) + " " + m.id + " (type " + type + ")";
      out.push_back(std::move(p));
    }
  }
  return out;
}

std::string hub_choice_note(const CaseDef& def) {
  if (!def.joints.automatic || (def.joint_types.empty() && def.joints.overrides.empty())) return "";
  // Members end to end within 5 degrees are one piece of wood split at the
  // node (a beam taking a brace, a typed node a few mm off line bends it by
  // well under a degree); the members a file's order chooses among meet at
  // 45-90 degrees.
  const double collinear_cos = std::cos(5.0 * 3.14159265358979323846 / 180.0);
  auto axis = [&](const MemberDef& m) -> Vec3 {
    const Vec3 d = def.nodes[std::size_t(def.node_index(m.node_b))].xyz_m -
                   def.nodes[std::size_t(def.node_index(m.node_a))].xyz_m;
    return d.norm() > 0.0 ? Vec3(d.normalized()) : Vec3::Zero();
  };
  std::map<std::string, std::vector<int>> ends;  // members ending at each node, in file order
  for (std::size_t i = 0; i < def.members.size(); ++i) {
    ends[def.members[i].node_a].push_back(int(i));
    ends[def.members[i].node_b].push_back(int(i));
  }
  std::vector<std::string> chosen;  // "'node': 'hub' (over 'other', ...)"
  for (const NodeDef& node : def.nodes) {
    const auto it = ends.find(node.id);
    if (it == ends.end() || it->second.size() < 2) continue;
    // plan_joints' candidates: the members of hub_kind, or every member
    // when none is of that kind; the first listed is the hub.
    std::vector<int> candidates;
    for (int m : it->second)
      if (def.members[std::size_t(m)].kind == def.joints.hub_kind) candidates.push_back(m);
    if (candidates.empty()) candidates = it->second;
    if (candidates.size() < 2) continue;
    const Vec3 hub_axis = axis(def.members[std::size_t(candidates.front())]);
    std::vector<std::string> across;
    for (std::size_t k = 1; k < candidates.size(); ++k)
      if (std::abs(hub_axis.dot(axis(def.members[std::size_t(candidates[k])]))) < collinear_cos)
        across.push_back("'" + def.members[std::size_t(candidates[k])].id + "'");
    if (across.empty()) continue;
    std::string entry = "'" + node.id + "': '" + def.members[std::size_t(candidates.front())].id + "' over ";
    for (std::size_t k = 0; k < across.size(); ++k) entry += (k ? ", " : "") + across[k];
    chosen.push_back(entry);
  }
  if (chosen.empty()) return "";
  std::ostringstream note;
  const std::string kind = member_kind_name(def.joints.hub_kind);
  note << "the order of the members in the case file chose the hub at " << chosen.size()
     << (chosen.size() == 1 ? " node" : " nodes") << " where members of different directions could each be it (joints.hub_kind: "
     << kind << "): the first listed runs through the node and the others there are joined to it (";
  const std::size_t shown = std::min<std::size_t>(chosen.size(), 4);
  for (std::size_t k = 0; k < shown; ++k) note << (k ? "; " : "") << chosen[k];
  if (chosen.size() > shown) note << "; and " << chosen.size() - shown << " more";
  note << "); to make another run through, list it first (info --joints lists every pair; cases/README.md, "
          "joints)";
  return note.str();
}

}  // namespace fq
