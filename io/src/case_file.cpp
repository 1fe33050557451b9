#include "io/case_file.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "io/input_error.h"
#include "io/name_hint.h"

// How the reader is organised. A case file is a mapping of top-level sections;
// each has an entry in kSections (key, required or not, parser function).
// Sections are parsed in the table's order, not the file's, so a section may
// refer to names defined by a section written later in the file. Inside a
// section, every mapping first goes through expect_keys (unknown or repeated
// keys are refused, naming the keys allowed there), then each field is read
// with an accessor that knows the field's full path and line: require/get
// find a key, and to_number, to_positive, to_name, to_vec3, ... convert its
// value or throw. Adding a section later (joint_types, joints, contact) means
// writing one parse function and adding one row to kSections.

namespace fq {
namespace {

// Why `file` cannot be read as a file ("" when it can be opened): not
// found, a folder, or something else (a device, a socket).
std::string why_not_a_readable_file(const std::filesystem::path& file) {
  std::error_code ec;
  const auto status = std::filesystem::status(file, ec);
  // A loop of symbolic links, or a folder on the way that may not be
  // searched, is no missing file (error probe: a link loop read "not
  // found").
  if (ec && ec != std::errc::no_such_file_or_directory && ec != std::errc::not_a_directory)
    return "cannot be reached: " + ec.message();
  if (ec || !std::filesystem::exists(status)) return "not found";
  if (std::filesystem::is_directory(status)) return "is a folder, not a file";
  if (!std::filesystem::is_regular_file(status)) return "is not a regular file";
  return "";
}

// The record file a case names, as the operating system finds it: `file`
// relative to the case file's folder. The lexically normal form ("a/b/../c"
// as "a/c") reads better in messages and summary.json, but it drops
// "link/.." without following the link, where the system goes up from the
// link's target: a case in a symbolically linked folder naming
// ../gm/rec.AT2 read another file of that name beside the link, silently
// (input probe, stop 41). The normal form is kept where its folder is the
// folder the system reaches; otherwise that folder with its links
// followed, and the file's own name (a record that is itself a link keeps
// the name the case gives it, as in a git-annex store; review, stop 41).
std::filesystem::path resolve_record_path(const std::filesystem::path& case_folder, const std::filesystem::path& file) {
  namespace fs = std::filesystem;
  const fs::path given = file.is_absolute() ? file : case_folder / file;
  const fs::path normal = given.lexically_normal();
  if (normal == given || given.filename().empty()) return normal;
  std::error_code ec, ec_normal;
  const fs::path folder = fs::weakly_canonical(given.parent_path().empty() ? fs::path(".") : given.parent_path(), ec);
  if (ec) return given;
  const fs::path normal_folder =
      fs::weakly_canonical(normal.parent_path().empty() ? fs::path(".") : normal.parent_path(), ec_normal);
  if (!ec_normal && normal_folder == folder) return normal;
  return folder / given.filename();
}

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// Compact decimal form for messages ("200", "0.02", "149.98"), 12 digits.
std::string fmt(double x) {
  std::ostringstream os;
  os.precision(12);
  os << x;
  return os.str();
}

std::string join(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}
std::string index_path(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// Short description of what a YAML node holds, for "got ..." in messages.
std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return "nothing";
    case YAML::NodeType::Scalar:
      return (n.Tag() == "!" ? "the quoted text \"" : "'") + n.Scalar() + (n.Tag() == "!" ? "\"" : "'");
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a mapping";
  }
  return "something else";
}

std::string join_names(const std::vector<std::string_view>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + std::string(names[i]);
  return s;
}

// A key found in a mapping: its value, the line to report and the field path.
struct Field {
  YAML::Node value;
  int line = 0;
  std::string path;
};

using Keys = std::vector<std::string_view>;

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  static int line_of(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

  [[noreturn]] void fail(int line, const std::string& path, const std::string& message) const {
    throw InputError(file_, line, path, message);
  }
  [[noreturn]] void fail(const Field& f, const std::string& message) const { fail(f.line, f.path, message); }

  // `node` must be a mapping (what = what it should hold, for the message).
  void expect_map(const YAML::Node& node, int line, const std::string& path, const std::string& what) const {
    if (!node.IsMap()) fail(line, path, "expected a mapping (" + what + "), got " + describe(node));
  }

  // Every key of mapping `node` must be in `allowed` and appear once.
  void expect_keys(const YAML::Node& node, const Keys& allowed, const std::string& path) const {
    std::vector<std::pair<std::string, int>> seen;
    for (auto it = node.begin(); it != node.end(); ++it) {
      // A copy (a cheap handle): `it->first` belongs to a temporary proxy
      // that dies at the end of the statement, so a reference would dangle
      // (found by fuzz_case_file under ASan, stack-use-after-scope).
      const YAML::Node k = it->first;
      const int line = line_of(k);
      if (!k.IsScalar()) fail(line, path, "expected a key name, got " + describe(k));
      const std::string key = k.Scalar();
      const std::string where = path.empty() ? std::string("at the top level") : "in '" + path + "'";
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string message = "unknown key '" + key + "' " + where + "; allowed keys here: " + join_names(allowed);
        if (const auto hint = nearest(key, allowed)) message += did_you_mean(std::string(*hint));
        fail(line, join(path, key), message);
      }
      for (const auto& [other, other_line] : seen)
        if (other == key)
          fail(line, join(path, key),
               "key '" + key + "' appears twice " + where + " (first on line " + std::to_string(other_line) + ")");
      seen.emplace_back(key, line);
    }
  }

  // The key's field, or nothing when absent. A key written with no value
  // (`key:`) counts as present with a null value and is reported on its line.
  std::optional<Field> get(const YAML::Node& map, std::string_view key, const std::string& path) const {
    for (auto it = map.begin(); it != map.end(); ++it) {
      if (it->first.IsScalar() && it->first.Scalar() == key) {
        const YAML::Node v = it->second;  // a copy, as in expect_keys
        const int line = (v.IsNull() || line_of(v) == 0) ? line_of(it->first) : line_of(v);
        return Field{v, line, join(path, key)};
      }
    }
    return std::nullopt;
  }
  Field require(const YAML::Node& map, std::string_view key, const std::string& path, const std::string& what) const {
    if (auto f = get(map, key, path)) return *f;
    fail(line_of(map), join(path, key), "missing required key '" + std::string(key) + "' (" + what + ")");
  }

  // ---- conversions of a field's value --------------------------------------
  double to_number(const Field& f, const std::string& what = "a number") const {
    const YAML::Node& v = f.value;
    if (!v.IsScalar() || v.Tag() == "!") fail(f, "expected " + what + ", got " + describe(v));
    std::string_view s = v.Scalar();
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double x = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty())
      fail(f, "expected " + what + ", got " + describe(v));
    if (!std::isfinite(x)) fail(f, "expected " + what + " (finite), got " + describe(v));
    return x;
  }
  double to_positive(const Field& f) const {
    const double x = to_number(f, "a positive number");
    if (!(x > 0.0)) fail(f, "expected a positive number, got " + describe(f.value));
    return x;
  }
  double to_non_negative(const Field& f) const {
    const double x = to_number(f, "a number >= 0");
    if (!(x >= 0.0)) fail(f, "expected a number >= 0, got " + describe(f.value));
    return x;
  }
  int to_int(const Field& f) const {
    const YAML::Node& v = f.value;
    int x = 0;
    if (v.IsScalar() && v.Tag() != "!") {
      const std::string& s = v.Scalar();
      const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
      if (ec == std::errc() && end == s.data() + s.size() && !s.empty()) return x;
    }
    fail(f, "expected a whole number, got " + describe(v));
  }
  bool to_bool(const Field& f) const {
    const YAML::Node& v = f.value;
    if (v.IsScalar() && v.Tag() != "!") {
      const std::string& s = v.Scalar();
      if (s == "true" || s == "True" || s == "TRUE") return true;
      if (s == "false" || s == "False" || s == "FALSE") return false;
    }
    fail(f, "expected true or false, got " + describe(v));
  }
  std::string to_text(const Field& f) const {
    if (!f.value.IsScalar()) fail(f, "expected text, got " + describe(f.value));
    return f.value.Scalar();
  }
  // Names and ids end up in folder names, CSV cells and messages: letters,
  // digits, '_', '-' and '.' only, so none of those can be broken by them.
  std::string to_name(const Field& f, const std::string& what) const {
    const YAML::Node& v = f.value;
    if (v.IsScalar() && !v.Scalar().empty()) {
      const std::string& s = v.Scalar();
      const bool ok = std::all_of(s.begin(), s.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
               c == '.';
      });
      // "." and ".." name folders of their own (a case named '.' wrote its
      // run into the study's folder): at least one character not a dot.
      const bool only_dots = s.find_first_not_of('.') == std::string::npos;
      if (ok && !only_dots) return s;
      if (ok) fail(f, "expected " + what + " with at least one letter, digit, '_' or '-', got " + describe(v));
    }
    fail(f, "expected " + what + " (letters, digits, '_', '-' or '.'), got " + describe(v));
  }
  // A list (the key's value must be a sequence; `non_empty` refuses []).
  YAML::Node to_list(const Field& f, const std::string& what, bool non_empty) const {
    if (!f.value.IsSequence()) fail(f, "expected a list of " + what + ", got " + describe(f.value));
    if (non_empty && f.value.size() == 0) fail(f, "expected a non-empty list of " + what + ", got an empty list");
    return f.value;
  }
  Vec3 to_vec3(const Field& f, const std::string& what) const {
    const YAML::Node& v = f.value;
    if (!v.IsSequence() || v.size() != 3)
      fail(f, "expected a list of 3 numbers (" + what + "), got " +
                  (v.IsSequence() ? "a list of " + std::to_string(v.size()) : describe(v)));
    Vec3 out;
    for (std::size_t i = 0; i < 3; ++i)
      out[static_cast<Eigen::Index>(i)] =
          to_number(Field{v[i], line_of(v[i]) ? line_of(v[i]) : f.line, index_path(f.path, i)});
    return out;
  }
  // Field of the i-th item of a list field.
  static Field item(const Field& list, std::size_t i) {
    const YAML::Node n = list.value[i];
    return Field{n, line_of(n) ? line_of(n) : list.line, index_path(list.path, i)};
  }

  // ---- accessors on a mapping ------------------------------------------------
  double required_positive(const YAML::Node& map, std::string_view key, const std::string& path,
                           const std::string& what) const {
    return to_positive(require(map, key, path, what));
  }
  double optional_positive(const YAML::Node& map, std::string_view key, const std::string& path, double dflt) const {
    const auto f = get(map, key, path);
    return f ? to_positive(*f) : dflt;
  }
  double optional_number(const YAML::Node& map, std::string_view key, const std::string& path, double dflt) const {
    const auto f = get(map, key, path);
    return f ? to_number(*f) : dflt;
  }
  double optional_non_negative(const YAML::Node& map, std::string_view key, const std::string& path,
                               double dflt) const {
    const auto f = get(map, key, path);
    return f ? to_non_negative(*f) : dflt;
  }
  bool optional_bool(const YAML::Node& map, std::string_view key, const std::string& path, bool dflt) const {
    const auto f = get(map, key, path);
    return f ? to_bool(*f) : dflt;
  }
  Vec3 optional_vec3(const YAML::Node& map, std::string_view key, const std::string& path, const Vec3& dflt,
                     const std::string& what) const {
    const auto f = get(map, key, path);
    return f ? to_vec3(*f, what) : dflt;
  }
  std::string required_name(const YAML::Node& map, std::string_view key, const std::string& path,
                            const std::string& what) const {
    return to_name(require(map, key, path, what), what);
  }

 private:
  // An allowed key close to a mistyped one: same key plus a unit suffix
  // ("dt" -> "dt_s") or within two edits ("densty_kg_per_m3").
  static std::optional<std::string_view> nearest(const std::string& key, const Keys& allowed) {
    for (std::string_view a : allowed)
      if (a.size() > key.size() && a.substr(0, key.size()) == key && a[key.size()] == '_') return a;
    for (std::string_view a : allowed)
      if (edit_distance(key, a) <= 2) return a;
    return std::nullopt;
  }

  std::string file_;
};

// Walks the items of list field `f`, checking each is a mapping with only
// `allowed` keys; calls fn(item_node, item_path, item_line, index).
template <class Fn>
void for_each_item(const Reader& r, const Field& f, const std::string& what, const Keys& allowed, Fn fn) {
  for (std::size_t i = 0; i < f.value.size(); ++i) {
    const Field it = Reader::item(f, i);
    r.expect_map(it.value, it.line, it.path, what);
    r.expect_keys(it.value, allowed, it.path);
    fn(it.value, it.path, it.line, i);
  }
}

// ---- top-level sections -----------------------------------------------------

void parse_version(const Reader& r, const Field& f, CaseDef& def) {
  const int v = r.to_int(f);
  if (v != kCaseSchemaVersion)
    r.fail(f, "unknown schema version " + std::to_string(v) + "; this build of framequake reads version " +
                  std::to_string(kCaseSchemaVersion));
  def.schema_version = v;
}

void parse_name(const Reader& r, const Field& f, CaseDef& def) {
  def.name = r.to_name(f, "a case name");
  if (def.name.size() > kMaxCaseNameLength)
    r.fail(f, "the case name is " + std::to_string(def.name.size()) + " characters long; at most " +
                  std::to_string(kMaxCaseNameLength) +
                  " (it names the run's output folder, and a sweep's folders add the record and the scale to it)");
}

void parse_description(const Reader& r, const Field& f, CaseDef& def) { def.description = r.to_text(f); }

void parse_time(const Reader& r, const Field& f, CaseDef& def) {
  r.expect_map(f.value, f.line, f.path, "dt_s, duration_s, gravity_mps2, integrator");
  r.expect_keys(f.value, {"dt_s", "duration_s", "gravity_mps2", "integrator"}, f.path);
  def.time.dt_s = r.required_positive(f.value, "dt_s", f.path, "the time step in s");
  // Lines of the keys a run's start checks name (case_runner.cpp).
  if (const auto d = r.get(f.value, "dt_s", f.path)) def.section_line["time.dt_s"] = d->line;
  if (const auto m = r.get(f.value, "integrator", f.path)) def.section_line["time.integrator"] = m->line;
  if (const auto d = r.get(f.value, "duration_s", f.path)) {
    def.time.duration_s = r.to_positive(*d);
    def.section_line["time.duration_s"] = d->line;
  }
  def.time.gravity_mps2 =
      r.optional_vec3(f.value, "gravity_mps2", f.path, def.time.gravity_mps2, "gx, gy, gz in m/s^2");
  if (const auto g = r.get(f.value, "gravity_mps2", f.path); g && !(def.time.gravity_mps2.stableNorm() <= kMaxGravity_mps2)) {
    std::ostringstream why;
    why << "gravity of " << def.time.gravity_mps2.stableNorm() << " m/s^2 is more than " << kMaxGravity_mps2
        << " m/s^2 (20 g; standard gravity is 9.80665): a typing error or a unit off?";
    r.fail(*g, why.str());
  }
  if (const auto m = r.get(f.value, "integrator", f.path)) {
    if (!parse_integrator(r.to_text(*m), def.time.integrator)) {
      r.fail(*m, "expected one of " + integrator_names_list() + ", got " + describe(m->value) +
                     did_you_mean(nearest_name(r.to_text(*m), integrator_names())));
    }
  }
  // One step (dt_s == duration_s) is a run; less than one is not.
  if (def.time.duration_s && def.time.dt_s > *def.time.duration_s) {
    const auto d = r.get(f.value, "dt_s", f.path);
    r.fail(*d, "the time step must not exceed duration_s (a run takes at least one step)");
  }
}

void parse_materials(const Reader& r, const Field& f, CaseDef& def) {
  r.to_list(f, "materials", true);
  for_each_item(r, f, "a material: name, density_kg_per_m3", {"name", "density_kg_per_m3"},
                [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
                  MaterialDef m;
                  m.line = line;
                  const Field name = r.require(n, "name", path, "the material's name");
                  m.name = r.to_name(name, "a material name");
                  if (const int other = def.material_index(m.name); other >= 0)
                    r.fail(name, "material name '" + m.name + "' is already used by materials[" +
                                     std::to_string(other) + "] (line " +
                                     std::to_string(def.materials[std::size_t(other)].line) + ")");
                  const Field density = r.require(n, "density_kg_per_m3", path, "density in kg/m^3");
                  m.density_kg_per_m3 = r.to_positive(density);
                  if (const std::string why = density_out_of_range(m.density_kg_per_m3); !why.empty())
                    r.fail(density, why);
                  def.materials.push_back(m);
                });
}

void parse_sections(const Reader& r, const Field& f, CaseDef& def) {
  r.to_list(f, "sections", false);
  for_each_item(r, f, "a section: name, width_m, depth_m", {"name", "width_m", "depth_m"},
                [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
                  SectionDef s;
                  s.line = line;
                  const Field name = r.require(n, "name", path, "the section's name");
                  s.name = r.to_name(name, "a section name");
                  if (const int other = def.section_index(s.name); other >= 0)
                    r.fail(name, "section name '" + s.name + "' is already used by sections[" + std::to_string(other) +
                                     "] (line " + std::to_string(def.sections[std::size_t(other)].line) + ")");
                  s.width_m = r.required_positive(n, "width_m", path, "edge along member local y in m");
                  s.depth_m = r.required_positive(n, "depth_m", path, "edge along member local z in m");
                  for (const char* key : {"width_m", "depth_m"})
                    if (const std::string why = edge_out_of_range(key[0] == 'w' ? s.width_m : s.depth_m); !why.empty())
                      r.fail(*r.get(n, key, path), why);
                  def.sections.push_back(s);
                });
}

void parse_nodes(const Reader& r, const Field& f, CaseDef& def) {
  r.to_list(f, "nodes", false);
  NameIndex ids(def.nodes, &NodeDef::id);
  for_each_item(r, f, "a node: id, xyz_m", {"id", "xyz_m"},
                [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
                  NodeDef nd;
                  nd.line = line;
                  const Field id = r.require(n, "id", path, "the node's id");
                  nd.id = r.to_name(id, "a node id");
                  if (const int other = ids.find(nd.id); other >= 0)
                    r.fail(id, "node id '" + nd.id + "' is already used by nodes[" + std::to_string(other) +
                                   "] (line " + std::to_string(def.nodes[std::size_t(other)].line) + ")");
                  const Field xyz = r.require(n, "xyz_m", path, "position x, y, z in m");
                  nd.xyz_m = r.to_vec3(xyz, "x, y, z in m");
                  if (const std::string why = coordinate_out_of_range(nd.xyz_m); !why.empty()) r.fail(xyz, why);
                  ids.add(nd.id, static_cast<int>(def.nodes.size()));
                  def.nodes.push_back(nd);
                });
}

// Members and blocks share one id space: both become bodies named by id.
// Indexed, as it is asked once per member and block.
struct BodyIds {
  NameIndex members, blocks;
  explicit BodyIds(const CaseDef& def) : members(def.members, &MemberDef::id), blocks(def.blocks, &BlockDef::id) {}
};
std::string body_id_owner(const CaseDef& def, const BodyIds& ids, const std::string& id) {
  if (const int i = ids.members.find(id); i >= 0)
    return "members[" + std::to_string(i) + "] (line " + std::to_string(def.members[std::size_t(i)].line) + ")";
  if (const int i = ids.blocks.find(id); i >= 0)
    return "blocks[" + std::to_string(i) + "] (line " + std::to_string(def.blocks[std::size_t(i)].line) + ")";
  return {};
}

std::string list_of_names(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size() && i < 12; ++i) s += (i ? ", " : "") + names[i];
  if (names.size() > 12) s += ", ...";
  return s;
}

template <class T>
std::string reference_message(const std::string& kind, const std::string& given, const std::vector<T>& items,
                              std::string T::*key, const std::string& list_key) {
  if (items.empty())
    return "no " + kind + " named '" + given + "': the case defines none (add a '" + list_key + ":' list)";
  std::vector<std::string> names;
  for (const T& it : items) names.push_back(it.*key);
  return "no " + kind + " named '" + given + "'; defined: " + list_of_names(names);
}

void parse_members(const Reader& r, const Field& f, CaseDef& def) {
  r.to_list(f, "members", false);
  const NameIndex node_ids(def.nodes, &NodeDef::id);
  BodyIds body_ids(def);
  for_each_item(
      r, f, "a member: id, kind, nodes, section, material, roll_deg, trim_m",
      {"id", "kind", "nodes", "section", "material", "roll_deg", "trim_m"},
      [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
        MemberDef m;
        m.line = line;
        const Field id = r.require(n, "id", path, "the member's id");
        m.id = r.to_name(id, "a member id");
        if (const std::string owner = body_id_owner(def, body_ids, m.id); !owner.empty())
          r.fail(id, "id '" + m.id + "' is already used by " + owner);

        const Field kind = r.require(n, "kind", path, "column, beam, brace or other");
        const std::string kind_text = r.to_text(kind);
        if (!parse_member_kind(kind_text, m.kind) || m.kind == MemberKind::Block || m.kind == MemberKind::Ground)
          r.fail(kind, "expected column, beam, brace or other, got " + describe(kind.value));

        const Field nodes = r.require(n, "nodes", path, "the two end nodes [a, b]");
        if (!nodes.value.IsSequence() || nodes.value.size() != 2)
          r.fail(nodes, "expected a list of two node ids [a, b], got " +
                            (nodes.value.IsSequence() ? "a list of " + std::to_string(nodes.value.size())
                                                      : describe(nodes.value)));
        int end_index[2] = {-1, -1};
        std::string* end_id[2] = {&m.node_a, &m.node_b};
        for (std::size_t k = 0; k < 2; ++k) {
          const Field e = Reader::item(nodes, k);
          *end_id[k] = r.to_name(e, "a node id");
          end_index[k] = node_ids.find(*end_id[k]);
          if (end_index[k] < 0) r.fail(e, reference_message("node", *end_id[k], def.nodes, &NodeDef::id, "nodes"));
        }
        if (m.node_a == m.node_b) r.fail(nodes, "a member needs two different nodes, got '" + m.node_a + "' twice");
        const double length_m =
            (def.nodes[std::size_t(end_index[1])].xyz_m - def.nodes[std::size_t(end_index[0])].xyz_m).norm();
        if (!(length_m > kMinMemberLength_m))
          r.fail(nodes, "nodes '" + m.node_a + "' and '" + m.node_b +
                            "' are at the same position, so the member would have no length");

        const Field section = r.require(n, "section", path, "the name of a section");
        m.section = r.to_name(section, "a section name");
        if (def.section_index(m.section) < 0)
          r.fail(section, reference_message("section", m.section, def.sections, &SectionDef::name, "sections"));
        const Field material = r.require(n, "material", path, "the name of a material");
        m.material = r.to_name(material, "a material name");
        if (def.material_index(m.material) < 0)
          r.fail(material, reference_message("material", m.material, def.materials, &MaterialDef::name, "materials"));

        m.roll_rad = r.optional_number(n, "roll_deg", path, 0.0) * kRadPerDeg;
        if (const auto trim = r.get(n, "trim_m", path)) {
          if (!trim->value.IsSequence() || trim->value.size() != 2)
            r.fail(*trim, "expected a list of two lengths >= 0 (m): [trim at node a, trim at node b]");
          m.trim_a_m = r.to_non_negative(Reader::item(*trim, 0));
          m.trim_b_m = r.to_non_negative(Reader::item(*trim, 1));
        }
        body_ids.members.add(m.id, static_cast<int>(def.members.size()));
        def.members.push_back(m);
      });
}

void parse_blocks(const Reader& r, const Field& f, CaseDef& def) {
  r.to_list(f, "blocks", false);
  BodyIds body_ids(def);
  for_each_item(
      r, f, "a block: id, size_m, center_m, material, ...",
      {"id", "kind", "size_m", "center_m", "rotation_deg", "material", "fixed", "velocity_mps",
       "angular_velocity_radps"},
      [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
        BlockDef b;
        b.line = line;
        const Field id = r.require(n, "id", path, "the block's id");
        b.id = r.to_name(id, "a block id");
        if (const std::string owner = body_id_owner(def, body_ids, b.id); !owner.empty())
          r.fail(id, "id '" + b.id + "' is already used by " + owner);
        if (const auto kind = r.get(n, "kind", path)) {
          if (!parse_member_kind(r.to_text(*kind), b.kind) || b.kind == MemberKind::Ground)
            r.fail(*kind, "expected block, column, beam, brace or other, got " + describe(kind->value));
        }
        const Field size = r.require(n, "size_m", path, "edge lengths along body x, y, z in m");
        b.size_m = r.to_vec3(size, "edge lengths along body x, y, z in m");
        for (std::size_t k = 0; k < 3; ++k)
          if (!(b.size_m[Eigen::Index(k)] > 0.0))
            r.fail(Reader::item(size, k), "expected a positive edge length in m, got " + describe(size.value[k]));
          else if (const std::string why = edge_out_of_range(b.size_m[Eigen::Index(k)]); !why.empty())
            r.fail(Reader::item(size, k), why);
        const Field centre = r.require(n, "center_m", path, "centre x, y, z in m");
        b.center_m = r.to_vec3(centre, "x, y, z in m");
        if (const std::string why = coordinate_out_of_range(b.center_m); !why.empty()) r.fail(centre, why);
        b.rotation_rad =
            r.optional_vec3(n, "rotation_deg", path, Vec3::Zero(), "angles about world x, then y, then z in degrees") *
            kRadPerDeg;
        const Field material = r.require(n, "material", path, "the name of a material");
        b.material = r.to_name(material, "a material name");
        if (def.material_index(b.material) < 0)
          r.fail(material, reference_message("material", b.material, def.materials, &MaterialDef::name, "materials"));
        b.fixed = r.optional_bool(n, "fixed", path, b.fixed);
        b.velocity_mps = r.optional_vec3(n, "velocity_mps", path, b.velocity_mps, "vx, vy, vz in m/s");
        b.angular_velocity_radps =
            r.optional_vec3(n, "angular_velocity_radps", path, b.angular_velocity_radps, "wx, wy, wz in rad/s");
        if (b.fixed && (b.velocity_mps.norm() > 0.0 || b.angular_velocity_radps.norm() > 0.0))
          r.fail(*r.get(n, b.velocity_mps.norm() > 0.0 ? "velocity_mps" : "angular_velocity_radps", path),
                 "a fixed block never moves, so it cannot have an initial velocity");
        body_ids.blocks.add(b.id, static_cast<int>(def.blocks.size()));
        def.blocks.push_back(b);
      });
}


// ---- joint types and joints ---------------------------------------------------

// One spring law with its dashpot (joints/spring_law.h). Keys depend on `law`.
SpringDef parse_spring(const Reader& r, const Field& f, const std::string& what) {
  r.expect_map(f.value, f.line, f.path, what + ": a mapping with law and its parameters");
  const Field law_field = r.require(f.value, "law", f.path, "linear, trilinear or curee");
  const std::string law = r.to_name(law_field, "a law name");
  const Keys common = {"law", "damping_ratio", "dashpot_N_s_per_m", "reference_length_m"};
  Keys params;
  SpringDef def;
  if (law == "linear") {
    params = {"stiffness_N_per_m"};
    def.law.kind = SpringLawKind::LinearElastic;
  } else if (law == "trilinear") {
    params = {"yield_strain_tension",        "yield_force_tension_N",        "ultimate_strain_tension",
              "ultimate_force_tension_N",    "yield_strain_compression",     "yield_force_compression_N",
              "ultimate_strain_compression", "ultimate_force_compression_N"};
    def.law.kind = SpringLawKind::Trilinear;
  } else if (law == "curee") {
    params = {"K0_N_per_m", "F0_N", "F1_N", "r1", "r2", "r3", "r4", "delta_u_m", "alpha", "beta"};
    def.law.kind = SpringLawKind::Curee;
  } else {
    r.fail(law_field, "expected a spring law: linear, trilinear or curee; got '" + law + "'");
  }
  Keys allowed = common;
  allowed.insert(allowed.end(), params.begin(), params.end());
  r.expect_keys(f.value, allowed, f.path);
  auto num = [&](std::string_view key) {
    return r.to_number(r.require(f.value, key, f.path, "a parameter of the " + law + " law"));
  };
  switch (def.law.kind) {
    case SpringLawKind::LinearElastic:
      def.law.linear.stiffness_Npm = r.required_positive(f.value, "stiffness_N_per_m", f.path, "k (N/m)");
      break;
    case SpringLawKind::Trilinear: {
      TrilinearParams& t = def.law.trilinear;
      t.yield_strain_tension = num("yield_strain_tension");
      t.yield_force_tension_N = num("yield_force_tension_N");
      t.ultimate_strain_tension = num("ultimate_strain_tension");
      t.ultimate_force_tension_N = num("ultimate_force_tension_N");
      t.yield_strain_compression = num("yield_strain_compression");
      t.yield_force_compression_N = num("yield_force_compression_N");
      t.ultimate_strain_compression = num("ultimate_strain_compression");
      t.ultimate_force_compression_N = num("ultimate_force_compression_N");
      break;
    }
    case SpringLawKind::Curee: {
      CureeParams& c = def.law.curee;
      c.K0_Npm = num("K0_N_per_m");
      c.F0_N = num("F0_N");
      c.F1_N = num("F1_N");
      c.r1 = num("r1");
      c.r2 = num("r2");
      c.r3 = num("r3");
      c.r4 = num("r4");
      c.delta_u_m = num("delta_u_m");
      c.alpha = num("alpha");
      c.beta = num("beta");
      break;
    }
    case SpringLawKind::Count: break;
  }
  if (def.law.kind == SpringLawKind::Trilinear)
    def.reference_length_m =
        r.required_positive(f.value, "reference_length_m", f.path, "length turning deformation into strain (m)");
  else
    def.reference_length_m = r.optional_positive(f.value, "reference_length_m", f.path, def.reference_length_m);
  def.dashpot.damping_ratio = r.optional_non_negative(f.value, "damping_ratio", f.path, 0.0);
  def.dashpot.coefficient_Nspm = r.optional_non_negative(f.value, "dashpot_N_s_per_m", f.path, 0.0);
  try {
    (void)initial_stiffness_Npm(def);
  } catch (const std::invalid_argument& e) {
    // The law names the parameter it refuses first ("trilinear spring:
    // ultimate_strain_tension must be > ..."): point at that key's line and
    // say the law's name once.
    std::string reason = e.what();
    if (const std::size_t colon = reason.find(": "); colon != std::string::npos && reason.compare(0, law.size(), law) == 0)
      reason = reason.substr(colon + 2);
    std::optional<Field> at;
    std::size_t first = std::string::npos;
    for (const Keys* keys : {static_cast<const Keys*>(&params), &common})
      for (const auto& key : *keys) {
        const std::size_t pos = reason.find(std::string(key));
        if (pos == std::string::npos || pos >= first) continue;
        if (const auto field = r.get(f.value, key, f.path)) {
          first = pos;
          at = *field;
        }
      }
    r.fail(at ? *at : f, std::string("invalid ") + law + " law parameters: " + reason);
  }
  return def;
}

JointBreakDef parse_fracture(const Reader& r, const Field& f) {
  r.expect_map(f.value, f.line, f.path, "criterion and, for strain_limit, strain_limit");
  r.expect_keys(f.value, {"criterion", "strain_limit"}, f.path);
  JointBreakDef b;
  // Without `criterion` the documented default (cases/README.md).
  b.criterion = BreakCriterion::AllNormalSpringsDeleted;
  if (const auto c = r.get(f.value, "criterion", f.path)) {
    const std::string name = r.to_name(*c, "a fracture criterion");
    bool found = false;
    for (BreakCriterion k : {BreakCriterion::AllNormalSpringsDeleted, BreakCriterion::AnySpringDeleted,
                             BreakCriterion::StrainLimit, BreakCriterion::Never})
      if (name == break_criterion_name(k)) {
        b.criterion = k;
        found = true;
      }
    if (!found)
      r.fail(*c, "expected all_normal_springs_deleted, any_spring_deleted, strain_limit or never; got '" + name + "'");
  }
  if (b.criterion == BreakCriterion::StrainLimit)
    b.strain_limit = r.required_positive(f.value, "strain_limit", f.path, "the joint strain at which it breaks (-)");
  else if (r.get(f.value, "strain_limit", f.path))
    r.fail(*r.get(f.value, "strain_limit", f.path), "strain_limit applies only to criterion strain_limit");
  return b;
}

void parse_joint_types(const Reader& r, const Field& f, CaseDef& def) {
  r.to_list(f, "joint types", false);
  const Keys allowed = {"name",     "layout",   "corner_fraction", "normal",     "shear",           "side_m",
                        "gap_m",    "axial",    "diagonal",        "shear_link", "fracture"};
  for_each_item(r, f, "a joint type", allowed, [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
    JointTypeDef t;
    t.line = line;
    const Field name = r.require(n, "name", path, "the joint type's name");
    t.name = r.to_name(name, "a joint type name");
    if (const int other = def.joint_type_index(t.name); other >= 0)
      r.fail(name, "joint type '" + t.name + "' is already defined on line " +
                       std::to_string(def.joint_types[std::size_t(other)].line));
    const Field layout = r.require(n, "layout", path, "single_point, four_corner or link_system");
    const std::string l = r.to_name(layout, "a layout name");
    if (l == "single_point") t.layout = JointLayoutKind::SinglePoint;
    else if (l == "four_corner") t.layout = JointLayoutKind::FourCorner;
    else if (l == "link_system") t.layout = JointLayoutKind::LinkSystem;
    else r.fail(layout, "expected single_point, four_corner or link_system; got '" + l + "'");
    auto refuse = [&](std::string_view key, const char* why) {
      if (const auto k = r.get(n, key, path)) r.fail(*k, std::string(key) + " " + why);
    };
    if (t.layout == JointLayoutKind::LinkSystem) {
      refuse("normal", "belongs to point layouts (single_point, four_corner), not link_system");
      refuse("shear", "belongs to point layouts (single_point, four_corner), not link_system");
      refuse("corner_fraction", "belongs to four_corner");
      t.gap_m = r.required_positive(n, "gap_m", path, "distance l between the two link planes (m)");
      t.side_m = r.optional_positive(n, "side_m", path, 0.0);
      t.axial = parse_spring(r, r.require(n, "axial", path, "the axial links' law"), "axial links");
      t.diagonal = parse_spring(r, r.require(n, "diagonal", path, "the diagonal links' law"), "diagonal links");
      if (const auto sl = r.get(n, "shear_link", path)) {
        t.shear_link = parse_spring(r, *sl, "shear links");
        t.with_shear_links = true;
      }
    } else {
      refuse("gap_m", "belongs to link_system");
      refuse("side_m", "belongs to link_system");
      refuse("axial", "belongs to link_system");
      refuse("diagonal", "belongs to link_system");
      refuse("shear_link", "belongs to link_system");
      if (t.layout == JointLayoutKind::SinglePoint) refuse("corner_fraction", "belongs to four_corner");
      t.corner_fraction = r.optional_positive(n, "corner_fraction", path, 1.0);
      t.normal = parse_spring(r, r.require(n, "normal", path, "the normal springs' law"), "normal springs");
      if (const auto sh = r.get(n, "shear", path))
        t.shear = parse_spring(r, *sh, "shear springs");
      else
        t.has_shear = false;
    }
    if (const auto fr = r.get(n, "fracture", path)) t.fracture = parse_fracture(r, *fr);
    def.joint_types.push_back(t);
  });
}

std::string joint_type_reference(const Reader& r, const Field& f, const CaseDef& def) {
  const std::string type = r.to_name(f, "a joint type name");
  if (def.joint_type_index(type) < 0) {
    std::vector<std::string> names;
    for (const JointTypeDef& t : def.joint_types) names.push_back(t.name);
    r.fail(f, "unknown joint type '" + type + "'; defined joint types: " +
                  (names.empty() ? std::string("none (add a joint_types section)") : list_of_names(names)));
  }
  return type;
}

MemberKind parse_kind_name(const Reader& r, const Field& f) {
  MemberKind k;
  const std::string name = r.to_name(f, "a member kind");
  if (!parse_member_kind(name, k) || k == MemberKind::Ground)
    r.fail(f, "expected a member kind (column, beam, brace, block, other); got '" + name + "'");
  return k;
}

void parse_joints(const Reader& r, const Field& f, CaseDef& def) {
  r.expect_map(f.value, f.line, f.path, "automatic, hub_kind, default_type, support_type, rules, overrides");
  r.expect_keys(f.value, {"automatic", "hub_kind", "default_type", "support_type", "rules", "overrides"}, f.path);
  JointsDef& j = def.joints;
  j.line = f.line;
  j.automatic = r.optional_bool(f.value, "automatic", f.path, true);
  if (const auto h = r.get(f.value, "hub_kind", f.path)) j.hub_kind = parse_kind_name(r, *h);
  if (const auto d = r.get(f.value, "default_type", f.path)) j.default_type = joint_type_reference(r, *d, def);
  if (const auto d = r.get(f.value, "support_type", f.path)) j.support_type = joint_type_reference(r, *d, def);
  if (const auto rules = r.get(f.value, "rules", f.path)) {
    r.to_list(*rules, "rules", false);
    for_each_item(r, *rules, "a rule: kinds, type", {"kinds", "type"},
                  [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
                    JointRuleDef rule;
                    rule.line = line;
                    const Field kinds = r.require(n, "kinds", path, "two member kinds, e.g. [beam, column]");
                    if (!kinds.value.IsSequence() || kinds.value.size() != 2)
                      r.fail(kinds, "expected a list of two member kinds, e.g. [beam, column]");
                    rule.kind_1 = parse_kind_name(r, Reader::item(kinds, 0));
                    rule.kind_2 = parse_kind_name(r, Reader::item(kinds, 1));
                    rule.type = joint_type_reference(r, r.require(n, "type", path, "a joint type name"), def);
                    // One rule per pair of kinds (in either order): a second
                    // would silently replace the first.
                    for (const JointRuleDef& q : j.rules)
                      if ((q.kind_1 == rule.kind_1 && q.kind_2 == rule.kind_2) ||
                          (q.kind_1 == rule.kind_2 && q.kind_2 == rule.kind_1))
                        r.fail(kinds, "a rule for these two kinds is already given at line " + std::to_string(q.line));
                    j.rules.push_back(rule);
                  });
  }
  if (const auto overrides = r.get(f.value, "overrides", f.path)) {
    r.to_list(*overrides, "overrides", false);
    const NameIndex node_ids(def.nodes, &NodeDef::id);
    const NameIndex member_ids(def.members, &MemberDef::id);
    for_each_item(
        r, *overrides, "an override: node, members, type", {"node", "members", "type"},
        [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
          JointOverrideDef o;
          o.line = line;
          const Field node = r.require(n, "node", path, "the node where the two members meet");
          o.node = r.to_name(node, "a node id");
          if (node_ids.find(o.node) < 0)
            r.fail(node, reference_message("node", o.node, def.nodes, &NodeDef::id, "nodes"));
          const Field members = r.require(n, "members", path, "the two member ids");
          if (!members.value.IsSequence() || members.value.size() != 2)
            r.fail(members, "expected a list of two member ids");
          for (std::size_t i = 0; i < 2; ++i) {
            const Field m = Reader::item(members, i);
            const std::string id = r.to_name(m, "a member id");
            const int k = member_ids.find(id);
            // The ground is no member: a support's joint type is the
            // support's own (info --joints names such a joint
            // 'node:ground-member', so a user tried it here; house probe).
            if (k < 0 && id == "ground")
              r.fail(m, "'ground' is not a member: the joint of a supported member and the ground takes its type "
                        "from the support (supports[i].joint_type, else joints.support_type)");
            if (k < 0) r.fail(m, "unknown member '" + id + "'");
            const auto it = def.members.begin() + k;
            if (it->node_a != o.node && it->node_b != o.node)
              r.fail(m, "member '" + id + "' does not end at node '" + o.node + "'");
            (i == 0 ? o.member_1 : o.member_2) = id;
          }
          if (o.member_1 == o.member_2) r.fail(members, "the two members must differ");
          o.type = joint_type_reference(r, r.require(n, "type", path, "a joint type name"), def);
          for (const JointOverrideDef& q : j.overrides)
            if (q.node == o.node && ((q.member_1 == o.member_1 && q.member_2 == o.member_2) ||
                                     (q.member_1 == o.member_2 && q.member_2 == o.member_1)))
              r.fail(members, "an override for these two members at node '" + o.node + "' is already given at line " +
                                  std::to_string(q.line));
          j.overrides.push_back(o);
        });
  }
}


// ---- contacts ----------------------------------------------------------------

ContactParams parse_contact_params(const Reader& r, const Field& f, const std::string& what) {
  r.expect_map(f.value, f.line, f.path, what);
  r.expect_keys(f.value,
                {"normal_stiffness_N_per_m", "restitution", "tangential_stiffness_N_per_m", "friction_coefficient"},
                f.path);
  ContactParams p;
  p.normal_stiffness_N_per_m = r.optional_positive(f.value, "normal_stiffness_N_per_m", f.path, p.normal_stiffness_N_per_m);
  p.restitution = r.optional_positive(f.value, "restitution", f.path, p.restitution);
  if (p.restitution > 1.0)
    if (const auto e = r.get(f.value, "restitution", f.path))
      r.fail(*e, "expected a restitution in (0, 1] (1: no loss at impact), got " + fmt(p.restitution));
  p.tangential_stiffness_N_per_m =
      r.optional_non_negative(f.value, "tangential_stiffness_N_per_m", f.path, p.tangential_stiffness_N_per_m);
  p.friction_coefficient = r.optional_non_negative(f.value, "friction_coefficient", f.path, p.friction_coefficient);
  try {
    (void)make_contact_coefficients(p, f.path.c_str());
  } catch (const std::invalid_argument& e) {
    r.fail(f, std::string("invalid contact parameters: ") + e.what());
  }
  return p;
}

void parse_contact(const Reader& r, const Field& f, CaseDef& def) {
  r.expect_map(f.value, f.line, f.path, "ground, default, pairs, intact_nodes");
  r.expect_keys(f.value, {"ground", "default", "pairs", "intact_nodes"}, f.path);
  ContactDef c;
  c.line = f.line;
  if (const auto m = r.get(f.value, "intact_nodes", f.path)) {
    if (!parse_intact_node_contact(r.to_text(*m), c.intact_nodes))
      r.fail(*m, "expected one of touch, ground_only, none (contacts across joints that still hold), got " +
                     describe(m->value));
  }
  if (const auto g = r.get(f.value, "ground", f.path)) c.ground = parse_contact_params(r, *g, "ground contact parameters");
  if (const auto d = r.get(f.value, "default", f.path))
    c.default_pair = parse_contact_params(r, *d, "default contact parameters");
  if (const auto pairs = r.get(f.value, "pairs", f.path)) {
    r.to_list(*pairs, "material pairs", false);
    const Keys keys = {"materials", "normal_stiffness_N_per_m", "restitution", "tangential_stiffness_N_per_m",
                       "friction_coefficient"};
    for_each_item(r, *pairs, "a material pair", keys,
                  [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
                    ContactPairDef p;
                    p.line = line;
                    const Field mats = r.require(n, "materials", path, "two material names");
                    if (!mats.value.IsSequence() || mats.value.size() != 2)
                      r.fail(mats, "expected a list of two material names");
                    for (std::size_t i = 0; i < 2; ++i) {
                      const Field m = Reader::item(mats, i);
                      const std::string name = r.to_name(m, "a material name");
                      if (def.material_index(name) < 0)
                        r.fail(m, reference_message("material", name, def.materials, &MaterialDef::name,
                                                    "materials"));
                      (i == 0 ? p.material_1 : p.material_2) = name;
                    }
                    // The pair's own keys are parameters; `materials` is not.
                    YAML::Node params(YAML::NodeType::Map);
                    for (auto it = n.begin(); it != n.end(); ++it)
                      if (it->first.Scalar() != "materials") params[it->first] = it->second;
                    p.params = parse_contact_params(r, Field{params, line, path}, "contact parameters");
                    // One entry per pair (in either order): a second would
                    // silently replace the first.
                    for (const ContactPairDef& q : c.pairs)
                      if ((q.material_1 == p.material_1 && q.material_2 == p.material_2) ||
                          (q.material_1 == p.material_2 && q.material_2 == p.material_1))
                        r.fail(mats, "the pair (" + p.material_1 + ", " + p.material_2 +
                                         ") is already given at line " + std::to_string(q.line));
                    c.pairs.push_back(p);
                  });
  }
  def.contact = c;
}

void parse_supports(const Reader& r, const Field& f, CaseDef& def) {
  r.to_list(f, "supports", false);
  // Indexed: a support is checked against every node, member and support.
  const NameIndex node_ids(def.nodes, &NodeDef::id);
  NameIndex supported(def.supports, &SupportDef::node);
  std::unordered_set<std::string_view> member_ends;
  for (const MemberDef& m : def.members) {
    member_ends.insert(m.node_a);
    member_ends.insert(m.node_b);
  }
  for_each_item(
      r, f, "a support: node, joint_type", {"node", "joint_type"},
      [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
        SupportDef s;
        s.line = line;
        if (const auto jt = r.get(n, "joint_type", path)) s.joint_type = joint_type_reference(r, *jt, def);
        const Field node = r.require(n, "node", path, "the id of the supported node");
        s.node = r.to_name(node, "a node id");
        if (node_ids.find(s.node) < 0)
          r.fail(node, reference_message("node", s.node, def.nodes, &NodeDef::id, "nodes"));
        if (const int i = supported.find(s.node); i >= 0)
          r.fail(node, "node '" + s.node + "' is already supported by supports[" + std::to_string(i) + "] (line " +
                           std::to_string(def.supports[std::size_t(i)].line) + ")");
        if (!member_ends.count(s.node))
          r.fail(node, "node '" + s.node + "' is not an end of any member, so a support there would hold nothing");
        supported.add(s.node, static_cast<int>(def.supports.size()));
        def.supports.push_back(s);
      });
}

void parse_ground(const Reader& r, const Field& f, CaseDef& def) {
  r.expect_map(f.value, f.line, f.path, "level_m");
  r.expect_keys(f.value, {"level_m"}, f.path);
  GroundDef g;
  g.level_m = r.optional_number(f.value, "level_m", f.path, g.level_m);
  if (const auto level = r.get(f.value, "level_m", f.path); level && std::abs(g.level_m) > kMaxCoordinate_m) {
    std::ostringstream why;
    why << "ground level " << g.level_m << " m lies more than " << kMaxCoordinate_m
        << " m from the origin, as no node may: place the structure and its ground near the origin (a typing error "
           "or a unit off by powers of ten?)";
    r.fail(*level, why.str());
  }
  def.ground = g;
}

void parse_assessment(const Reader& r, const Field& f, CaseDef& def) {
  r.expect_map(f.value, f.line, f.path, "safety_drift_ratio_rad and collapse_drift_ratio_rad");
  r.expect_keys(f.value, {"safety_drift_ratio_rad", "collapse_drift_ratio_rad"}, f.path);
  AssessmentDef& a = def.assessment;
  a.safety_drift_ratio_rad = r.optional_positive(f.value, "safety_drift_ratio_rad", f.path, a.safety_drift_ratio_rad);
  a.collapse_drift_ratio_rad =
      r.optional_positive(f.value, "collapse_drift_ratio_rad", f.path, a.collapse_drift_ratio_rad);
  if (a.collapse_drift_ratio_rad <= a.safety_drift_ratio_rad)
    r.fail(f, "collapse_drift_ratio_rad (" + fmt(a.collapse_drift_ratio_rad) +
                        ") must be larger than safety_drift_ratio_rad (" + fmt(a.safety_drift_ratio_rad) + ")");
}

// Direction of a component: a signed axis name or a non-zero 3-vector.
Vec3 parse_axis(const Reader& r, const Field& f) {
  if (f.value.IsScalar()) {
    static const struct {
      const char* name;
      Vec3 direction;
    } axes[] = {{"x", Vec3::UnitX()}, {"+x", Vec3::UnitX()}, {"-x", -Vec3::UnitX()},
                {"y", Vec3::UnitY()}, {"+y", Vec3::UnitY()}, {"-y", -Vec3::UnitY()},
                {"z", Vec3::UnitZ()}, {"+z", Vec3::UnitZ()}, {"-z", -Vec3::UnitZ()}};
    for (const auto& a : axes)
      if (f.value.Scalar() == a.name) return a.direction;
    r.fail(f, "expected x, y, z, -x, -y, -z or a direction [dx, dy, dz], got " + describe(f.value));
  }
  if (!f.value.IsSequence())
    r.fail(f, "expected x, y, z, -x, -y, -z or a direction [dx, dy, dz], got " + describe(f.value));
  const Vec3 d = r.to_vec3(f, "a direction dx, dy, dz");
  if (!(d.norm() > 0.0)) r.fail(f, "expected a non-zero direction vector");
  return d.normalized();
}

void parse_ground_motion(const Reader& r, const Field& f, CaseDef& def) {
  const std::string& p = f.path;
  r.expect_map(f.value, f.line, p, "time_scale, window_start_s, window_length_s, components");
  r.expect_keys(f.value, {"time_scale", "window_start_s", "window_length_s", "components"}, p);
  GroundMotionDef gm;
  gm.time_scale = r.optional_positive(f.value, "time_scale", p, gm.time_scale);
  const auto start_field = r.get(f.value, "window_start_s", p);
  gm.window_start_s = start_field ? r.to_non_negative(*start_field) : gm.window_start_s;
  if (start_field) def.section_line["ground_motion.window_start_s"] = start_field->line;
  const auto length_field = r.get(f.value, "window_length_s", p);
  gm.window_length_s = length_field ? r.to_positive(*length_field) : gm.window_length_s;
  if (length_field) def.section_line["ground_motion.window_length_s"] = length_field->line;

  const Field comps = r.require(f.value, "components", p, "a list of records with file, format, axis");
  r.to_list(comps, "ground-motion components", true);
  const std::filesystem::path case_folder = def.source_file.parent_path();
  for_each_item(
      r, comps, "a component: file, format, axis, unit, amplitude_scale",
      {"file", "format", "unit", "axis", "amplitude_scale"},
      [&](const YAML::Node& n, const std::string& path, int line, std::size_t) {
        GroundMotionComponentDef c;
        c.line = line;
        const Field file = r.require(n, "file", path, "path of the record, relative to the case file's folder");
        c.file = r.to_text(file);
        if (c.file.empty()) r.fail(file, "expected a file path, got an empty text");
        c.resolved_file = resolve_record_path(case_folder, c.file);
        if (const std::string why = why_not_a_readable_file(c.resolved_file); !why.empty())
          r.fail(file, "record file " + why + ": " + c.resolved_file.string());

        const Field format = r.require(n, "format", path, "peer_at2 or two_column");
        if (!parse_record_format(r.to_text(format), c.format))
          r.fail(format, "expected peer_at2 or two_column, got " + describe(format.value));
        if (const auto unit = r.get(n, "unit", path)) {
          if (c.format != RecordFormat::TwoColumn)
            r.fail(*unit, "'unit' applies to two_column records only (a PEER .AT2 file is in g by definition)");
          if (!parse_acceleration_unit(r.to_text(*unit), c.unit))
            r.fail(*unit, "expected g, m/s2 or cm/s2, got " + describe(unit->value));
        }
        c.direction = parse_axis(r, r.require(n, "axis", path, "x, y, z, -x, -y, -z or [dx, dy, dz]"));
        c.amplitude_scale = r.optional_positive(n, "amplitude_scale", path, c.amplitude_scale);

        // Read now: a bad record fails with its own file, line and field.
        c.record = read_accelerogram(c.resolved_file, c.format, c.unit);
        if (const std::string why = scaled_record_problem(c.record, c.amplitude_scale); !why.empty())
          r.fail(r.get(n, "amplitude_scale", path).value_or(file), why);
        const double record_end_s = c.record.duration_s();
        // Record time counts from the first sample; a file whose times start
        // elsewhere is told in its own times too (a probe's file ending at
        // 1.5 s read "ends at 1 s").
        const double file_start_s = c.record.file_start_time_s;
        const std::string in_file =
            file_start_s == 0.0 ? std::string()
                                : "; record time counts from the record's first sample, t = " + fmt(file_start_s) +
                                      " s in the file, so its end is at t = " + fmt(file_start_s + record_end_s) +
                                      " s in the file";
        // Within half a sample of the end counts as at the end: the window
        // would hold no sample interval (a start written as the record's
        // last time, N*DT, lands just before or after the end).
        // Further beyond it is simply after the end (a window_start_s of 60 s
        // on a 53.71 s record read "within half a sample of the end").
        if (gm.window_start_s > record_end_s + 0.5 * c.record.dt_s)
          r.fail(start_field ? *start_field : file, "the window starts at " + fmt(gm.window_start_s) +
                                                        " s, after the end of record " + c.resolved_file.string() +
                                                        " (which ends at " + fmt(record_end_s) + " s" + in_file + ")");
        if (gm.window_start_s >= record_end_s - 0.5 * c.record.dt_s)
          r.fail(start_field ? *start_field : file, "the window starts at " + fmt(gm.window_start_s) +
                                                        " s, at or within half a sample (" +
                                                        fmt(0.5 * c.record.dt_s) + " s) of the end of record " +
                                                        c.resolved_file.string() + " (" + fmt(record_end_s) + " s" +
                                                        in_file + ")");
        // Half a sample of slack: a window written as N*DT must not be
        // refused over the rounding of DT.
        if (length_field && gm.window_start_s + gm.window_length_s > record_end_s + 0.5 * c.record.dt_s)
          r.fail(*length_field, "the window (" + fmt(gm.window_start_s) + " s + " + fmt(gm.window_length_s) +
                                    " s) runs past the end of record " + c.resolved_file.string() + " (" +
                                    fmt(record_end_s) + " s" + in_file +
                                    "); leave window_length_s out to use the record to its end");
        gm.components.push_back(std::move(c));
      });
  def.ground_motion = std::move(gm);
}

void parse_output(const Reader& r, const Field& f, CaseDef& def) {
  r.expect_map(f.value, f.line, f.path, "folder, frame_interval_s, history_interval_s, vtk_binary");
  r.expect_keys(f.value, {"folder", "frame_interval_s", "history_interval_s", "vtk_binary"}, f.path);
  if (const auto folder = r.get(f.value, "folder", f.path)) {
    def.output.folder = r.to_text(*folder);
    if (def.output.folder.empty()) r.fail(*folder, "expected a folder path, got an empty text");
  }
  def.output.frame_interval_s = r.optional_positive(f.value, "frame_interval_s", f.path, def.output.frame_interval_s);
  def.output.history_interval_s =
      r.optional_positive(f.value, "history_interval_s", f.path, def.output.history_interval_s);
  def.output.vtk_binary = r.optional_bool(f.value, "vtk_binary", f.path, def.output.vtk_binary);
}

struct SectionEntry {
  std::string_view key;
  bool required;
  const char* what;  // for "missing required key" messages
  void (*parse)(const Reader&, const Field&, CaseDef&);
};

// Parse order = table order (definitions before the sections that refer to
// them). To add a section: write its parse function and add a row.
const SectionEntry kSections[] = {
    {"framequake_case", true, "the schema version, 1", parse_version},
    {"name", false, "", parse_name},
    {"description", false, "", parse_description},
    {"time", true, "a mapping with dt_s and duration_s", parse_time},
    {"materials", true, "a list of materials with name and density_kg_per_m3", parse_materials},
    {"sections", false, "", parse_sections},
    {"nodes", false, "", parse_nodes},
    {"members", false, "", parse_members},
    {"blocks", false, "", parse_blocks},
    {"joint_types", false, "", parse_joint_types},
    {"joints", false, "", parse_joints},
    {"supports", false, "", parse_supports},
    {"contact", false, "", parse_contact},
    {"ground", false, "", parse_ground},
    {"ground_motion", false, "", parse_ground_motion},
    {"output", false, "", parse_output},
    {"assessment", false, "", parse_assessment},
};

CaseDef parse_root(const Reader& r, const YAML::Node& root, const std::filesystem::path& file) {
  Keys keys;
  for (const SectionEntry& s : kSections) keys.push_back(s.key);
  r.expect_map(root, Reader::line_of(root) ? Reader::line_of(root) : 1, "",
               "case keys such as framequake_case, time, materials");
  // The version comes first: keys of a newer schema would otherwise be
  // reported as unknown instead of the version being named as the problem.
  if (const auto v = r.get(root, "framequake_case", "")) {
    CaseDef scratch;
    parse_version(r, *v, scratch);
  }
  r.expect_keys(root, keys, "");

  CaseDef def;
  def.source_file = file;
  for (auto it = root.begin(); it != root.end(); ++it)
    def.section_line[it->first.Scalar()] = Reader::line_of(it->first);
  for (const SectionEntry& s : kSections) {
    if (const auto f = r.get(root, s.key, ""))
      s.parse(r, *f, def);
    else if (s.required)
      r.fail(Reader::line_of(root), std::string(s.key),
             "missing required key '" + std::string(s.key) + "' (" + s.what + ")");
  }

  // Checks across sections.
  if (def.name.empty()) {
    // The file's stem, with every character a name may not hold (they end
    // up in folder names) replaced by '_': "my case.yaml" is my_case.
    def.name = file.stem().string();
    for (char& c : def.name)
      if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
            c == '.'))
        c = '_';
    if (def.name.empty()) def.name = "case";
  }
  if (def.output.folder.empty()) def.output.folder = default_output_folder(def.name);
  if (def.members.empty() && def.blocks.empty())
    r.fail(Reader::line_of(root), "", "the case has no bodies: expected at least one member or block");
  if (!def.time.duration_s && !def.ground_motion)
    r.fail(def.section_line.at("time"), "time.duration_s",
           "missing required key 'duration_s' (required when there is no ground_motion section)");
  return def;
}

namespace {

// The innermost '{' or '[' still open at byte `until` of a YAML text, with
// its line and column (1-based), skipping quoted strings and comments; none
// when every bracket before `until` is closed.
struct OpenBracket {
  char bracket;
  int line;
  int column;
};
std::optional<OpenBracket> unclosed_flow_bracket(const std::string& text, int until) {
  std::vector<OpenBracket> open;
  int line = 1, column = 0;
  char quote = 0;
  bool comment = false;
  const std::size_t end = until >= 0 ? std::min(text.size(), std::size_t(until)) : text.size();
  for (std::size_t i = 0; i < end; ++i) {
    const char ch = text[i];
    ++column;
    if (ch == '\n') {
      ++line;
      column = 0;
      comment = false;
      continue;
    }
    if (comment) continue;
    if (quote) {
      if (ch == quote) quote = 0;
      continue;
    }
    if (ch == '\'' || ch == '"') {
      quote = ch;
    } else if (ch == '#' && (i == 0 || text[i - 1] == ' ' || text[i - 1] == '\t')) {
      comment = true;
    } else if (ch == '{' || ch == '[') {
      open.push_back({ch, line, column});
    } else if ((ch == '}' || ch == ']') && !open.empty()) {
      open.pop_back();
    }
  }
  if (open.empty()) return std::nullopt;
  return open.back();
}

}  // namespace

}  // namespace

namespace {

// Counts the documents of a YAML stream from the parser's events, without
// building nodes. yaml-cpp 0.7's LoadAll never ends on some malformed input
// (a stray ',' at the top level: the parser returns the same empty document
// again and again without consuming the token, so LoadAll allocates until
// memory runs out; found by fuzz_case_file). Each real document consumes
// text, so a document starting where the previous one started means the
// parser is stuck there.
class DocumentScan : public YAML::EventHandler {
 public:
  struct Doc {
    int start_pos = -1;
    YAML::Mark start;
    int first_node_line = -1;  // 0-based line of the document's first node
  };
  std::vector<Doc> docs;
  void OnDocumentStart(const YAML::Mark& m) override { docs.push_back({m.pos, m, -1}); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& m, YAML::anchor_t) override { node(m); }
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { node(m); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string&) override { node(m); }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(m);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    node(m);
  }
  void OnMapEnd() override {}

 private:
  void node(const YAML::Mark& m) {
    if (!docs.empty() && docs.back().first_node_line < 0) docs.back().first_node_line = m.line;
  }
};

}  // namespace

// Declared in case_def.h; defined here, with the reader that checks it
// first (the fuzzers link the reader without the model builder).
std::string density_out_of_range(double density_kg_per_m3) {
  if (density_kg_per_m3 >= kMinDensity_kg_per_m3 && density_kg_per_m3 <= kMaxDensity_kg_per_m3) return "";
  std::ostringstream why;
  why << "density " << density_kg_per_m3 << " kg/m^3 is outside " << kMinDensity_kg_per_m3 << " to "
      << kMaxDensity_kg_per_m3
      << " kg/m^3 (the lightest solids, aerogels, weigh about 1 kg/m^3 and the densest, osmium, 22 600; "
         "wood 300-900): a typing error or a unit off by powers of ten";
  return why.str();
}

std::string edge_out_of_range(double edge_m) {
  if (edge_m >= kMinEdge_m && edge_m <= kMaxEdge_m) return "";
  std::ostringstream why;
  why << "edge length " << edge_m << " m is outside " << kMinEdge_m << " to " << kMaxEdge_m
      << " m (a micrometre to 100 km): a typing error or a unit off by powers of ten";
  return why.str();
}

std::string coordinate_out_of_range(const Vec3& xyz_m) {
  if (xyz_m.cwiseAbs().maxCoeff() <= kMaxCoordinate_m) return "";
  std::ostringstream why;
  why << "position (" << xyz_m.x() << ", " << xyz_m.y() << ", " << xyz_m.z() << ") m lies more than "
      << kMaxCoordinate_m
      << " m from the origin: coordinates that large lose the resolution a time step's motion needs; "
         "place the structure near the origin (a typing error or a unit off by powers of ten?)";
  return why.str();
}

namespace {

// The first control character in `text` that YAML allows no raw byte of
// (all of C0 but tab, LF and CR, and DEL: the check of load_case_file), or
// -1 when there is none.
int first_control_character(std::string_view text) {
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7f) return c;
  }
  return -1;
}

std::string control_hex(int c) {
  static const char* const kHex = "0123456789ABCDEF";
  return std::string("0x") + kHex[c >> 4] + kHex[c & 15];
}

// The same control characters written as YAML escapes in a quoted scalar
// ("\e", "\0", "\x7f", "\u001b"): the raw bytes are refused before parsing,
// and these reached the terminal just the same (`info` printed a
// description's ESC, NUL and DEL bytes; a probe). Refused in every key and
// value, with the scalar's line and field. `walked`: the positions of the
// lists and mappings already walked, so that aliases of one node (`*a`) are
// walked once: a "billion laughs" file of nested aliases would otherwise
// take exponential time here.
void refuse_escaped_control_characters(const std::string& file, const YAML::Node& node, const std::string& path,
                                       std::unordered_set<int>& walked) {
  const auto check = [&](const YAML::Node& n, const std::string& where) {
    if (!n.IsScalar()) return;
    const int c = first_control_character(n.Scalar());
    if (c < 0) return;
    throw InputError(file, Reader::line_of(n), where,
                     "control character " + control_hex(c) +
                         " (a YAML escape such as \\e, \\0 or \\x7f) in the text; expected printable text "
                         "(tab and line breaks allowed)");
  };
  if (node.IsScalar()) {
    check(node, path);
    return;
  }
  if (node.Mark().pos >= 0 && !walked.insert(node.Mark().pos).second) return;
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      refuse_escaped_control_characters(file, node[i], index_path(path, i), walked);
  } else if (node.IsMap()) {
    for (auto it = node.begin(); it != node.end(); ++it) {
      const YAML::Node key = it->first;  // copies: see expect_keys
      const YAML::Node value = it->second;
      check(key, path);
      refuse_escaped_control_characters(file, value, key.IsScalar() ? join(path, key.Scalar()) : path, walked);
    }
  }
}

}  // namespace

CaseDef load_case_file(const std::filesystem::path& file) {
  const std::string name = file.string();
  if (const std::string why = why_not_a_readable_file(file); !why.empty())
    throw InputError(name, 0, "", "case file " + why);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(name, 0, "", "cannot open the case file for reading");
  std::stringstream buffer;
  buffer << in.rdbuf();

  const std::string text = buffer.str();
  // A text editor's "Unicode" is UTF-16: every other byte of ASCII text is
  // 0x00, which the check below would call a binary file (error probe).
  // Known by its byte-order mark, or by a NUL beside the first character.
  const auto byte = [&](std::size_t i) { return i < text.size() ? static_cast<unsigned char>(text[i]) : 0x100u; };
  if ((byte(0) == 0xFF && byte(1) == 0xFE) || (byte(0) == 0xFE && byte(1) == 0xFF) ||
      (text.size() >= 2 && ((byte(0) == 0 && byte(1) != 0) || (byte(0) != 0 && byte(1) == 0))))
    throw InputError(name, 0, "",
                     "the case file is UTF-16 text (a byte-order mark or a 0x00 byte beside each character); "
                     "expected UTF-8: save it as UTF-8 (or plain ASCII) text");
  // YAML allows no control characters but tab, LF and CR (YAML 1.2, 5.1
  // c-printable); they mean a binary or corrupted file. Refused here with
  // their position, before yaml-cpp would echo the raw byte in its message.
  std::size_t line_no = 1;
  for (const char& ch : text) {
    if (ch == '\n') ++line_no;
    if (const int c = first_control_character(std::string_view(&ch, 1)); c >= 0)
      throw InputError(name, int(line_no), "",
                       "control byte " + control_hex(c) +
                           " in the text; expected a YAML text file (is this a binary file?)");
  }

  const Reader r(name);
  YAML::Node root;
  try {
    std::istringstream stream(text);
    YAML::Parser parser(stream);
    DocumentScan scan;
    while (parser.HandleNextDocument(scan)) {
      const auto& d = scan.docs;
      if (d.size() >= 2 && d[d.size() - 1].start_pos == d[d.size() - 2].start_pos) {
        const YAML::Mark& m = d.back().start;
        const std::size_t pos = std::size_t(m.pos);
        const std::string shown = pos < text.size() ? "'" + text.substr(pos, 1) + "'" : "the end of the file";
        throw InputError(name, m.line + 1, "",
                         "YAML syntax error: unexpected " + shown + " at column " + std::to_string(m.column + 1) +
                             "; expected a mapping of keys such as 'framequake_case: 1'");
      }
    }
    if (scan.docs.size() > 1) {
      const DocumentScan::Doc& second = scan.docs[1];
      const int line = (second.first_node_line >= 0 ? second.first_node_line : second.start.line) + 1;
      throw InputError(name, line, "",
                       "expected one YAML document, found " + std::to_string(scan.docs.size()) +
                           " (remove the '---' separators)");
    }
    if (!scan.docs.empty()) root = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    // yaml-cpp's depth guard says only "bad file" (CLI probe).
    throw InputError(name, e.mark.line >= 0 ? e.mark.line + 1 : 0, "",
                     "YAML syntax error: brackets or indentation nested " + std::to_string(e.depth()) +
                         " levels deep, past what the YAML reader accepts; a case file needs a handful");
  } catch (const YAML::Exception& e) {
    // yaml-cpp reports an unclosed '{' or '[' where it gave up, often a line
    // or more after the bracket: name the bracket's own line.
    if (e.msg.find("end of map flow not found") != std::string::npos ||
        e.msg.find("end of sequence flow not found") != std::string::npos) {
      if (const auto open = unclosed_flow_bracket(text, e.mark.pos)) {
        throw InputError(name, open->line, "",
                         std::string("YAML syntax error: the '") + open->bracket + "' at column " +
                             std::to_string(open->column) + " is not closed (expected '" +
                             (open->bracket == '{' ? '}' : ']') + "' before line " + std::to_string(e.mark.line + 1) +
                             ")");
      }
    }
    // A tab in the indentation (YAML indents with spaces only) gives
    // yaml-cpp's "illegal map value" or the like, which does not say so.
    if (e.mark.line >= 0) {
      std::size_t begin = 0;
      for (int line = 0; line <= e.mark.line && begin != std::string::npos; ++line) {
        const std::size_t end = text.find('\n', begin);
        const std::string_view row(text.data() + begin, (end == std::string::npos ? text.size() : end) - begin);
        const std::size_t first = row.find_first_not_of(" \t");
        const std::string_view indent = row.substr(0, first == std::string_view::npos ? row.size() : first);
        if (line >= e.mark.line - 1 && indent.find('\t') != std::string_view::npos)
          throw InputError(name, line + 1, "",
                           "YAML syntax error: " + e.msg +
                               "; this line is indented with a tab character, and YAML indents with spaces only");
        begin = end == std::string::npos ? end : end + 1;
      }
    }
    throw InputError(name, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", "YAML syntax error: " + e.msg);
  }
  if (!root.IsDefined() || root.IsNull())
    throw InputError(name, 0, "", "the file is empty; expected a mapping starting with 'framequake_case: 1'");
  std::unordered_set<int> walked;
  refuse_escaped_control_characters(name, root, "", walked);
  try {
    return parse_root(r, root, file);
  } catch (const YAML::Exception& e) {
    // Not expected (types are checked before every access); kept so that a
    // yaml-cpp surprise still names the file and line.
    throw InputError(name, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", "YAML error: " + e.msg);
  }
}

}  // namespace fq
