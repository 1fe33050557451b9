// Base shear and vertical reaction in history.csv (io/scene_output.h): the
// force the ground applies to the structure through support joints and
// ground contacts, against statics. A structure at rest relative to ground
// moving with a constant acceleration a_g is pushed by the ground with
// M a_g horizontally and carries its weight M g vertically (Newton's second
// law for the whole structure; the ground-motion inertia force -M a_g of
// the relative frame is what the base shear balances).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io_test_util.h"

namespace fq {
namespace {

using test::TempDir;

// The last row of history.csv as column name -> value.
std::map<std::string, double> last_row(const std::filesystem::path& history) {
  std::ifstream in(history);
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::map<std::string, double> row;
  std::stringstream h(header), v(last);
  for (std::string name, value; std::getline(h, name, ',') && std::getline(v, value, ',');)
    row[name] = std::stod(value);
  return row;
}

// Runs the case text (its output into dir/out) and checks the last row of
// history.csv against statics: base shear M a_g along x, none along y, a
// vertical reaction of M g, each to `relative` of its value (y to 1e-9 N).
// Returns that row.
std::map<std::string, double> expect_static_base_force(const TempDir& dir, const std::string& case_text,
                                                       double mass_kg, double a_g_mps2, double relative) {
  const CaseRunReport report = run_case(load_case_file(dir.write("case.yaml", case_text)), {});
  EXPECT_EQ(report.result.status, RunStatus::Completed);
  const auto row = last_row(dir.path() / "out/history.csv");
  EXPECT_TRUE(row.count("base_shear_x_N") && row.count("base_shear_y_N") && row.count("base_reaction_z_N"));
  if (!row.count("base_shear_x_N") || !row.count("base_shear_y_N") || !row.count("base_reaction_z_N")) return row;
  const double shear = mass_kg * a_g_mps2, weight = mass_kg * kStandardGravity_mps2;
  EXPECT_NEAR(row.at("base_shear_x_N"), shear, relative * shear);
  EXPECT_NEAR(row.at("base_shear_y_N"), 0.0, 1e-9);
  EXPECT_NEAR(row.at("base_reaction_z_N"), weight, relative * weight);
  return row;
}

// A record of constant acceleration (m/s^2) for 2 s, along x.
std::string constant_x_motion(const TempDir& dir, double a_mps2) {
  const auto file = dir.write("constant.txt", test::constant_record(2.0, a_mps2));
  return "ground_motion: {components: [{file: " + file.string() + ", format: two_column, axis: x}]}\n";
}

// A column 0.3 m tall on a four-corner support joint whose springs carry a
// damping ratio of 1 (each spring's dashpot is set from its own stiffness
// and an effective mass, so the column's rocking mode, 4 k c^2 / (m L^2 / 3)
// = (157 rad/s)^2, gets a ratio of about 0.08): the step of a_g at t = 0
// rings down as exp(-12 t), 1e-8 after 1.5 s, leaving the quasi-static
// state. Mass 450 * 0.02 * 0.02 * 0.3 = 0.054 kg.
TEST(BaseForce, ColumnOnASupportJointCarriesMassTimesGroundAcceleration) {
  TempDir dir;
  const double a_g = 1.5, mass = 450.0 * 0.02 * 0.02 * 0.3;
  const std::string text =
      "framequake_case: 1\n"
      "time: {dt_s: 1.0e-5, duration_s: 1.5}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}]\n"
      "sections: [{name: col, width_m: 0.02, depth_m: 0.02}]\n"
      "nodes: [{id: a, xyz_m: [0, 0, 0]}, {id: b, xyz_m: [0, 0, 0.3]}]\n"
      "members: [{id: c, kind: column, nodes: [a, b], section: col, material: wood}]\n"
      "joint_types: [{name: base, layout: four_corner,\n"
      "               normal: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 1.0},\n"
      "               shear: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 1.0},\n"
      "               fracture: {criterion: never}}]\n"
      "supports: [{node: a, joint_type: base}]\n" +
      constant_x_motion(dir, a_g) + "output: {folder: " + (dir.path() / "out").string() +
      ", frame_interval_s: 0.5, history_interval_s: 0.01}\n";
  expect_static_base_force(dir, text, mass, a_g, 1e-6);
}

// A block resting on the ground (contacts, friction 0.5) under a_g = 2 m/s^2,
// below mu g = 4.9 m/s^2: it sticks, and friction is the base shear. The
// contact's restitution 0.3 damps the step's ringing (contact period about
// 2 ms; 1 s is hundreds of periods).
TEST(BaseForce, BlockStickingOnTheGroundIsPushedByFriction) {
  TempDir dir;
  const double a_g = 2.0, mass = 450.0 * 0.1 * 0.1 * 0.05;
  const std::string text =
      "framequake_case: 1\n"
      "time: {dt_s: 1.0e-5, duration_s: 1.0}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}]\n"
      "ground: {level_m: 0.0}\n"
      "blocks: [{id: b, size_m: [0.1, 0.1, 0.05], center_m: [0, 0, 0.025], material: wood}]\n"
      "contact:\n"
      "  ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.3, friction_coefficient: 0.5}\n" +
      constant_x_motion(dir, a_g) + "output: {folder: " + (dir.path() / "out").string() +
      ", frame_interval_s: 0.5, history_interval_s: 0.01}\n";
  const auto row = expect_static_base_force(dir, text, mass, a_g, 1e-4);
  // The contacts' own column, the normal force alone, agrees.
  ASSERT_TRUE(row.count("ground_normal_force_N") && row.count("base_reaction_z_N"));
  EXPECT_NEAR(row.at("ground_normal_force_N"), row.at("base_reaction_z_N"), 1e-9);
}

}  // namespace
}  // namespace fq
