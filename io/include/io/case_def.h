// Definition of one framequake case: plain structs that a case file is a
// serialisation of (STYLE.md 3.8). This header is the ONE place where the
// defaults live; the case-file reader (case_file.h) only fills these structs,
// tests and programs may build them directly, and build_model (model.h) turns
// them into bodies. cases/README.md documents the file keys that map onto
// these fields.
//
// Units are SI and carried by the names. Angles are in degrees in the file
// and in radians here.
//
// Source lines: every list item (material, section, node, member, block,
// support, ground-motion component) keeps the 1-based line it starts on in
// `line`, and CaseDef::section_line keeps the line of each top-level key, so
// later stages (model builder, joints, the run) can point a user at the place
// in the file. A line of 0 means "not from a file" (built in code).
//
// Member geometry (the convention build_model applies; cases/README.md):
//   - body local x runs from node a to node b; the box length along local x
//     is the node distance, and the box centre is the midpoint of the nodes;
//   - a member more than 10 degrees from vertical has local z = world z made
//     orthogonal to local x, so the section depth (along local z) of a beam
//     is vertical and its width (along local y) horizontal;
//   - a member within 10 degrees of vertical has local y = world x made
//     orthogonal to local x (then local z = x × y: world +y for a column
//     drawn upwards);
//   - roll_rad then turns the section about local x (right-handed: local y
//     towards local z).
// Block rotation: rotation_rad = (rx, ry, rz) is applied about the WORLD x
// axis first, then world y, then world z: R = Rz(rz) Ry(ry) Rx(rx).
#pragma once

#include <filesystem>
#include <limits>
#include <map>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "dem_core/body_store.h"
#include "dem_core/ground_motion.h"
#include "dem_core/integrator.h"
#include "dem_core/types.h"
#include "contacts/contact_params.h"
#include "io/accelerogram.h"
#include "joints/fracture.h"
#include "joints/spring_law.h"
#include "io/output_def.h"

namespace fq {

// The case-file schema version this build reads (key `framequake_case`).
inline constexpr int kCaseSchemaVersion = 1;

// Members shorter than this are refused: no wooden member is shorter than a
// millimetre, so a micrometre is certainly two nodes typed at the same place
// (and a zero-length box has no orientation and a degenerate inertia).
inline constexpr double kMinMemberLength_m = 1e-6;

struct TimeDef {
  // Required in a file. 1e-5 s is the step of seed 001 for its scaled frames.
  double dt_s = 1e-5;
  // Simulated time (s). Unset: the end of the ground-motion window in
  // simulation time (GroundMotion::end_time_s); required when there is no
  // ground motion.
  std::optional<double> duration_s;
  Vec3 gravity_mps2 = Vec3(0.0, 0.0, -kStandardGravity_mps2);  // (m/s^2), world frame
  // Time integrator (dem_core/integrator.h); `framequake run --integrator`
  // overrides it.
  Integrator integrator = Integrator::CentralDifference;
};

struct MaterialDef {
  std::string name;
  double density_kg_per_m3 = 0.0;  // required, kMinDensity..kMaxDensity (0 = unset, refused)
  int line = 0;
};

// Densities a case may give (kg/m^3). Solids range from about 1 (the
// lightest aerogels) to 22 600 (osmium); the bounds leave a decade below
// and a factor 44 above, room for a scaled model whose mass similitude
// raises the density, and refuse what only a typing error or a wrong unit
// gives (a density of 1e-300 made every mode's frequency overflow, so the
// stable-step check saw no limit and the run went on).
inline constexpr double kMinDensity_kg_per_m3 = 0.1;
inline constexpr double kMaxDensity_kg_per_m3 = 1.0e6;
// Why `density_kg_per_m3` is refused, or "" when it lies in that range.
std::string density_out_of_range(double density_kg_per_m3);

// Largest coordinate magnitude of a node or a block centre (m). At 1e5 m a
// double resolves 1.5e-11 m, still well below the 1e-7 m a body moves in a
// step; at map coordinates (1e6-1e7 m) it resolves 1e-10-2e-9 m, the size
// of the contact tolerances, and beyond ~1e154 m a member's length
// overflows (a node at 1e300 m was refused as "edge length not positive").
// A structure is put near the origin; a larger number is a typing error.
inline constexpr double kMaxCoordinate_m = 1.0e5;
// Why the position `xyz_m` is refused, or "" when every coordinate lies
// within kMaxCoordinate_m.
std::string coordinate_out_of_range(const Vec3& xyz_m);

// Edges of a member's section or of a block (m): from a micrometre (as
// kMinMemberLength_m: no wooden part is thinner than a millimetre) to
// kMaxCoordinate_m. Outside that only a typing error or a wrong unit gets
// (a section 1e300 m wide gave an infinite mass and ended the run as an
// internal error; one 1e-300 m wide a mass of zero).
inline constexpr double kMinEdge_m = 1e-6;
inline constexpr double kMaxEdge_m = kMaxCoordinate_m;
// Why the edge length `edge_m` is refused, or "" when it lies in that range.
std::string edge_out_of_range(double edge_m);

// Gravity a case may give: up to 20 g (m/s^2), the bound a recorded ground
// acceleration has (accelerogram.h). Zero (verification scenes) and any
// direction are allowed; 9.80665 m/s^2 is standard.
inline constexpr double kMaxGravity_mps2 = 20.0 * kStandardGravity_mps2;

// A case's name names its output folder (out/<name>, and in a sweep
// <name>_<record>_x<scale>), which a file system limits to 255 bytes: 128
// leave room for the record and the scale.
inline constexpr std::size_t kMaxCaseNameLength = 128;

// Rectangular cross-section of a member.
// A section side from which a member wider than it is long is taken for
// sizes typed in millimetres (stout_members_warning, io/case_runner.h; the
// below-ground refusal, io/src/model.cpp): no timber section is a metre
// wide, and a stub shorter than a real section is no mistake.
inline constexpr double kStoutSectionSide_m = 1.0;
// A member of length_m whose section's wider side is side_m looks like one
// whose sizes were typed in millimetres.
inline bool section_typed_in_mm(double side_m, double length_m) {
  return length_m > 0.0 && side_m > length_m && side_m >= kStoutSectionSide_m;
}

struct SectionDef {
  std::string name;
  double width_m = 0.0;  // required, > 0; edge along member local y
  double depth_m = 0.0;  // required, > 0; edge along member local z
  int line = 0;
};

struct NodeDef {
  std::string id;
  Vec3 xyz_m = Vec3::Zero();  // required; world frame (m)
  int line = 0;
};

// A box between two nodes (geometry convention in the header comment).
struct MemberDef {
  std::string id;                       // required; unique among members and blocks
  MemberKind kind = MemberKind::Other;  // required in a file: column | beam | brace | other
  std::string node_a;                   // required; local x runs from node_a ...
  std::string node_b;                   // ... to node_b
  std::string section;                  // required; name of a SectionDef
  std::string material;                 // required; name of a MaterialDef
  double roll_rad = 0.0;                // section roll about local x (rad); file: roll_deg
  // End trims (m): the box is shortened by trim_a_m at node a and trim_b_m at
  // node b (file: trim_m: [a, b]) so it stops at the face of the member it
  // meets instead of overlapping it; the nodes stay where joints act. Members
  // that overlap at rest would push each other apart through contact as soon
  // as their joint breaks.
  double trim_a_m = 0.0;
  double trim_b_m = 0.0;
  int line = 0;
};

// A free box not tied to nodes (verification scenes, debris).
struct BlockDef {
  std::string id;                              // required; unique among members and blocks
  MemberKind kind = MemberKind::Block;         // any kind except ground
  Vec3 size_m = Vec3::Zero();                  // required, each > 0; edges along body x, y, z (m)
  Vec3 center_m = Vec3::Zero();                // required; world frame (m)
  Vec3 rotation_rad = Vec3::Zero();            // about world x, then y, then z (rad); file: rotation_deg
  std::string material;                        // required; name of a MaterialDef
  bool fixed = false;                          // a fixed block never moves
  Vec3 velocity_mps = Vec3::Zero();            // initial, world frame (m/s)
  Vec3 angular_velocity_radps = Vec3::Zero();  // initial, world frame (rad/s)
  int line = 0;
};

// A node tied to the ground body.
struct SupportDef {
  std::string node;        // required; id of a NodeDef that is an end of some member
  std::string joint_type;  // joint tying each member end at the node to the ground;
                           // empty = joints.support_type (required once joint types exist)
  int line = 0;
};

// ---- joints (joint_types, joints) -------------------------------------------
// Where a joint's springs sit (joints/joint_layout.h):
//   single_point  one normal and two shear springs at the connection point
//   four_corner   four such points at (+-f b/2, +-f h/2) of the connected
//                 member's section (f = corner_fraction)
//   link_system   seed 000 Fig. 4: axial, diagonal and shear links between two
//                 square planes of side side_m a gap gap_m apart
enum class JointLayoutKind { SinglePoint, FourCorner, LinkSystem };
const char* joint_layout_kind_name(JointLayoutKind kind);

struct JointTypeDef {
  std::string name;
  JointLayoutKind layout = JointLayoutKind::FourCorner;
  double corner_fraction = 1.0;       // four_corner: 1 = section corners (-)
  SpringDef normal;                   // point layouts: each normal spring
  SpringDef shear;                    // point layouts: each shear spring
  bool has_shear = true;              // point layouts: false = no shear springs
  double side_m = 0.0;                // link_system: a (m); 0 = the member's smaller section edge
  double gap_m = 0.0;                 // link_system: l (m); required for link_system
  SpringDef axial;                    // link_system: k
  SpringDef diagonal;                 // link_system: k'
  SpringDef shear_link;               // link_system: k_s
  bool with_shear_links = false;      // link_system
  JointBreakDef fracture;             // joint-level criterion (joints/fracture.h)
  int line = 0;
};

// Joint type for a pair of member kinds meeting at a node.
struct JointRuleDef {
  MemberKind kind_1 = MemberKind::Other;
  MemberKind kind_2 = MemberKind::Other;
  std::string type;
  int line = 0;
};

// A joint type for one specific pair of members at a node.
struct JointOverrideDef {
  std::string node;
  std::string member_1, member_2;
  std::string type;
  int line = 0;
};

// How joints are generated where members share a node (cases/README.md):
// at every node the "hub" is the first member of kind hub_kind (column by
// default) ending there (file order), or the first member when none of that
// kind ends there; every other member ending at
// the node is joined to the hub. Its type is the override for that pair, else
// the rule for the two kinds, else default_type; a node where none applies is
// an error. Supports join every member ending at a supported node to the
// ground body.
struct JointsDef {
  bool automatic = true;
  // Automatic joints join every member ending at a node to the node's hub:
  // the first member of this kind ending there (file order), else the first
  // member. Column: posts are continuous and beams frame into them; beam:
  // the floor beam is continuous and the posts above and below tenon into it.
  MemberKind hub_kind = MemberKind::Column;
  std::string default_type;  // may be empty
  std::string support_type;  // default joint type of supports; may be empty
  std::vector<JointRuleDef> rules;
  std::vector<JointOverrideDef> overrides;
  int line = 0;
};

struct GroundDef {
  double level_m = 0.0;  // height (z) of the ground surface (m)
};

// How storeys are judged (io/storey_drift.h). A storey is a band between two
// consecutive heights at which columns end; its drift is the mean horizontal
// displacement of its columns' top ends relative to their bottom ends.
struct AssessmentDef {
  // Japanese practice for timber houses: 1/30 rad is the safety-limit storey
  // drift of design (limit-strength calculation); beyond it a storey is
  // damaged but still stands.
  double safety_drift_ratio_rad = 1.0 / 30.0;
  // 1/10 rad: by then the joints of a post-and-beam storey have passed their
  // ultimate rotation (0.075-0.15 rad for tenons, cases/README.md) and the
  // gravity (P-delta) moment keeps growing while their resistance falls; a
  // storey that reaches it is counted as collapsed (cases/README.md,
  // "Frames A, B and C", "Verdicts").
  double collapse_drift_ratio_rad = 0.1;
};

struct GroundMotionComponentDef {
  std::filesystem::path file;           // as written in the case file
  std::filesystem::path resolved_file;  // relative paths resolved against the case file's folder
  RecordFormat format = RecordFormat::PeerAt2;
  AccelerationUnit unit = AccelerationUnit::MetrePerSecond2;  // two_column only
  Vec3 direction = Vec3::UnitX();                             // unit vector, world frame (file: axis)
  double amplitude_scale = 1.0;                               // (-)
  AccelerationRecord record;                                  // loaded by load_case_file
  int line = 0;
};

struct GroundMotionDef {
  double time_scale = 1.0;      // simulation s per record s, > 0 (similitude of a scaled model)
  double window_start_s = 0.0;  // record time at simulation t = 0 (record s), >= 0
  // Record seconds used, > 0; infinity = to the end of the record.
  double window_length_s = std::numeric_limits<double>::infinity();
  std::vector<GroundMotionComponentDef> components;  // non-empty
};

// ---- contacts (contact) -----------------------------------------------------
// Contact parameters (contacts/contact_params.h, every default argued there)
// for the ground and for material pairs. Without a `contact` section bodies
// pass through each other and through the ground.
struct ContactPairDef {
  std::string material_1, material_2;
  ContactParams params;
  int line = 0;
};

// Which contacts act across connections that still hold (contact.intact_nodes;
// cases/README.md, "Contact across intact joints"). Pairs joined to each
// other directly by an intact joint never touch, in every mode.
enum class IntactNodeContact {
  // Members that meet at a node without a joint between them (two columns
  // both tenoned into the hub beam, a cross beam against a column) touch and
  // bear on each other while the joints hold; supported members bear on the
  // ground. The model frames A-C are argued with (the default).
  Touch,
  // Members joined at a node through a common member by intact joints, and
  // not joined to each other, touch only once one of those joints breaks;
  // supported members still bear on the ground.
  GroundOnly,
  // Seed 001's model, literally: "the model behaves as continuous medium
  // before the fracture of the springs"; no contact across an intact
  // connection, neither between members at a node nor between a supported
  // member and the ground, until a joint breaks.
  None,
};

// "touch", "ground_only", "none": the case file's words.
inline const char* intact_node_contact_name(IntactNodeContact mode) {
  switch (mode) {
    case IntactNodeContact::GroundOnly: return "ground_only";
    case IntactNodeContact::None: return "none";
    case IntactNodeContact::Touch: break;
  }
  return "touch";
}
// The mode a case file's word names; false for any other word.
inline bool parse_intact_node_contact(std::string_view word, IntactNodeContact& mode) {
  for (const IntactNodeContact m : {IntactNodeContact::Touch, IntactNodeContact::GroundOnly, IntactNodeContact::None})
    if (word == intact_node_contact_name(m)) {
      mode = m;
      return true;
    }
  return false;
}

struct ContactDef {
  std::optional<ContactParams> ground;  // box-ground half-space at ground.level_m; unset = no ground contact
  IntactNodeContact intact_nodes = IntactNodeContact::Touch;
  ContactParams default_pair;           // every material pair without an entry in `pairs`
  std::vector<ContactPairDef> pairs;
  int line = 0;
};

struct CaseDef {
  std::filesystem::path source_file;  // case file as given; empty when built in code
  int schema_version = kCaseSchemaVersion;
  std::string name;  // default: the case file's stem
  std::string description;
  TimeDef time;
  std::vector<MaterialDef> materials;
  std::vector<SectionDef> sections;
  std::vector<NodeDef> nodes;
  std::vector<MemberDef> members;
  std::vector<BlockDef> blocks;
  std::vector<SupportDef> supports;
  std::vector<JointTypeDef> joint_types;
  JointsDef joints;
  std::optional<ContactDef> contact;  // unset: no contacts
  std::optional<GroundDef> ground;               // unset: no `ground` section
  std::optional<GroundMotionDef> ground_motion;  // unset: no shaking
  AssessmentDef assessment;                      // storey verdict limits
  // folder default: out/<name>, relative to the working directory (filled by
  // load_case_file; build_model fills it when left empty).
  OutputDef output;
  // top-level key, and time.dt_s, time.duration_s, time.integrator,
  // ground_motion.window_start_s and ground_motion.window_length_s where
  // given -> 1-based line
  std::map<std::string, int> section_line;

  // Index of the item with that name/id, or -1.
  int material_index(std::string_view material_name) const;
  int section_index(std::string_view section_name) const;
  int node_index(std::string_view id) const;
  int joint_type_index(std::string_view type_name) const;
};

namespace case_def_detail {
template <class T>
int find_by_key(const std::vector<T>& items, std::string T::*key, std::string_view value) {
  for (std::size_t i = 0; i < items.size(); ++i)
    if (items[i].*key == value) return static_cast<int>(i);
  return -1;
}
}  // namespace case_def_detail

// First index of each name in a list, as find_by_key finds it, in O(1):
// set-up looks a name up per node or member end, which a scan made
// quadratic in the case's size (100k bodies took 90 s). The index holds
// copies of the names, so it stays valid when the list grows; adding to
// the list needs a matching add() here.
class NameIndex {
 public:
  NameIndex() = default;
  template <class T>
  NameIndex(const std::vector<T>& items, std::string T::*key) {
    map_.reserve(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) add(items[i].*key, static_cast<int>(i));
  }
  // Keeps an earlier index of the same name (find_by_key returns the first).
  void add(const std::string& name, int index) { map_.emplace(name, index); }
  int find(std::string_view name) const {
    const auto it = map_.find(name);
    return it == map_.end() ? -1 : it->second;
  }

 private:
  struct Hash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  std::unordered_map<std::string, int, Hash, std::equal_to<>> map_;
};

inline int CaseDef::material_index(std::string_view material_name) const {
  return case_def_detail::find_by_key(materials, &MaterialDef::name, material_name);
}
inline int CaseDef::section_index(std::string_view section_name) const {
  return case_def_detail::find_by_key(sections, &SectionDef::name, section_name);
}
inline int CaseDef::node_index(std::string_view id) const {
  return case_def_detail::find_by_key(nodes, &NodeDef::id, id);
}
inline int CaseDef::joint_type_index(std::string_view type_name) const {
  return case_def_detail::find_by_key(joint_types, &JointTypeDef::name, type_name);
}

// Default output folder of a case named `case_name`: out/<case_name>.
inline std::filesystem::path default_output_folder(const std::string& case_name) {
  return std::filesystem::path("out") / case_name;
}

}  // namespace fq
