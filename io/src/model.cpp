#include "io/model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "io/input_error.h"

namespace fq {

namespace {

// A member counts as vertical (its section follows the column rule of
// cases/README.md: width along world x) when its axis is within this angle
// of world z (case_def.h). The sloped rule (depth in the vertical plane
// through the axis) has no reliable direction near the vertical, and for a
// lean in the x-z plane it differs from the column rule by a quarter turn
// however small the lean. A cut at 1e-9 rad let a column whose top was
// 1 um off in x swap width and depth (a 6.5 times larger drift of a
// portal, geometry probe of stop 26); coordinates rounded to 1 mm on a
// 0.3 m column lean by 3e-3 rad. 10 degrees lies where few members are
// drawn: columns and posts within a few milliradians of vertical, braces
// and rafters 30-80 degrees from it.
constexpr double kVerticalTolerance_rad = 10.0 * std::numbers::pi / 180.0;

// The ground body's thickness. It only needs to be a valid box whose top face
// is the ground surface; 20 mm is thicker than any expected contact overlap,
// so nothing can pass through it within one contact.
constexpr double kGroundThickness_m = 0.020;

// A block may touch the ground surface exactly; the corner heights computed
// from a centre and a rotated half size carry round-off of ~1e-16 relative,
// so 1 nm of tolerance absorbs it while any real mistake (millimetres) is
// still caught.
constexpr double kGroundTolerance_m = 1e-9;

// The fixed ground body is dense soil; its mass is never used (fixed bodies
// have zero inverse mass) but add_box needs a positive density.
constexpr double kGroundDensity_kg_per_m3 = 2000.0;


[[noreturn]] void throw_input_error(const std::string& file, int line, const std::string& field,
                                    const std::string& message) {
  throw InputError(file, line, field, message);
}

std::string fmt(double x) {
  std::ostringstream os;
  os.precision(12);
  os << x;
  return os.str();
}

// What clears a member box that reaches below the ground surface. A node
// under the surface is a mistake in the heights; a member whose nodes are on
// or above the surface and whose box still dips below it leans (a post off
// plumb, an inclined brace or strut standing on the ground): the corners of
// its end face, half the section to either side of the axis, hang below
// the node. Trimming that end by t raises them by t u_z (u the axis pointing
// into the member from that end), so the trim that clears them is the
// present one plus dip / u_z (modelled as a box, the member cannot have its
// foot cut level).
std::string below_ground_advice(const CaseDef& def, const MemberDef& m, const BoxBodyDef& box, double level_m) {
  const Vec3 pa = def.nodes[std::size_t(def.node_index(m.node_a))].xyz_m;
  const Vec3 pb = def.nodes[std::size_t(def.node_index(m.node_b))].xyz_m;
  // A section wider than the member is long reaches below the ground from
  // nodes well above it: section sizes typed in millimetres (a probe's
  // 10 x 10 "m" beam was told to raise its nodes).
  const double side_m = std::max(box.size_m.y(), box.size_m.z());
  if (section_typed_in_mm(side_m, (pb - pa).norm()))
    return "its section ('" + m.section + "', " + fmt(box.size_m.y()) + " x " + fmt(box.size_m.z()) +
           " m) is wider than the member is long (" + fmt((pb - pa).norm()) +
           " m): section sizes are in metres (width_m, depth_m); were they typed in millimetres?";
  for (const auto& [node, xyz] : {std::pair{&m.node_a, pa}, std::pair{&m.node_b, pb}})
    if (xyz.z() < level_m - kGroundTolerance_m)
      return "its node '" + *node + "' is at z = " + fmt(xyz.z()) +
             " m, under the surface: raise its nodes or lower ground.level_m";
  // The lower end's face: its corners are the box's lowest points.
  const Mat3 r = box.orientation.toRotationMatrix();
  const Vec3 axis = (pb - pa).normalized();
  const bool at_a = pa.z() <= pb.z();
  const Vec3 into = at_a ? axis : Vec3(-axis);
  const Vec3 face_centre = box.position_m - into * (0.5 * box.size_m.x());
  const double corner_z =
      face_centre.z() - 0.5 * (std::fabs(r(2, 1)) * box.size_m.y() + std::fabs(r(2, 2)) * box.size_m.z());
  const double dip_m = level_m - corner_z;
  if (!(dip_m > 0.0)) return "raise its nodes, trim it clear of the ground (trim_m) or lower ground.level_m";
  const double trim_now = at_a ? m.trim_a_m : m.trim_b_m;
  const double trim_other = at_a ? m.trim_b_m : m.trim_a_m;
  // Rounded up to a micrometre, so that the advised trim clears the corner
  // (to within the tolerance the check allows).
  const double trim_needed =
      into.z() > 0.0 ? std::ceil((trim_now + dip_m / into.z() - kGroundTolerance_m) * 1e6) * 1e-6 : HUGE_VAL;
  // A member lying flat or nearly so cannot be trimmed clear: the trim
  // would take half its length or more (review probe: a 0.3 m member rising
  // 0.1 mm was told to trim 30 m, one rising 10 mm over 0.5 m its whole
  // length).
  const double length_m = (pb - pa).norm();
  if (!(trim_needed < 0.5 * (length_m - trim_other)))
    return "it lies too flat for a trim to clear the ground (the corners of its end at node '" +
           (at_a ? m.node_a : m.node_b) +
           "' dip below that node, and a trim clearing them would take half its length or more): raise its nodes "
           "or lower ground.level_m";
  return "it leans, so the corners of its end at node '" + (at_a ? m.node_a : m.node_b) +
         "' dip below that node: trim that end by at least " + fmt(trim_needed) + " m (trim_m[" + (at_a ? "0" : "1") +
         "], now " + fmt(trim_now) + " m), or raise its nodes";
}

std::string item_path(const char* list, std::size_t i) { return std::string(list) + "[" + std::to_string(i) + "]"; }

// Corners of a box (world frame) for bounding boxes.
void extend_bounds(const Vec3& centre_m, const Quat& q, const Vec3& size_m, Vec3& lo, Vec3& hi) {
  const Mat3 r = q.toRotationMatrix();
  for (int k = 0; k < 8; ++k) {
    const Vec3 s((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5);
    const Vec3 c = centre_m + r * s.cwiseProduct(size_m);
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
}

}  // namespace

Quat member_orientation(const Vec3& a_m, const Vec3& b_m, double roll_rad) {
  const Vec3 ex = (b_m - a_m).normalized();
  Vec3 ey;
  Vec3 ez;
  // |ex x z| = sin(angle to the vertical): the horizontal part of ex.
  if (std::hypot(ex.x(), ex.y()) > std::sin(kVerticalTolerance_rad)) {
    ez = (Vec3::UnitZ() - ex.z() * ex).normalized();
    ey = ez.cross(ex);
  } else {
    ey = (Vec3::UnitX() - ex.x() * ex).normalized();
    ez = ex.cross(ey);
  }
  // Roll the section about local x (right-handed, y towards z).
  const double c = std::cos(roll_rad);
  const double s = std::sin(roll_rad);
  const Vec3 ey_rolled = c * ey + s * ez;
  const Vec3 ez_rolled = -s * ey + c * ez;
  Mat3 r;
  r.col(0) = ex;
  r.col(1) = ey_rolled;
  r.col(2) = ez_rolled;
  return Quat(r).normalized();
}

Quat block_orientation(const Vec3& rotation_rad) {
  return (Eigen::AngleAxisd(rotation_rad.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rotation_rad.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rotation_rad.x(), Vec3::UnitX()))
      .normalized();
}

Model build_model(const CaseDef& def_in) {
  Model model;
  model.def = def_in;
  CaseDef& def = model.def;
  const std::string file = def.source_file.string();
  auto fail = [&file](int line, const std::string& field, const std::string& message) {
    throw_input_error(file, line, field, message);
  };

  if (def.name.empty()) def.name = def.source_file.empty() ? std::string("case") : def.source_file.stem().string();
  if (def.output.folder.empty()) def.output.folder = default_output_folder(def.name);
  const int time_line = def.section_line.count("time") ? def.section_line.at("time") : 0;
  if (!(def.time.dt_s > 0.0) || !std::isfinite(def.time.dt_s))
    fail(time_line, "time.dt_s", "expected a positive time step in s");
  if (def.members.empty() && def.blocks.empty())
    fail(0, "", "the case has no bodies: expected at least one member or block");

  auto material_density = [&](const std::string& name, int line, const std::string& path) {
    const int i = def.material_index(name);
    if (i < 0) fail(line, path + ".material", "no material named '" + name + "'");
    const MaterialDef& m = def.materials[std::size_t(i)];
    if (!(m.density_kg_per_m3 > 0.0) || !std::isfinite(m.density_kg_per_m3))
      fail(m.line, item_path("materials", std::size_t(i)) + ".density_kg_per_m3",
           "expected a positive density in kg/m^3");
    if (const std::string why = density_out_of_range(m.density_kg_per_m3); !why.empty())
      fail(m.line, item_path("materials", std::size_t(i)) + ".density_kg_per_m3", why);
    return m.density_kg_per_m3;
  };
  const NameIndex member_ids(def.members, &MemberDef::id), block_ids(def.blocks, &BlockDef::id);
  auto check_unique_id = [&](const std::string& id, std::size_t upto_members, std::size_t upto_blocks, int line,
                             const std::string& path) {
    // The ground body is named "ground" in every output (body names, joint
    // names such as se0:ground-column1_se): a member or block of that id
    // would be told from it by nothing (review probe: two joints of one name).
    if (id == "ground")
      fail(line, path + ".id", "id 'ground' is the ground body's name in the outputs; give this one another id");
    // The first holder of the id (indexed: this runs per member and block).
    if (const int j = member_ids.find(id); j >= 0 && std::size_t(j) < upto_members)
      fail(line, path + ".id", "id '" + id + "' is already used by " + item_path("members", std::size_t(j)));
    if (const int j = block_ids.find(id); j >= 0 && std::size_t(j) < upto_blocks)
      fail(line, path + ".id", "id '" + id + "' is already used by " + item_path("blocks", std::size_t(j)));
  };
  const NameIndex node_ids(def.nodes, &NodeDef::id);

  // Box definitions first, so the ground body can be sized to them.
  std::vector<BoxBodyDef> member_boxes;
  std::vector<BoxBodyDef> block_boxes;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  for (std::size_t i = 0; i < def.members.size(); ++i) {
    const MemberDef& m = def.members[i];
    const std::string path = item_path("members", i);
    if (m.id.empty()) fail(m.line, path + ".id", "expected a member id");
    check_unique_id(m.id, i, 0, m.line, path);
    const int a = node_ids.find(m.node_a);
    const int b = node_ids.find(m.node_b);
    if (a < 0) fail(m.line, path + ".nodes[0]", "no node named '" + m.node_a + "'");
    if (b < 0) fail(m.line, path + ".nodes[1]", "no node named '" + m.node_b + "'");
    const Vec3 pa = def.nodes[std::size_t(a)].xyz_m;
    const Vec3 pb = def.nodes[std::size_t(b)].xyz_m;
    const double length_m = (pb - pa).norm();
    if (!(length_m > kMinMemberLength_m))
      fail(m.line, path + ".nodes",
           "nodes '" + m.node_a + "' and '" + m.node_b +
               "' are at the same position, so the member would have no length");
    const int s = def.section_index(m.section);
    if (s < 0) fail(m.line, path + ".section", "no section named '" + m.section + "'");
    const SectionDef& sec = def.sections[std::size_t(s)];
    if (!(sec.width_m > 0.0) || !(sec.depth_m > 0.0) || !std::isfinite(sec.width_m) || !std::isfinite(sec.depth_m))
      fail(sec.line, item_path("sections", std::size_t(s)), "expected a positive width_m and depth_m");
    if (m.kind == MemberKind::Ground) fail(m.line, path + ".kind", "a member cannot be of kind ground");

    if (!(m.trim_a_m >= 0.0) || !(m.trim_b_m >= 0.0) || !(m.trim_a_m + m.trim_b_m < length_m - kMinMemberLength_m))
      fail(m.line, path + ".trim_m",
           "expected two trims >= 0 whose sum is less than the member length " + std::to_string(length_m) + " m");
    const Vec3 axis = (pb - pa) / length_m;
    const double box_length_m = length_m - m.trim_a_m - m.trim_b_m;

    BoxBodyDef box;
    box.name = m.id;
    box.kind = m.kind;
    box.size_m = Vec3(box_length_m, sec.width_m, sec.depth_m);
    box.density_kg_per_m3 = material_density(m.material, m.line, path);
    box.position_m = pa + (m.trim_a_m + 0.5 * box_length_m) * axis;
    box.orientation = member_orientation(pa, pb, m.roll_rad);
    extend_bounds(box.position_m, box.orientation, box.size_m, lo, hi);
    member_boxes.push_back(box);
  }
  for (std::size_t i = 0; i < def.blocks.size(); ++i) {
    const BlockDef& bl = def.blocks[i];
    const std::string path = item_path("blocks", i);
    if (bl.id.empty()) fail(bl.line, path + ".id", "expected a block id");
    check_unique_id(bl.id, def.members.size(), i, bl.line, path);
    if (!(bl.size_m.minCoeff() > 0.0) || !bl.size_m.allFinite())
      fail(bl.line, path + ".size_m", "expected three positive edge lengths in m");
    if (bl.kind == MemberKind::Ground) fail(bl.line, path + ".kind", "a block cannot be of kind ground");
    BoxBodyDef box;
    box.name = bl.id;
    box.kind = bl.kind;
    box.size_m = bl.size_m;
    box.density_kg_per_m3 = material_density(bl.material, bl.line, path);
    box.position_m = bl.center_m;
    box.orientation = block_orientation(bl.rotation_rad);
    box.velocity_mps = bl.velocity_mps;
    box.angular_velocity_radps = bl.angular_velocity_radps;
    box.fixed = bl.fixed;
    extend_bounds(box.position_m, box.orientation, box.size_m, lo, hi);
    block_boxes.push_back(box);
  }
  for (std::size_t i = 0; i < def.supports.size(); ++i) {
    const SupportDef& s = def.supports[i];
    if (node_ids.find(s.node) < 0) fail(s.line, item_path("supports", i) + ".node", "no node named '" + s.node + "'");
  }

  // Ground body. Its top face is the ground surface. In plan it covers the
  // structure's footprint twice over (edge = 2 x footprint edge, centred on
  // it) and at least the footprint plus the structure's height on every
  // side: a member toppling about its base lands up to its height away.
  // With ground contact, a member below the ground would start inside it:
  // the contact throws it out at the first step, breaking its joints (a
  // support node below the ground is a mistake in the node heights or in
  // level_m, an untrimmed brace end one in trim_m), and a block below it is
  // thrown out at once. Without ground contact members pass through the
  // ground and may start in it. The ground contact's surface is
  // ground.level_m, or z = 0 without a ground section.
  const bool ground_contact = def.contact && def.contact->ground;
  const double level_m = def.ground ? def.ground->level_m : 0.0;
  if (def.ground || !def.supports.empty() || ground_contact) {
    for (std::size_t i = 0; ground_contact && i < def.members.size(); ++i) {
      Vec3 mlo = Vec3::Constant(std::numeric_limits<double>::infinity());
      Vec3 mhi = -mlo;
      extend_bounds(member_boxes[i].position_m, member_boxes[i].orientation, member_boxes[i].size_m, mlo, mhi);
      if (mlo.z() < level_m - kGroundTolerance_m)
        fail(def.members[i].line, item_path("members", i) + ".nodes",
             "the member '" + def.members[i].id + "' reaches " + fmt(level_m - mlo.z()) +
                 " m below the ground surface (z = " + fmt(level_m) + " m); " +
                 below_ground_advice(def, def.members[i], member_boxes[i], level_m));
    }
    for (std::size_t i = 0; i < def.blocks.size(); ++i) {
      Vec3 blo = Vec3::Constant(std::numeric_limits<double>::infinity());
      Vec3 bhi = -blo;
      extend_bounds(block_boxes[i].position_m, block_boxes[i].orientation, block_boxes[i].size_m, blo, bhi);
      if (blo.z() < level_m - kGroundTolerance_m)
        fail(def.blocks[i].line, item_path("blocks", i) + ".center_m",
             "the block reaches " + fmt(level_m - blo.z()) + " m below the ground surface (z = " + fmt(level_m) +
                 " m); raise it or lower ground.level_m");
    }
  }
  // The ground body, where there is a ground section or supports (a case
  // with ground contact alone has its surface at z = 0 and no body for it).
  if (def.ground || !def.supports.empty()) {
    const Vec3 extent = (hi - lo).cwiseMax(Vec3::Zero());
    const double height_m = std::max(0.0, hi.z() - level_m);
    BoxBodyDef g;
    g.name = "ground";
    g.kind = MemberKind::Ground;
    g.size_m = Vec3(std::max(2.0 * extent.x(), extent.x() + 2.0 * height_m),
                    std::max(2.0 * extent.y(), extent.y() + 2.0 * height_m), kGroundThickness_m);
    g.density_kg_per_m3 = kGroundDensity_kg_per_m3;
    g.position_m = Vec3(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), level_m - 0.5 * kGroundThickness_m);
    g.fixed = true;
    model.ground_body = model.bodies.add_box(g);
  }

  // Sizes and densities were checked above; add_box still refuses a mass or
  // inertia that doubles cannot hold (edges of 1e-200 m), named here.
  for (std::size_t i = 0; i < member_boxes.size(); ++i) {
    try {
      model.member_body.push_back(model.bodies.add_box(member_boxes[i]));
    } catch (const std::invalid_argument& e) {
      fail(def.members[i].line, item_path("members", i), e.what());
    }
  }
  for (std::size_t i = 0; i < block_boxes.size(); ++i) {
    try {
      model.block_body.push_back(model.bodies.add_box(block_boxes[i]));
    } catch (const std::invalid_argument& e) {
      fail(def.blocks[i].line, item_path("blocks", i) + ".size_m", e.what());
    }
  }

  // Ground motion.
  if (def.ground_motion) {
    const GroundMotionDef& gm = *def.ground_motion;
    for (std::size_t i = 0; i < gm.components.size(); ++i) {
      const GroundMotionComponentDef& c = gm.components[i];
      GroundMotionComponent comp;
      comp.record = c.record;
      comp.direction = c.direction;
      comp.amplitude_scale = c.amplitude_scale;
      comp.time_scale = gm.time_scale;
      comp.window_start_s = gm.window_start_s;
      comp.window_length_s = gm.window_length_s;
      try {
        model.ground_motion.add_component(std::move(comp));
      } catch (const std::invalid_argument& e) {
        fail(c.line, "ground_motion.components[" + std::to_string(i) + "]", e.what());
      }
    }
  }

  model.settings.dt_s = def.time.dt_s;
  model.settings.gravity_mps2 = def.time.gravity_mps2;
  model.settings.integrator = def.time.integrator;
  if (def.time.duration_s) {
    model.settings.duration_s = *def.time.duration_s;
  } else if (!model.ground_motion.empty()) {
    model.settings.duration_s = model.ground_motion.end_time_s();
  } else {
    fail(time_line, "time.duration_s", "missing duration_s (required when there is no ground motion)");
  }
  if (!(model.settings.duration_s > 0.0) || !std::isfinite(model.settings.duration_s))
    fail(time_line, "time.duration_s", "expected a positive duration in s");
  // A run of no step would "complete" having done nothing (the case reader
  // refuses an explicit duration_s below dt_s; this catches a window, or a
  // duration shortened by compare/sweep --window-length).
  // The line of a key of the case file where it was read; 0 when not given.
  auto key_line = [&](const char* key) {
    const auto it = def.section_line.find(key);
    return it != def.section_line.end() ? it->second : 0;
  };
  auto line_of = [&](const char* key) { return key_line(key) ? key_line(key) : time_line; };
  if (model.settings.duration_s < model.settings.dt_s) {
    if (def.time.duration_s)
      fail(line_of("time.duration_s"), "time.duration_s",
           "the run lasts " + fmt(model.settings.duration_s) + " s, less than one time step (dt_s = " +
               fmt(model.settings.dt_s) + " s)");
    // Named at dt_s, with the window beside it: either may be the mistake
    // (a probe's dt_s of 10 s was blamed on the window, at the time: line).
    // Without window_length_s the window runs from window_start_s to the
    // record's end (review probe: the message named the absent key).
    auto at_line = [&](const char* key) { return key_line(key) ? ", line " + std::to_string(key_line(key)) : ""; };
    const std::string window = key_line("ground_motion.window_length_s")
                                   ? "ground_motion.window_length_s" + at_line("ground_motion.window_length_s")
                                   : "from ground_motion.window_start_s" + at_line("ground_motion.window_start_s") +
                                         " to the record's end";
    fail(line_of("time.dt_s"), "time.dt_s",
         "the time step dt_s = " + fmt(model.settings.dt_s) +
             " s is longer than the run: the ground-motion window lasts " + fmt(model.settings.duration_s) +
             " s of simulated time (" + window + ", times time_scale); give a smaller dt_s, a longer window or a "
             "duration_s");
  }
  if (const double steps = model.settings.duration_s / model.settings.dt_s; !(steps <= kMaxSimulationSteps)) {
    // Which of the two is off: a step below 10 ns is no time step a frame
    // needs (a probe's 1e-300 s was blamed on a 2 s duration).
    const char* field = def.time.duration_s && model.settings.dt_s >= 1e-8 ? "time.duration_s" : "time.dt_s";
    fail(line_of(field), field,
         "duration " + fmt(model.settings.duration_s) + " s at dt_s = " + fmt(model.settings.dt_s) + " s is " +
             (std::isfinite(steps) ? fmt(steps) : "more than " + fmt(kMaxSimulationSteps)) + " steps; at most " +
             fmt(kMaxSimulationSteps) +
             " are accepted (check the units of dt_s and duration_s)");
  }
  return model;
}

}  // namespace fq
