// Storeys and inter-storey drift (io/storey_drift.h): which columns make a
// storey (a column split at mid-height is one column line, a floor node
// typed a few mm off level is of its floor), and the drift of known rigid
// motions against their closed forms
// (a column turned by theta about its bottom point drifts h sin(theta); a
// rigid translation of a whole storey does not drift), the floor's own
// drift and its slips on its column tops and at the columns' feet (a floor
// sliding on joints soft in shear against the oscillator's closed form is
// test_storey_drift_sliding.cpp, labelled slow), plus the verdict
// thresholds and the drift columns and summary of a real run.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io/input_error.h"
#include "io/model.h"
#include "io/storey_drift.h"
#include "io_test_util.h"

namespace fq {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

// Two storeys of 0.29 m in the x-z plane (two columns each) plus a
// through-column 0.58 m tall at x = 1; beams join the tops.
const char* kFrame =
    "framequake_case: 1\n"
    "name: two_storeys\n"
    "time: {dt_s: 1.0e-5, duration_s: 0.01}\n"
    "materials: [{name: wood, density_kg_per_m3: 450}]\n"
    "sections: [{name: col, width_m: 0.010, depth_m: 0.020}, {name: beam, width_m: 0.010, depth_m: 0.010}]\n"
    "nodes:\n"
    "  - {id: a0, xyz_m: [0, 0, 0]}\n"
    "  - {id: a1, xyz_m: [0, 0, 0.29]}\n"
    "  - {id: a2, xyz_m: [0, 0, 0.58]}\n"
    "  - {id: b0, xyz_m: [0.5, 0, 0]}\n"
    "  - {id: b1, xyz_m: [0.5, 0, 0.29]}\n"
    "  - {id: b2, xyz_m: [0.5, 0, 0.58]}\n"
    "  - {id: c0, xyz_m: [1.0, 0, 0]}\n"
    "  - {id: c2, xyz_m: [1.0, 0, 0.58]}\n"
    "members:\n"
    "  - {id: col_a1, kind: column, nodes: [a0, a1], section: col, material: wood}\n"
    "  - {id: col_a2, kind: column, nodes: [a2, a1], section: col, material: wood}\n"  // drawn downwards
    "  - {id: col_b1, kind: column, nodes: [b0, b1], section: col, material: wood}\n"
    "  - {id: col_b2, kind: column, nodes: [b1, b2], section: col, material: wood}\n"
    "  - {id: col_c, kind: column, nodes: [c0, c2], section: col, material: wood}\n"
    "  - {id: beam_1, kind: beam, nodes: [a1, b1], section: beam, material: wood}\n"
    "  - {id: beam_2, kind: beam, nodes: [a2, b2], section: beam, material: wood}\n";

Model frame_model() {
  TempDir dir;
  return build_model(load_case_file(dir.write("frame.yaml", kFrame)));
}

// A monitor of `model`'s storeys (default limits, steps of 1e-5 s, a
// residual window of 1 s), tracked once at rest (t = 0).
StoreyDriftMonitor monitor_at_rest(const Model& model) {
  StoreyDriftMonitor monitor(find_storeys(model), AssessmentDef{}, 1e-5, 1.0);
  monitor.track(model.bodies, 0.0);
  return monitor;
}

// kFrame with joints (a rigid default type): its beams are held at the
// column tops they end at, and so measure the floor there (StoreyColumn::
// floor_points). kFrame alone has no joint types: nothing is joined, and
// every column top counts its own point.
Model jointed_frame_model() {
  TempDir dir;
  return build_model(load_case_file(dir.write(
      "jointed.yaml", std::string(kFrame) +
                          "joint_types: [{name: rigid, layout: four_corner, normal: {law: linear, stiffness_N_per_m: "
                          "1.0e8}, shear: {law: linear, stiffness_N_per_m: 1.0e8}, fracture: {criterion: never}}]\n"
                          "joints: {default_type: rigid}\n")));
}

// Turns body `b` by `angle` about world y through world point `pivot`.
void turn_about_y(BodyStore& bodies, BodyId b, const Vec3& pivot, double angle) {
  const Quat q(Eigen::AngleAxisd(angle, Vec3::UnitY()));
  bodies.position_m[b] = pivot + q * (bodies.position_m[b] - pivot);
  bodies.orientation[b] = (q * bodies.orientation[b]).normalized();
  bodies.update_rotations();
}

TEST(StoreyDrift, StoreysAreTheBandsBetweenColumnLevels) {
  const Model model = frame_model();
  const std::vector<Storey> storeys = find_storeys(model);
  ASSERT_EQ(storeys.size(), 2u);
  EXPECT_EQ(storeys[0].number, 1);
  EXPECT_DOUBLE_EQ(storeys[0].bottom_z_m, 0.0);
  EXPECT_DOUBLE_EQ(storeys[0].top_z_m, 0.29);
  EXPECT_DOUBLE_EQ(storeys[1].height_m(), 0.29);
  // Storey 1: col_a1, col_b1 and the through-column; storey 2: col_a2, col_b2 and it again.
  EXPECT_EQ(storeys[0].column_names, (std::vector<std::string>{"col_a1", "col_b1", "col_c"}));
  EXPECT_EQ(storeys[1].column_names, (std::vector<std::string>{"col_a2", "col_b2", "col_c"}));
  // At rest nothing drifts.
  for (const Storey& s : storeys) EXPECT_NEAR(storey_drift_m(s, model.bodies).norm(), 0.0, 1e-15);
}

// A one-storey portal on a hillside: feet at z = 0 and 0.1 m, both tops at
// 0.39 m (columns 'long' and 'short', then 'beam').
Model hillside_portal_model() {
  TempDir dir;
  return build_model(load_case_file(dir.write("hillside.yaml",
      "framequake_case: 1\n"
      "time: {dt_s: 1.0e-5, duration_s: 0.01}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}]\n"
      "sections: [{name: col, width_m: 0.010, depth_m: 0.020}]\n"
      "nodes:\n"
      "  - {id: a0, xyz_m: [0, 0, 0]}\n"
      "  - {id: a1, xyz_m: [0, 0, 0.39]}\n"
      "  - {id: b0, xyz_m: [0.5, 0, 0.1]}\n"
      "  - {id: b1, xyz_m: [0.5, 0, 0.39]}\n"
      "members:\n"
      "  - {id: long, kind: column, nodes: [a0, a1], section: col, material: wood}\n"
      "  - {id: short, kind: column, nodes: [b0, b1], section: col, material: wood}\n"
      "  - {id: beam, kind: beam, nodes: [a1, b1], section: col, material: wood}\n")));
}

// A one-storey portal on a hillside: feet at z = 0 and 0.1 m, both tops at
// 0.39 m. One storey (a foot is no level; the geometry probe got a storey
// 0-0.1 m of the long column alone), both columns in it, the short one
// counted from its foot: turned by theta about their feet, the columns
// drift 0.39 sin(theta) and 0.29 sin(theta), the storey their mean.
TEST(StoreyDrift, AColumnOnAHillsideStepCountsFromItsFoot) {
  Model model = hillside_portal_model();
  const std::vector<Storey> storeys = find_storeys(model);
  ASSERT_EQ(storeys.size(), 1u);
  EXPECT_DOUBLE_EQ(storeys[0].bottom_z_m, 0.0);
  EXPECT_DOUBLE_EQ(storeys[0].top_z_m, 0.39);
  EXPECT_EQ(storeys[0].column_names, (std::vector<std::string>{"long", "short"}));
  const double theta = 0.05;
  turn_about_y(model.bodies, model.member_body[0], Vec3(0, 0, 0), theta);
  turn_about_y(model.bodies, model.member_body[1], Vec3(0.5, 0, 0.1), theta);
  const Eigen::Vector2d d = storey_drift_m(storeys[0], model.bodies);
  EXPECT_NEAR(d.x(), 0.5 * (0.39 + 0.29) * std::sin(theta), 1e-12);
  EXPECT_NEAR(d.y(), 0.0, 1e-12);
}

// The same hillside portal swaying as a frame: both tops move d = 11 mm
// along x, each column turned about its foot by asin(d / its height). The
// storey drifts d / 0.39 = 0.0282 rad (the mean of its columns' top
// displacements over the storey's height), under the safety limit 1/30;
// the short column tilts d / 0.29 = 0.0379 rad, past it, as a short column
// does: its ratio is over its own 0.29 m, and the run says that it alone
// would be damaged (geometry probe, 2026-11-27: over the storey's height
// it read 0.19 / 0.29 of its tilt and no warning came).
TEST(StoreyDrift, AShortColumnsDriftRatioIsOverItsOwnHeight) {
  Model model = hillside_portal_model();
  const std::vector<Storey> storeys = find_storeys(model);
  ASSERT_EQ(storeys.size(), 1u);
  ASSERT_EQ(storeys[0].columns.size(), 2u);
  EXPECT_NEAR(storeys[0].columns[0].height_m, 0.39, 1e-15);
  EXPECT_NEAR(storeys[0].columns[1].height_m, 0.29, 1e-15);
  StoreyDriftMonitor monitor(storeys, AssessmentDef{}, 1e-5, 1.0);
  monitor.track(model.bodies, 0.0);
  const double d = 0.011;
  turn_about_y(model.bodies, model.member_body[0], Vec3(0, 0, 0), std::asin(d / 0.39));
  turn_about_y(model.bodies, model.member_body[1], Vec3(0.5, 0, 0.1), std::asin(d / 0.29));
  monitor.track(model.bodies, 0.1);
  const StoreyDriftRecord& r = monitor.records()[0];
  EXPECT_NEAR(r.peak_ratio_rad, d / 0.39, 1e-12);
  EXPECT_NEAR(r.peak_column_ratio_rad, d / 0.29, 1e-12);
  EXPECT_EQ(r.peak_column, 1);
  EXPECT_EQ(monitor.verdict(0), StoreyVerdict::Standing);
  const std::string note = monitor.twist_warning(0);
  EXPECT_NE(note.find("column 'short' (0.29 m tall in the storey's 0.39 m; its ratio is over its own height) alone "
                      "drifted 0.0379 rad, which would make it damaged"),
            std::string::npos)
      << note;
}

// Turns every member of `model` by `angle` about world y through the
// origin: a rigid sway of the whole frame, under which every point at
// height z moves z sin(angle) along x, so every storey whose columns are
// vertical drifts its height times sin(angle): drift ratio sin(angle).
void sway_whole_frame(Model& model, double angle) {
  for (const BodyId b : model.member_body) turn_about_y(model.bodies, b, Vec3::Zero(), angle);
}

// kFrame with col_a1 split at mid-height (node am, z = 0.145) into two
// column members for a knee brace (the brace from am to b0): no beam
// frames into am and a column continues up from it, so it is a joint along
// one column line, not a floor. The geometry probe got three storeys
// (0-0.145, 0.145-0.29, 0.29-0.58), the split column's drift taken from
// its upper half alone.
std::string knee_split_frame() {
  std::string text = kFrame;
  const std::string a1 = "  - {id: col_a1, kind: column, nodes: [a0, a1], section: col, material: wood}\n";
  text.replace(text.find(a1), a1.size(),
               "  - {id: col_a1a, kind: column, nodes: [a0, am], section: col, material: wood}\n"
               "  - {id: col_a1b, kind: column, nodes: [am, a1], section: col, material: wood}\n"
               "  - {id: knee, kind: brace, nodes: [am, b0], section: beam, material: wood}\n");
  const std::string a0 = "  - {id: a0, xyz_m: [0, 0, 0]}\n";
  text.replace(text.find(a0), a0.size(), a0 + "  - {id: am, xyz_m: [0, 0, 0.145]}\n");
  return text;
}

TEST(StoreyDrift, AColumnSplitAtMidHeightIsOneColumnLineOfItsStorey) {
  TempDir dir;
  Model split = build_model(load_case_file(dir.write("split.yaml", knee_split_frame())));
  Model whole = frame_model();
  const std::vector<Storey> s = find_storeys(split), w = find_storeys(whole);
  ASSERT_EQ(s.size(), 2u);
  ASSERT_EQ(w.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_DOUBLE_EQ(s[k].bottom_z_m, w[k].bottom_z_m);
    EXPECT_DOUBLE_EQ(s[k].top_z_m, w[k].top_z_m);
    EXPECT_EQ(s[k].columns.size(), w[k].columns.size());
  }
  EXPECT_EQ(s[0].column_names, (std::vector<std::string>{"col_a1a+col_a1b", "col_b1", "col_c"}));
  EXPECT_EQ(s[1].column_names, w[1].column_names);
  // The line's points lie on its two segments: its foot on the lower, its
  // top on the upper.
  EXPECT_EQ(s[0].columns[0].bottom_body, split.member_body[0]);
  EXPECT_EQ(s[0].columns[0].top_body, split.member_body[1]);
  EXPECT_TRUE(s[0].columns[0].bottom_start_m.isApprox(Vec3(0, 0, 0)));
  EXPECT_TRUE(s[0].columns[0].top_start_m.isApprox(Vec3(0, 0, 0.29)));
  // A rigid sway of the whole frame by theta: every storey of both frames
  // drifts its height times sin(theta).
  const double theta = 0.03;
  sway_whole_frame(split, theta);
  sway_whole_frame(whole, theta);
  for (std::size_t k = 0; k < 2; ++k) {
    const Eigen::Vector2d ds = storey_drift_m(s[k], split.bodies), dw = storey_drift_m(w[k], whole.bodies);
    EXPECT_NEAR(ds.x() / s[k].height_m(), std::sin(theta), 1e-12) << k;
    EXPECT_NEAR(ds.y(), 0.0, 1e-12) << k;
    EXPECT_NEAR(ds.x(), dw.x(), 1e-12) << k;
  }
  // The upper half moved sideways by (u, v) alone (its joint with the
  // lower half slipped): the line drifts (u, v), which its upper half on
  // its own does not show (a translation turns no body), and storey 1, the
  // mean of its three lines, drifts a third of it.
  Model slipped = build_model(load_case_file(dir.write("slip.yaml", knee_split_frame())));
  const Vec3 slip(0.012, -0.006, 0.0);
  slipped.bodies.position_m[slipped.member_body[1]] += slip;
  std::vector<Eigen::Vector2d> per_column;
  const Eigen::Vector2d d = storey_drift_m(s[0], slipped.bodies, &per_column);
  EXPECT_NEAR(per_column[0].x(), slip.x(), 1e-15);
  EXPECT_NEAR(per_column[0].y(), slip.y(), 1e-15);
  EXPECT_NEAR(d.x(), slip.x() / 3.0, 1e-15);
  EXPECT_NEAR(d.y(), slip.y() / 3.0, 1e-15);
}

// Three column lines (x = 0, 0.5, 1) of two storeys of 0.29 m, beams of
// section `beam_depth_m` deep (roll 0: depth_m is vertical) joining each
// floor; node b1, where the middle line's floor beams meet, typed at
// `b1_z_m`.
std::string three_bay_frame(double b1_z_m, double beam_depth_m) {
  std::ostringstream t;
  t << "framequake_case: 1\n"
       "time: {dt_s: 1.0e-5, duration_s: 0.01}\n"
       "materials: [{name: wood, density_kg_per_m3: 450}]\n"
       "sections: [{name: col, width_m: 0.010, depth_m: 0.020}, {name: beam, width_m: 0.010, depth_m: "
    << beam_depth_m << "}]\n"
       "nodes:\n"
       "  - {id: a0, xyz_m: [0, 0, 0]}\n"
       "  - {id: a1, xyz_m: [0, 0, 0.29]}\n"
       "  - {id: a2, xyz_m: [0, 0, 0.58]}\n"
       "  - {id: b0, xyz_m: [0.5, 0, 0]}\n"
       "  - {id: b1, xyz_m: [0.5, 0, "
    << b1_z_m << "]}\n"
       "  - {id: b2, xyz_m: [0.5, 0, 0.58]}\n"
       "  - {id: c0, xyz_m: [1.0, 0, 0]}\n"
       "  - {id: c1, xyz_m: [1.0, 0, 0.29]}\n"
       "  - {id: c2, xyz_m: [1.0, 0, 0.58]}\n"
       "members:\n"
       "  - {id: col_a1, kind: column, nodes: [a0, a1], section: col, material: wood}\n"
       "  - {id: col_b1, kind: column, nodes: [b0, b1], section: col, material: wood}\n"
       "  - {id: col_c1, kind: column, nodes: [c0, c1], section: col, material: wood}\n"
       "  - {id: col_a2, kind: column, nodes: [a1, a2], section: col, material: wood}\n"
       "  - {id: col_b2, kind: column, nodes: [b1, b2], section: col, material: wood}\n"
       "  - {id: col_c2, kind: column, nodes: [c1, c2], section: col, material: wood}\n"
       "  - {id: beam_ab1, kind: beam, nodes: [a1, b1], section: beam, material: wood}\n"
       "  - {id: beam_bc1, kind: beam, nodes: [b1, c1], section: beam, material: wood}\n"
       "  - {id: beam_ab2, kind: beam, nodes: [a2, b2], section: beam, material: wood}\n"
       "  - {id: beam_bc2, kind: beam, nodes: [b2, c2], section: beam, material: wood}\n";
  return t.str();
}

// A floor node typed 5 mm high on beams 10 mm deep (the geometry probe:
// a storey 5 mm tall of its own, damaged, and the storey above renumbered
// 3) lies within its floor's beams: one floor, at the median height of its
// nodes (0.29), two storeys of 0.29 m, the middle line's column ends taken
// at 0.29 (on their axes, 5 mm below and above the node), so a rigid sway
// by theta drifts both storeys by exactly sin(theta). Typed 12 mm high it
// lies beyond the 10 mm beams' depth: a level of its own (three storeys);
// on beams 30 mm deep it is one floor again.
TEST(StoreyDrift, AFloorNodeTypedOffLevelWithinItsBeamsDepthIsOfThatFloor) {
  TempDir dir;
  Model model = build_model(load_case_file(dir.write("5mm.yaml", three_bay_frame(0.295, 0.010))));
  const std::vector<Storey> storeys = find_storeys(model);
  ASSERT_EQ(storeys.size(), 2u);
  EXPECT_DOUBLE_EQ(storeys[0].bottom_z_m, 0.0);
  EXPECT_DOUBLE_EQ(storeys[0].top_z_m, 0.29);
  EXPECT_DOUBLE_EQ(storeys[1].top_z_m, 0.58);
  EXPECT_EQ(storeys[0].column_names, (std::vector<std::string>{"col_a1", "col_b1", "col_c1"}));
  EXPECT_EQ(storeys[1].column_names, (std::vector<std::string>{"col_a2", "col_b2", "col_c2"}));
  EXPECT_NEAR(storeys[0].columns[1].top_start_m.z(), 0.29, 1e-15);
  EXPECT_NEAR(storeys[1].columns[1].bottom_start_m.z(), 0.29, 1e-15);
  const double theta = 0.04;
  sway_whole_frame(model, theta);
  for (const Storey& s : storeys) {
    std::vector<Eigen::Vector2d> per_column;
    const Eigen::Vector2d d = storey_drift_m(s, model.bodies, &per_column);
    EXPECT_NEAR(d.x() / s.height_m(), std::sin(theta), 1e-12) << s.number;
    for (const Eigen::Vector2d& c : per_column) EXPECT_NEAR(c.x() / s.height_m(), std::sin(theta), 1e-12) << s.number;
  }

  const std::vector<Storey> apart =
      find_storeys(build_model(load_case_file(dir.write("12mm.yaml", three_bay_frame(0.302, 0.010)))));
  ASSERT_EQ(apart.size(), 3u);
  EXPECT_DOUBLE_EQ(apart[1].bottom_z_m, 0.29);
  EXPECT_DOUBLE_EQ(apart[1].top_z_m, 0.302);
  const std::vector<Storey> deep =
      find_storeys(build_model(load_case_file(dir.write("deep.yaml", three_bay_frame(0.302, 0.030)))));
  ASSERT_EQ(deep.size(), 2u);
  EXPECT_DOUBLE_EQ(deep[0].top_z_m, 0.29);
}

// A column whose top is typed 3 mm above its floor on its own node, with
// no beam framing into it and no column continuing up from it (the
// geometry probe's col_top_3mm: a storey 3 mm tall of five columns), is a
// level of its own (a free top) within the 10 mm depth of the floor's
// beams at 0.29: one floor, and the column reaches it.
TEST(StoreyDrift, AColumnTopTypedAboveItsFloorWithoutABeamReachesTheFloor) {
  TempDir dir;
  std::string text = three_bay_frame(0.29, 0.010);
  const std::string b1 = "  - {id: col_b1, kind: column, nodes: [b0, b1], section: col, material: wood}\n";
  text.replace(text.find(b1), b1.size(),
               "  - {id: col_b1, kind: column, nodes: [b0, b1x], section: col, material: wood}\n");
  const std::string c0 = "  - {id: c0, xyz_m: [1.0, 0, 0]}\n";
  text.replace(text.find(c0), c0.size(), c0 + "  - {id: b1x, xyz_m: [0.5, 0, 0.293]}\n");
  Model model = build_model(load_case_file(dir.write("3mm.yaml", text)));
  const std::vector<Storey> storeys = find_storeys(model);
  ASSERT_EQ(storeys.size(), 2u);
  EXPECT_DOUBLE_EQ(storeys[0].top_z_m, 0.29);
  EXPECT_EQ(storeys[0].column_names, (std::vector<std::string>{"col_a1", "col_b1", "col_c1"}));
  EXPECT_EQ(storeys[1].column_names, (std::vector<std::string>{"col_a2", "col_b2", "col_c2"}));
  sway_whole_frame(model, 0.02);
  for (const Storey& s : storeys)
    EXPECT_NEAR(storey_drift_m(s, model.bodies).x() / s.height_m(), std::sin(0.02), 1e-12) << s.number;
}

// Every first-storey column top typed 3 mm above the floor on a node of
// its own (no beam there, no column continuing up: each a level of its own
// with the least tolerance, 1 mm), the floor beams and the upper columns
// on the nodes at 0.29 (scale probe: the upper columns were counted into
// storey 1 as 3 mm columns, halving its mean drift). The upper columns'
// feet, where the 10 mm beams frame in, lie within those beams' depth of
// the level at 0.293: they stand on that floor. Storey 1 has its three
// columns, storey 2 the upper three, and a rigid sway by theta drifts both
// by sin(theta).
TEST(StoreyDrift, ColumnsStandingOnTheBeamsBelowTopsTypedAboveThemAreOfTheStoreyAbove) {
  TempDir dir;
  std::string text = three_bay_frame(0.29, 0.010);
  for (const char* line : {"a", "b", "c"}) {
    const std::string l(line);
    const std::string lower = "  - {id: col_" + l + "1, kind: column, nodes: [" + l + "0, " + l + "1]";
    ASSERT_NE(text.find(lower), std::string::npos) << l;
    text.replace(text.find(lower), lower.size(),
                 "  - {id: col_" + l + "1, kind: column, nodes: [" + l + "0, " + l + "1t]");
    const std::string node = "  - {id: " + l + "2, xyz_m: [";
    const double x = l == "a" ? 0.0 : l == "b" ? 0.5 : 1.0;
    std::ostringstream top;
    top << "  - {id: " << l << "1t, xyz_m: [" << x << ", 0, 0.293]}\n";
    text.replace(text.find(node), 0, top.str());
  }
  Model model = build_model(load_case_file(dir.write("tops_3mm.yaml", text)));
  const std::vector<Storey> storeys = find_storeys(model);
  ASSERT_EQ(storeys.size(), 2u);
  EXPECT_DOUBLE_EQ(storeys[0].top_z_m, 0.293);
  EXPECT_EQ(storeys[0].column_names, (std::vector<std::string>{"col_a1", "col_b1", "col_c1"}));
  EXPECT_EQ(storeys[1].column_names, (std::vector<std::string>{"col_a2", "col_b2", "col_c2"}));
  sway_whole_frame(model, 0.02);
  for (const Storey& s : storeys)
    EXPECT_NEAR(storey_drift_m(s, model.bodies).x() / s.height_m(), std::sin(0.02), 1e-12) << s.number;
}

TEST(StoreyDrift, TurnedColumnDriftsHeightTimesSine) {
  Model model = frame_model();
  const std::vector<Storey> storeys = find_storeys(model);
  const double theta = 0.07;  // rad
  // Every storey-1 column turned about its base: drift = h sin(theta) along x
  // (a positive turn about y moves the top towards +x).
  turn_about_y(model.bodies, model.member_body[0], Vec3(0, 0, 0), theta);
  turn_about_y(model.bodies, model.member_body[2], Vec3(0.5, 0, 0), theta);
  // The through-column turned about its base: its storey-1 band drifts
  // h sin(theta) and so does its storey-2 band (both bands rotate alike).
  turn_about_y(model.bodies, model.member_body[4], Vec3(1.0, 0, 0), theta);
  const Eigen::Vector2d d1 = storey_drift_m(storeys[0], model.bodies);
  EXPECT_NEAR(d1.x(), 0.29 * std::sin(theta), 1e-12);
  EXPECT_NEAR(d1.y(), 0.0, 1e-12);
  // Storey 2: two untouched columns and the through-column's upper band.
  const Eigen::Vector2d d2 = storey_drift_m(storeys[1], model.bodies);
  EXPECT_NEAR(d2.x(), 0.29 * std::sin(theta) / 3.0, 1e-12);
}

TEST(StoreyDrift, TranslatedStoreyDoesNotDrift) {
  Model model = frame_model();
  const std::vector<Storey> storeys = find_storeys(model);
  // The upper storey's columns slide 0.2 m sideways and drop 0.29 m,
  // upright: a storey that fell without leaning has no drift.
  for (int m : {1, 3}) model.bodies.position_m[model.member_body[std::size_t(m)]] += Vec3(0.2, 0.1, -0.29);
  EXPECT_NEAR(storey_drift_m(storeys[1], model.bodies).norm(), 0.0, 1e-12);
}

TEST(StoreyDrift, MonitorKeepsPeaksAndJudgesByTheLimits) {
  Model model = frame_model();
  AssessmentDef limits;  // 1/30 and 1/10 rad
  StoreyDriftMonitor monitor(find_storeys(model), limits, 1e-5, 1.0);
  const BodyId col_a1 = model.member_body[0], col_b1 = model.member_body[2], col_c = model.member_body[4];
  auto lean_storey1 = [&](double angle) {  // sets storey 1 to lean by `angle` (absolute)
    Model fresh = frame_model();
    for (BodyId b : {col_a1, col_b1, col_c}) {
      model.bodies.position_m[b] = fresh.bodies.position_m[b];
      model.bodies.orientation[b] = fresh.bodies.orientation[b];
    }
    model.bodies.update_rotations();
    turn_about_y(model.bodies, col_a1, Vec3(0, 0, 0), angle);
    turn_about_y(model.bodies, col_b1, Vec3(0.5, 0, 0), angle);
    turn_about_y(model.bodies, col_c, Vec3(1.0, 0, 0), angle);
  };
  monitor.sample(model.bodies, 0, 0.0);
  EXPECT_EQ(monitor.verdict(0), StoreyVerdict::Standing);
  lean_storey1(-0.05);  // sin(0.05) = 0.04998 > 1/30: damaged
  monitor.sample(model.bodies, 1, 0.5);
  monitor.sample(model.bodies, 1, 0.5);  // a repeated step is ignored
  EXPECT_EQ(monitor.verdict(0), StoreyVerdict::Damaged);
  EXPECT_NEAR(monitor.records()[0].peak_ratio_x_rad, std::sin(0.05), 1e-12);
  lean_storey1(0.02);  // back below: the peak and the verdict stay
  monitor.sample(model.bodies, 2, 1.0);
  EXPECT_EQ(monitor.verdict(0), StoreyVerdict::Damaged);
  EXPECT_NEAR(monitor.records()[0].final_ratio_x_rad, std::sin(0.02), 1e-12);
  EXPECT_LT(monitor.records()[0].collapse_time_s, 0.0);
  lean_storey1(0.2);  // sin(0.2) = 0.199 >= 0.1: collapsed, at t = 1.5 s
  monitor.sample(model.bodies, 3, 1.5);
  EXPECT_EQ(monitor.verdict(0), StoreyVerdict::Collapsed);
  EXPECT_DOUBLE_EQ(monitor.records()[0].collapse_time_s, 1.5);
  EXPECT_DOUBLE_EQ(monitor.records()[0].peak_time_s, 1.5);
  // Storey 2 holds two unmoved columns and the through-column's upper band
  // (which leans with it): a third of the lean.
  EXPECT_NEAR(monitor.records()[1].peak_ratio_rad, std::sin(0.2) / 3.0, 1e-12);
}

// A storey that twists: storey 1's mean drift is that of its three columns,
// so one column leaning by 0.05 rad (drift ratio sin 0.05 = 0.04998, past
// the 1/30 damage limit) while the other two stand gives the storey
// 0.04998 / 3 = 0.0167 rad, standing. The column's own peak is kept and
// named, and the warning says the column alone would make the storey
// damaged. The same lean on all three columns gives no warning (the mean
// then is the column's).
TEST(StoreyDrift, AColumnPastAWorseVerdictThanItsStoreysMeanIsWarnedOf) {
  Model model = frame_model();
  StoreyDriftMonitor monitor(find_storeys(model), AssessmentDef{}, 1e-5, 1.0);
  const BodyId col_a1 = model.member_body[0];
  monitor.track(model.bodies, 0.0);
  turn_about_y(model.bodies, col_a1, Vec3(0, 0, 0), -0.05);
  monitor.track(model.bodies, 0.1);
  const StoreyDriftRecord& r = monitor.records()[0];
  EXPECT_NEAR(r.peak_ratio_rad, std::sin(0.05) / 3.0, 1e-12);
  EXPECT_EQ(monitor.verdict(0), StoreyVerdict::Standing);
  EXPECT_NEAR(r.peak_column_ratio_rad, std::sin(0.05), 1e-12);
  ASSERT_GE(r.peak_column, 0);
  EXPECT_EQ(monitor.storeys()[0].column_names[std::size_t(r.peak_column)], "col_a1");
  // The frame lies in one plane (its columns at y = 0): a lean along x
  // turns no floor about z, so this is no twist but one column leaning
  // while the others stand.
  EXPECT_NEAR(r.peak_twist_ratio_rad, 0.0, 1e-12);
  const std::string w = monitor.twist_warning(0);
  EXPECT_NE(w.find("storey 1's columns did not move alike: its drift, the mean of its 3 columns, peaked at 0.0167 rad "
                   "(standing), but column 'col_a1' alone drifted 0.05 rad, which would make it damaged, while the "
                   "floor did not turn"),
            std::string::npos)
      << w;

  Model even = frame_model();
  StoreyDriftMonitor same(find_storeys(even), AssessmentDef{}, 1e-5, 1.0);
  same.track(even.bodies, 0.0);
  turn_about_y(even.bodies, even.member_body[0], Vec3(0, 0, 0), -0.05);
  turn_about_y(even.bodies, even.member_body[2], Vec3(0.5, 0, 0), -0.05);
  turn_about_y(even.bodies, even.member_body[4], Vec3(1.0, 0, 0), -0.05);
  same.track(even.bodies, 0.1);
  EXPECT_EQ(same.verdict(0), StoreyVerdict::Damaged);
  EXPECT_EQ(same.twist_warning(0), "");
}

// Columns that drifted alike are no twist, though the largest passes a
// limit the mean stays under (geometry probe: 0.0597 rad against a mean of
// 0.0588 at a collapse limit of 0.0588, 1.5 % apart, was called a twist).
// Storey 1's three columns leaning to drift ratios 0.033, 0.033 and 0.0345
// (turned by their arcsines) drift 0.0335 on the mean, under a safety
// limit of 0.034 that the third passes alone, 3.0 % above the mean: said,
// without "twists". Leaning 0.030, 0.030 and 0.040, the third is 20 %
// above the mean of 0.0333 (kTwistColumnExcess = 10 %), but in this plane
// frame its floor does not turn: columns that did not move alike, no twist.
TEST(StoreyDrift, AColumnJustAboveItsStoreysMeanIsNoTwist) {
  AssessmentDef limits;
  limits.safety_drift_ratio_rad = 0.034;
  const double pivots_x[] = {0.0, 0.5, 1.0};
  auto lean = [&](const double (&ratios)[3]) {
    Model model = frame_model();
    StoreyDriftMonitor monitor(find_storeys(model), limits, 1e-5, 1.0);
    monitor.track(model.bodies, 0.0);
    for (int c = 0; c < 3; ++c)
      turn_about_y(model.bodies, model.member_body[std::size_t(2 * c)], Vec3(pivots_x[c], 0, 0), std::asin(ratios[c]));
    monitor.track(model.bodies, 0.1);
    return monitor;
  };
  const StoreyDriftMonitor alike = lean({0.033, 0.033, 0.0345});
  EXPECT_NEAR(alike.records()[0].peak_ratio_rad, 0.0335, 1e-12);
  EXPECT_NEAR(alike.records()[0].peak_column_ratio_rad, 0.0345, 1e-12);
  EXPECT_EQ(alike.verdict(0), StoreyVerdict::Standing);
  const std::string note = alike.twist_warning(0);
  EXPECT_EQ(note.find("twists"), std::string::npos) << note;
  EXPECT_NE(note.find("storey 1's drift, the mean of its 3 columns, peaked at 0.0335 rad (standing), under the safety "
                      "limit of 0.034 rad, which its largest column, 'col_c', passes alone at 0.0345 rad, 3 % above "
                      "the mean"),
            std::string::npos)
      << note;
  const StoreyDriftMonitor apart = lean({0.030, 0.030, 0.040});
  EXPECT_EQ(apart.verdict(0), StoreyVerdict::Standing);
  const std::string twist = apart.twist_warning(0);
  EXPECT_NE(twist.find("storey 1's columns did not move alike: its drift, the mean of its 3 columns, peaked at 0.0333 "
                       "rad (standing), but column 'col_c' alone drifted 0.04 rad, which would make it damaged, while "
                       "the floor did not turn"),
            std::string::npos)
      << twist;
}

// A square storey (columns at (+-0.25, +-0.25) m, 0.29 m tall) whose four
// columns each lean by theta tangentially, so their tops move by
// d = h sin(theta) at right angles to their arm r from the centre: the
// floor turns by d / r about z, the mean drift is zero, and the turn gives
// the farthest column the drift ratio (d / r) r / h = sin(theta)
// (StoreyDriftRecord::peak_twist_ratio_rad). That is a twist.
TEST(StoreyDrift, AFloorThatTurnsIsATwist) {
  TempDir dir;
  const Model model0 = build_model(load_case_file(dir.write("square.yaml",
      "framequake_case: 1\n"
      "time: {dt_s: 1.0e-5, duration_s: 0.01}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}]\n"
      "sections: [{name: col, width_m: 0.010, depth_m: 0.010}]\n"
      "nodes:\n"
      "  - {id: a0, xyz_m: [0.25, 0.25, 0]}\n  - {id: a1, xyz_m: [0.25, 0.25, 0.29]}\n"
      "  - {id: b0, xyz_m: [-0.25, 0.25, 0]}\n  - {id: b1, xyz_m: [-0.25, 0.25, 0.29]}\n"
      "  - {id: c0, xyz_m: [-0.25, -0.25, 0]}\n  - {id: c1, xyz_m: [-0.25, -0.25, 0.29]}\n"
      "  - {id: d0, xyz_m: [0.25, -0.25, 0]}\n  - {id: d1, xyz_m: [0.25, -0.25, 0.29]}\n"
      "members:\n"
      "  - {id: ca, kind: column, nodes: [a0, a1], section: col, material: wood}\n"
      "  - {id: cb, kind: column, nodes: [b0, b1], section: col, material: wood}\n"
      "  - {id: cc, kind: column, nodes: [c0, c1], section: col, material: wood}\n"
      "  - {id: cd, kind: column, nodes: [d0, d1], section: col, material: wood}\n")));
  Model model = model0;
  StoreyDriftMonitor monitor(find_storeys(model), AssessmentDef{}, 1e-5, 1.0);
  monitor.track(model.bodies, 0.0);
  const double theta = 0.05;
  for (std::size_t m = 0; m < 4; ++m) {
    const BodyId b = model.member_body[m];
    const Vec3 foot(model0.def.nodes[2 * m].xyz_m);
    // Tangent to the turn about z: z x r, normalised; the column turns
    // about the horizontal axis at right angles to it, through its foot.
    const Vec3 tangent = Vec3::UnitZ().cross(Vec3(foot.x(), foot.y(), 0.0)).normalized();
    const Vec3 axis = Vec3::UnitZ().cross(tangent);
    const Quat q(Eigen::AngleAxisd(-theta, axis));
    model.bodies.position_m[b] = foot + q * (model.bodies.position_m[b] - foot);
    model.bodies.orientation[b] = (q * model.bodies.orientation[b]).normalized();
  }
  model.bodies.update_rotations();
  monitor.track(model.bodies, 0.1);
  const StoreyDriftRecord& r = monitor.records()[0];
  EXPECT_NEAR(r.peak_ratio_rad, 0.0, 1e-12);
  EXPECT_NEAR(r.peak_column_ratio_rad, std::sin(theta), 1e-12);
  EXPECT_NEAR(r.peak_twist_ratio_rad, std::sin(theta), 1e-12);
  const std::string w = monitor.twist_warning(0);
  // (The mean's peak is round-off, 1e-16 rad.)
  EXPECT_NE(w.find("storey 1 twists: its drift, the mean of its 4 columns, peaked at "), std::string::npos) << w;
  EXPECT_NE(w.find("(standing), but column 'ca' alone drifted 0.05 rad, which would make it damaged"),
            std::string::npos)
      << w;
}

// Storey 1 of the plane frame slides by d = 0.05 m along x without leaning
// (its three columns translated, feet and all): its columns' drift is zero
// (standing), but its floor moved d / h = 0.05 / 0.29 = 0.172 rad relative to
// the foundation (collapsed by the 0.1 rad limit), with a base slip of d;
// the run warns. Storey 2's floor (its columns: two unmoved, the through-
// column's upper band moved by d) moved d/3 - d relative to the floor below.
TEST(StoreyDrift, AStoreyThatSlidOffItsFoundationIsWarnedOf) {
  Model model = frame_model();
  StoreyDriftMonitor monitor(find_storeys(model), AssessmentDef{}, 1e-5, 1.0);
  monitor.track(model.bodies, 0.0);
  const double d = 0.05, h = 0.29;
  for (std::size_t m : {0, 2, 4}) model.bodies.position_m[model.member_body[m]] += Vec3(d, 0, 0);
  monitor.track(model.bodies, 0.1);
  const StoreyDriftRecord& r = monitor.records()[0];
  EXPECT_NEAR(r.peak_ratio_rad, 0.0, 1e-12);
  EXPECT_EQ(monitor.verdict(0), StoreyVerdict::Standing);
  EXPECT_NEAR(r.peak_floor_ratio_rad, d / h, 1e-12);
  EXPECT_NEAR(r.peak_base_slip_m, d, 1e-12);
  EXPECT_NEAR(monitor.records()[1].peak_floor_ratio_rad, (2.0 / 3.0) * d / h, 1e-12);
  const std::string w = monitor.slip_warning(0);
  EXPECT_NE(w.find("storey 1's floor moved 0.172 rad of its height relative to the foundation, which would make it "
                   "collapsed, while its columns tilted 0 rad (standing): the columns' feet slid up to 50 mm on the "
                   "foundation ("),
            std::string::npos)
      << w;
  // A rigid sway (columns turned about their feet) slides nothing: no warning.
  Model swayed = frame_model();
  StoreyDriftMonitor sway(find_storeys(swayed), AssessmentDef{}, 1e-5, 1.0);
  sway.track(swayed.bodies, 0.0);
  turn_about_y(swayed.bodies, swayed.member_body[0], Vec3(0, 0, 0), 0.05);
  turn_about_y(swayed.bodies, swayed.member_body[2], Vec3(0.5, 0, 0), 0.05);
  turn_about_y(swayed.bodies, swayed.member_body[4], Vec3(1.0, 0, 0), 0.05);
  sway.track(swayed.bodies, 0.1);
  EXPECT_NEAR(sway.records()[0].peak_base_slip_m, 0.0, 1e-12);
  EXPECT_NEAR(sway.records()[0].peak_floor_ratio_rad, sway.records()[0].peak_ratio_rad, 1e-12);
  EXPECT_EQ(sway.slip_warning(0), "");
}

// The floor below a storey is measured where the storey stands on it: a
// mezzanine post in storey 1 (col_m, between the frame's columns, carrying
// nothing of storey 2) leaning by 0.05 rad moves storey 1's mean top, but
// not the tops of the three columns storey 2 stands on, so storey 2 neither
// drifts nor slips (review probe: a frame without broken joints showed a
// base slip; with the whole floor's mean the slip here would be
// 0.29 sin(0.05) / 4 = 3.6 mm).
TEST(StoreyDrift, TheFloorBelowIsTakenWhereTheStoreyStandsOnIt) {
  TempDir dir;
  std::string text = kFrame;
  text.insert(text.find("members:\n"), "  - {id: m0, xyz_m: [0.25, 0, 0]}\n  - {id: m1, xyz_m: [0.25, 0, 0.29]}\n");
  text += "  - {id: col_m, kind: column, nodes: [m0, m1], section: col, material: wood}\n";
  Model model = build_model(load_case_file(dir.write("mezzanine.yaml", text)));
  StoreyDriftMonitor monitor(find_storeys(model), AssessmentDef{}, 1e-5, 1.0);
  ASSERT_EQ(monitor.storeys().size(), 2u);
  ASSERT_EQ(monitor.storeys()[0].columns.size(), 4u);
  monitor.track(model.bodies, 0.0);
  turn_about_y(model.bodies, model.member_body.back(), Vec3(0.25, 0, 0), 0.05);
  monitor.track(model.bodies, 0.1);
  EXPECT_NEAR(monitor.records()[0].peak_floor_ratio_rad, std::sin(0.05) / 4.0, 1e-12);
  EXPECT_NEAR(monitor.records()[1].peak_floor_ratio_rad, 0.0, 1e-12);
  EXPECT_NEAR(monitor.records()[1].peak_base_slip_m, 0.0, 1e-12);
}

// Where nothing slips the floor moves with the column tops, and the floor
// drift is the column drift. kFrame jointed (jointed_frame_model), so
// its beams are held at the column tops they end at: storey 1's lines a
// and b measure the floor on beam_1 at a1 and b1, storey 2's on beam_2 at
// a2 and b2; the through-column col_c has no node at 0.29, and no beam
// ends at its top c2: it counts its own top points. The frame sways as a
// parallelogram: every column turned by theta about its foot, the
// storey-2 columns' feet carried with the floor below, and each floor
// translated with the column tops it rests on, by d = h (sin(theta), 0,
// cos(theta) - 1) per storey (h = 0.29 m). Every column's top then moves
// d off its foot, and each floor d off the floor below (storey 2's: beam_1
// and col_c's point at 0.29): each storey drifts h sin(theta) by its
// columns and by its floor alike, and neither slip moves. At theta = 0.05
// both drifts are sin(0.05) = 0.04998 rad, damaged alike: no slip warning.
TEST(StoreyDrift, WhereNothingSlipsTheFloorDriftIsTheColumnDrift) {
  Model model = jointed_frame_model();
  StoreyDriftMonitor monitor = monitor_at_rest(model);
  ASSERT_EQ(monitor.storeys().size(), 2u);
  const BodyId beam_1 = model.member_body[5], beam_2 = model.member_body[6];
  for (std::size_t k = 0; k < 2; ++k) {
    const Storey& s = monitor.storeys()[k];
    const BodyId beam = k == 0 ? beam_1 : beam_2;
    ASSERT_EQ(s.column_names[2], "col_c");
    for (std::size_t c = 0; c < 2; ++c) {
      ASSERT_EQ(s.columns[c].floor_points.size(), 1u) << s.column_names[c];
      EXPECT_EQ(s.columns[c].floor_points[0].body, beam) << s.column_names[c];
      EXPECT_TRUE(s.columns[c].floor_points[0].start_m.isApprox(s.columns[c].top_start_m)) << s.column_names[c];
    }
    EXPECT_TRUE(s.columns[2].floor_points.empty());
  }
  const double theta = 0.05, h = 0.29;
  const Vec3 d(h * std::sin(theta), 0.0, h * (std::cos(theta) - 1.0));
  // Members in kFrame's order: col_a1, col_a2, col_b1, col_b2, col_c, beam_1, beam_2.
  const Vec3 feet[] = {Vec3(0, 0, 0), Vec3(0, 0, h), Vec3(0.5, 0, 0), Vec3(0.5, 0, h), Vec3(1.0, 0, 0)};
  const Vec3 carried[] = {Vec3::Zero(), d, Vec3::Zero(), d, Vec3::Zero(), d, 2.0 * d};
  for (std::size_t m = 0; m < 7; ++m) {
    if (m < 5) turn_about_y(model.bodies, model.member_body[m], feet[m], theta);
    model.bodies.position_m[model.member_body[m]] += carried[m];
  }
  model.bodies.update_rotations();
  monitor.track(model.bodies, 0.1);
  for (std::size_t k = 0; k < 2; ++k) {
    const StoreyDriftRecord& r = monitor.records()[k];
    EXPECT_NEAR(r.peak_ratio_rad, std::sin(theta), 1e-12) << k;
    EXPECT_NEAR(r.peak_floor_ratio_rad, std::sin(theta), 1e-12) << k;
    EXPECT_NEAR(r.peak_top_slip_m, 0.0, 1e-12) << k;
    EXPECT_NEAR(r.peak_base_slip_m, 0.0, 1e-12) << k;
    EXPECT_EQ(monitor.verdict(k), StoreyVerdict::Damaged);
    EXPECT_EQ(monitor.slip_warning(k), "") << k;
  }
}

// The floor of storey 1 slides on its column tops: kFrame jointed, beam_1
// moved d = 20 mm along x, nothing else. Storey 1's floor is beam_1 at
// lines a and b and col_c's own point at 0.29 (no node there): it moved
// (d + d + 0) / 3 = 2d/3 off the foundation and off the column tops, which
// stayed: top slip 2d/3, floor drift 2d/3 / h, column drift and base slip
// nothing. Storey 2's columns, which did not move, stand on that floor:
// their feet are 2d/3 off it (base slip), and its floor (beam_2, col_c's
// top) 2d/3 / h back from the floor below. The monitor's state carries the
// top slip through a checkpoint: a fresh monitor loaded from it has the
// same records, and saves the same bytes.
TEST(StoreyDrift, AFloorOffItsColumnTopsIsItsStoreysTopSlipAndTheBaseSlipOfTheStoreyAbove) {
  Model model = jointed_frame_model();
  StoreyDriftMonitor monitor = monitor_at_rest(model);
  const double d = 0.02, h = 0.29;
  model.bodies.position_m[model.member_body[5]] += Vec3(d, 0, 0);
  monitor.track(model.bodies, 0.1);
  const StoreyDriftRecord& r1 = monitor.records()[0];
  const StoreyDriftRecord& r2 = monitor.records()[1];
  EXPECT_NEAR(r1.peak_ratio_rad, 0.0, 1e-15);
  EXPECT_NEAR(r1.peak_top_slip_m, 2.0 * d / 3.0, 1e-15);
  EXPECT_NEAR(r1.peak_floor_ratio_rad, 2.0 * d / 3.0 / h, 1e-14);
  EXPECT_NEAR(r1.peak_base_slip_m, 0.0, 1e-15);
  EXPECT_NEAR(r2.peak_ratio_rad, 0.0, 1e-15);
  EXPECT_NEAR(r2.peak_top_slip_m, 0.0, 1e-15);
  EXPECT_NEAR(r2.peak_base_slip_m, 2.0 * d / 3.0, 1e-15);
  EXPECT_NEAR(r2.peak_floor_ratio_rad, 2.0 * d / 3.0 / h, 1e-14);

  StateWriter saved;
  monitor.save_state(saved);
  StoreyDriftMonitor resumed(find_storeys(model), AssessmentDef{}, 1e-5, 1.0);
  StateReader in(saved.bytes());
  resumed.load_state(in);
  EXPECT_EQ(in.remaining(), 0u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(resumed.records()[k].peak_top_slip_m, monitor.records()[k].peak_top_slip_m) << k;
    EXPECT_EQ(resumed.records()[k].peak_base_slip_m, monitor.records()[k].peak_base_slip_m) << k;
    EXPECT_EQ(resumed.records()[k].peak_floor_ratio_rad, monitor.records()[k].peak_floor_ratio_rad) << k;
  }
  StateWriter again;
  resumed.save_state(again);
  EXPECT_TRUE(again.bytes() == saved.bytes());
}

// A storey whose columns' feet slid and whose floor slid on the column
// tops as well: jointed kFrame, storey 1's three columns moved d = 10 mm
// along x upright, beam_1 moved 2d. Column drift nothing (standing); base
// slip d; the floor is beam_1 at lines a and b (2d) and col_c's own top
// (d): 5d/3, top slip 5d/3 - d = 2d/3, floor drift 5d/3 / h = 0.0575 rad
// (damaged). Each slip carries more than a quarter of the floor drift's
// excess (5d/3) over the column drift (kSlipShareNamed): the warning names
// both.
TEST(StoreyDrift, AFloorThatSlidOnItsColumnTopsWhileTheirFeetSlidNamesBoth) {
  Model model = jointed_frame_model();
  StoreyDriftMonitor monitor = monitor_at_rest(model);
  const double d = 0.01, h = 0.29;
  for (std::size_t m : {0, 2, 4}) model.bodies.position_m[model.member_body[m]] += Vec3(d, 0, 0);
  model.bodies.position_m[model.member_body[5]] += Vec3(2.0 * d, 0, 0);
  monitor.track(model.bodies, 0.1);
  const StoreyDriftRecord& r = monitor.records()[0];
  EXPECT_NEAR(r.peak_ratio_rad, 0.0, 1e-15);
  EXPECT_NEAR(r.peak_base_slip_m, d, 1e-15);
  EXPECT_NEAR(r.peak_top_slip_m, 2.0 * d / 3.0, 1e-15);
  EXPECT_NEAR(r.peak_floor_ratio_rad, 5.0 * d / 3.0 / h, 1e-14);
  // The cause, as the caller knows it: unknown (both named), some of the
  // column joints broken, none of them, a lone joint either way, or none at
  // all (this storey has three columns; a one-column storey's wording is
  // in test_run_warnings, the breaking cantilever).
  EXPECT_NE(monitor.slip_warning(0).find(" (events.csv lists the joints that broke; a joint soft in shear lets its "
                                         "members slide while it holds); the verdict is that of the tilt"),
            std::string::npos);
  EXPECT_NE(monitor.slip_warning(0, 2, 5).find(
                " (2 of the 5 joints holding its columns broke; events.csv lists them); the verdict"),
            std::string::npos)
      << monitor.slip_warning(0, 2, 5);
  EXPECT_NE(monitor.slip_warning(0, 0, 5).find(" (none of the joints holding its columns broke: a joint soft in shear "
                                               "lets its members slide while it holds); the verdict"),
            std::string::npos)
      << monitor.slip_warning(0, 0, 5);
  EXPECT_NE(monitor.slip_warning(0, 1, 1).find(" (the joint holding its columns broke; events.csv says when); the"),
            std::string::npos)
      << monitor.slip_warning(0, 1, 1);
  EXPECT_NE(monitor.slip_warning(0, 0, 1).find(" (the joint holding its columns did not break: a joint soft in shear"),
            std::string::npos)
      << monitor.slip_warning(0, 0, 1);
  EXPECT_NE(monitor.slip_warning(0, 0, 0).find(" (no joint holds its columns: they stand and slide on their "
                                               "contacts); the verdict"),
            std::string::npos)
      << monitor.slip_warning(0, 0, 0);
  const std::string w = monitor.slip_warning(0);
  EXPECT_NE(w.find("storey 1's floor moved 0.0575 rad of its height relative to the foundation, which would make it "
                   "damaged, while its columns tilted 0 rad (standing): the floor slid up to 6.67 mm on its column "
                   "tops and the columns' feet slid up to 10 mm on the foundation ("),
            std::string::npos)
      << w;
}

// A storey whose peak comes in the last 2 % of the run may still have been
// growing: storey 1 leaning to 0.05 rad (past half the 1/30 safety limit)
// at t = 9.9 s of a 10 s run is said to; the same peak at t = 5 s, a peak
// under half the safety limit, or a collapsed storey are not.
TEST(StoreyDrift, APeakInTheRunsLastMomentsIsSaidToBePerhapsStillGrowing) {
  auto lean_at = [](double angle, double t_s) {
    Model model = frame_model();
    StoreyDriftMonitor monitor(find_storeys(model), AssessmentDef{}, 1e-5, 1.0);
    monitor.track(model.bodies, 0.0);
    turn_about_y(model.bodies, model.member_body[0], Vec3(0, 0, 0), angle);
    turn_about_y(model.bodies, model.member_body[2], Vec3(0.5, 0, 0), angle);
    turn_about_y(model.bodies, model.member_body[4], Vec3(1.0, 0, 0), angle);
    monitor.track(model.bodies, t_s);
    return monitor;
  };
  const std::string w = lean_at(0.05, 9.9).peak_at_end_warning(0, 10.0);
  EXPECT_NE(w.find("storey 1's drift peaked at 0.04998 rad at t = 9.9 s, in the last 2 % of the run (which ended at "
                   "10 s): it may still have been growing, so its verdict (damaged) holds for this window only"),
            std::string::npos)
      << w;
  EXPECT_EQ(lean_at(0.05, 5.0).peak_at_end_warning(0, 10.0), "");
  EXPECT_EQ(lean_at(0.01, 9.9).peak_at_end_warning(0, 10.0), "");  // 0.01 < half of 1/30
  EXPECT_EQ(lean_at(0.2, 9.9).peak_at_end_warning(0, 10.0), "");   // collapsed: nothing left to grow into
}

TEST(StoreyDrift, AssessmentLimitsAreReadAndChecked) {
  TempDir dir;
  const CaseDef def = load_case_file(
      dir.write("a.yaml", std::string(kFrame) + "assessment: {safety_drift_ratio_rad: 0.02, collapse_drift_ratio_rad: 0.2}\n"));
  EXPECT_DOUBLE_EQ(def.assessment.safety_drift_ratio_rad, 0.02);
  EXPECT_DOUBLE_EQ(def.assessment.collapse_drift_ratio_rad, 0.2);
  try {
    load_case_file(dir.write("b.yaml", std::string(kFrame) + "assessment: {collapse_drift_ratio_rad: 0.01}\n"));
    FAIL() << "a collapse limit below the safety limit was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "assessment");
    EXPECT_NE(std::string(e.what()).find("must be larger than safety_drift_ratio_rad"), std::string::npos) << e.what();
  }
}

// A column pinned at its foot (a single-point joint: no moment) and tipped
// by 0.3 rad topples under gravity. Its storey (the band between its two
// ends, h = L cos 0.3) drifts L (sin(phi) - sin 0.3), which passes 0.1 h at
// phi = asin(sin 0.3 + 0.1 cos 0.3) = 0.40 rad: the run's verdict is
// collapsed, and history.csv's drift ratio is its drift over h.
TEST(StoreyDrift, RunWritesDriftColumnsAndVerdicts) {
  TempDir dir;
  const std::string text =
      "framequake_case: 1\n"
      "name: leaning\n"
      "time: {dt_s: 1.0e-4, duration_s: 0.6}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}]\n"
      "sections: [{name: col, width_m: 0.010, depth_m: 0.020}]\n"
      "nodes: [{id: a, xyz_m: [0, 0, 0]}, {id: b, xyz_m: [0.0886560, 0, 0.2866009]}]\n"  // 0.3 rad lean, L = 0.3 m
      "members: [{id: c, kind: column, nodes: [a, b], section: col, material: wood}]\n"
      "joint_types: [{name: pin, layout: single_point, normal: {law: linear, stiffness_N_per_m: 1.0e5},\n"
      "               shear: {law: linear, stiffness_N_per_m: 1.0e5}, fracture: {criterion: never}}]\n"
      "supports: [{node: a, joint_type: pin}]\n"
      "output: {folder: " + (dir.path() / "out").string() + ", frame_interval_s: 0.1, history_interval_s: 0.01}\n";
  const CaseRunReport report = run_case(load_case_file(dir.write("lean.yaml", text)), {});
  ASSERT_EQ(report.storeys.size(), 1u);
  // The column is its own storey and starts leaning: drift is measured from
  // the start, and free fall of a tipped rod adds lean every step.
  EXPECT_EQ(report.storeys[0].verdict, StoreyVerdict::Collapsed);
  EXPECT_GT(report.storeys[0].drift.collapse_time_s, 0.0);
  EXPECT_NEAR(report.storeys[0].height_m, 0.3 * std::cos(0.3), 1e-6);
  std::ifstream history(dir.path() / "out/history.csv");
  std::string line;
  std::getline(history, line);
  std::vector<std::string> header;
  {
    std::stringstream h(line);
    for (std::string cell; std::getline(h, cell, ',');) header.push_back(cell);
  }
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return std::size_t(it - header.begin());
  };
  const std::size_t dx = column("storey1_drift_x_m"), rx = column("storey1_drift_ratio_x_rad");
  column("storey1_drift_y_m");
  column("storey1_drift_ratio_y_rad");
  int rows = 0;
  double last_ratio = 0.0;
  while (std::getline(history, line)) {
    std::vector<double> v;
    std::stringstream r(line);
    for (std::string cell; std::getline(r, cell, ',');) v.push_back(std::stod(cell));
    EXPECT_NEAR(v[rx], v[dx] / report.storeys[0].height_m, 1e-9);
    last_ratio = v[rx];
    ++rows;
  }
  EXPECT_EQ(rows, 61);
  (void)last_ratio;
  // When: a rigid rod (length L, depth d in the plane of fall) pinned at its
  // end falls from theta0 with theta'^2 = a (cos theta0 - cos theta),
  // a = g L / (L^2/3 + d^2/12) (energy; moment of inertia about the pin).
  // t(theta_c) = integral of dtheta / theta', with theta = theta0 + u^2 to
  // remove the start's singularity. The pin's springs (1e5 N/m) sag by
  // m g / k = 3 micrometres, far below what the 10 ms sampling resolves.
  const double L = 0.3, d = 0.02, g = 9.80665, theta0 = 0.3;
  const double a = g * L / (L * L / 3.0 + d * d / 12.0);
  const double theta_c = std::asin(std::sin(theta0) + 0.1 * std::cos(theta0));
  const double u_max = std::sqrt(theta_c - theta0);
  const int n = 20000;
  double t_c = 0.0;
  for (int k = 0; k < n; ++k) {  // midpoint rule in u
    const double u = (k + 0.5) * u_max / n;
    t_c += 2.0 * u / std::sqrt(a * (std::cos(theta0) - std::cos(theta0 + u * u))) * (u_max / n);
  }
  // The monitor follows every step (0.1 ms), not only the 10 ms rows: the
  // first step at or past t_c, within the 1 ms the sag and the sway of
  // the pin's springs allow.
  EXPECT_GE(report.storeys[0].drift.collapse_time_s, t_c - 1e-3);
  EXPECT_LE(report.storeys[0].drift.collapse_time_s, t_c + 1e-3);
  std::ifstream summary(dir.path() / "out/summary.json");
  std::stringstream s;
  s << summary.rdbuf();
  EXPECT_NE(s.str().find("\"storeys\""), std::string::npos);
  EXPECT_NE(s.str().find("\"collapsed\""), std::string::npos) << s.str();
  EXPECT_NE(s.str().find("\"collapse_drift_ratio_rad\""), std::string::npos);
}

}  // namespace
}  // namespace fq

namespace fq {
namespace {

TEST(StoreyDrift, ResidualIsTheMeanOfTheLastSecondNotTheLastSample) {
  // Storey 1 leans by theta(t) = theta0 + a sin(2 pi t / T), tracked at
  // every step of 1 ms for 3 s (blocks of one step), T = 0.25 s: a sway
  // about a permanent lean. The trailing second holds 1000 steps over
  // exactly 4 periods, whose discrete means
  // are mean(sin) = 0 and mean(sin^2) = 1/2, so the mean drift ratio
  // sin(theta) is sin(theta0) (1 - a^2 / 4) up to O(a^4) (here 1e-13 of
  // it). The run ends at a crest, where the last sample is sin(theta0 + a).
  const double theta0 = 0.01, a = 1e-3, period = 0.25;
  Model model = frame_model();
  const Model fresh = frame_model();
  StoreyDriftMonitor monitor(find_storeys(model), AssessmentDef{}, 1e-3, 1.0);  // steps of 1 ms
  const BodyId cols[] = {model.member_body[0], model.member_body[2], model.member_body[4]};
  const double pivots_x[] = {0.0, 0.5, 1.0};
  const int samples = 3000;
  const double t_end = 3.0 + period / 4.0;  // sin(2 pi t_end / T) = 1
  for (int k = 0; k <= samples; ++k) {
    const double t = t_end - 1e-3 * double(samples - k);
    const double theta = theta0 + a * std::sin(2.0 * M_PI * t / period);
    for (int c = 0; c < 3; ++c) {
      model.bodies.position_m[cols[c]] = fresh.bodies.position_m[cols[c]];
      model.bodies.orientation[cols[c]] = fresh.bodies.orientation[cols[c]];
    }
    model.bodies.update_rotations();
    for (int c = 0; c < 3; ++c) turn_about_y(model.bodies, cols[c], Vec3(pivots_x[c], 0, 0), theta);
    monitor.track(model.bodies, t);
    monitor.sample(model.bodies, k, t);
  }
  const StoreyDriftRecord& r = monitor.records()[0];
  EXPECT_NEAR(r.final_ratio_x_rad, std::sin(theta0 + a), 1e-12);
  EXPECT_NEAR(r.residual_ratio_x_rad, std::sin(theta0) * (1.0 - a * a / 4.0), 1e-12);
  EXPECT_NEAR(r.residual_ratio_y_rad, 0.0, 1e-15);
  EXPECT_NEAR(r.residual_window_s, 0.999, 1e-9);
}

// The residual's window in blocks of whole steps. At dt = 1e-4 s the second
// is 10 000 steps, summed in 1000 blocks of 10. After steps 0..25 004 the
// window holds the last 1000 complete blocks (steps 15 000..24 999) and the
// open block (25 000..25 004): the mean of the drift ratio over steps
// 15 000..25 004, summed here directly, step by step. The lean grows with
// the step, theta_k = 1e-6 k, so a window off by one block would be off by
// 1e-6 x 10 / 2 in theta, far above the 1e-12 allowed.
TEST(StoreyDrift, ResidualIsTheMeanOverTheLastSecondsStepsInBlocks) {
  Model model = frame_model();
  const Model fresh = frame_model();
  const double dt = 1e-4;
  StoreyDriftMonitor monitor(find_storeys(model), AssessmentDef{}, dt, 1.0);
  const BodyId cols[] = {model.member_body[0], model.member_body[2], model.member_body[4]};
  const double pivots_x[] = {0.0, 0.5, 1.0};
  const int last = 25004, first_in_window = 15000;
  double sum = 0.0;
  for (int k = 0; k <= last; ++k) {
    const double theta = 1e-6 * k;
    for (int c = 0; c < 3; ++c) {
      model.bodies.position_m[cols[c]] = fresh.bodies.position_m[cols[c]];
      model.bodies.orientation[cols[c]] = fresh.bodies.orientation[cols[c]];
    }
    model.bodies.update_rotations();
    for (int c = 0; c < 3; ++c) turn_about_y(model.bodies, cols[c], Vec3(pivots_x[c], 0, 0), theta);
    monitor.track(model.bodies, dt * k);
    if (k >= first_in_window) sum += storey_drift_m(monitor.storeys()[0], model.bodies).x() / monitor.storeys()[0].height_m();
  }
  const StoreyDriftRecord& r = monitor.records()[0];
  EXPECT_NEAR(r.residual_ratio_x_rad, sum / double(last - first_in_window + 1), 1e-12);
  EXPECT_NEAR(r.residual_window_s, dt * double(last - first_in_window), 1e-12);
}

// A run that became unstable is not assessed: summary.json gives its
// storeys the verdict "not_assessed" (it said "standing", from the few
// steps before the blow-up; stress probe). A support joint of 1e9 N/m on a
// 0.054 kg column has a stable step near 1e-6 s; forced at 1e-5 s it blows
// up within steps.
TEST(StoreyDrift, AnUnstableRunIsNotAssessed) {
  TempDir dir;
  const std::string text =
      "framequake_case: 1\n"
      "time: {dt_s: 1.0e-5, duration_s: 0.01}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}]\n"
      "sections: [{name: col, width_m: 0.02, depth_m: 0.02}]\n"
      "nodes: [{id: a, xyz_m: [0, 0, 0]}, {id: b, xyz_m: [0, 0, 0.3]}]\n"
      "members: [{id: c, kind: column, nodes: [a, b], section: col, material: wood}]\n"
      "joint_types: [{name: stiff, layout: four_corner, normal: {law: linear, stiffness_N_per_m: 1.0e9},\n"
      "               shear: {law: linear, stiffness_N_per_m: 1.0e9}, fracture: {criterion: never}}]\n"
      "supports: [{node: a, joint_type: stiff}]\n"
      "output: {folder: " + (dir.path() / "out").string() + ", frame_interval_s: 0.01, history_interval_s: 0.001}\n";
  CaseRunOptions options;
  options.allow_unstable_time_step = true;
  const CaseRunReport report = run_case(load_case_file(dir.write("stiff.yaml", text)), options);
  ASSERT_EQ(report.result.status, RunStatus::Unstable);
  std::ifstream in(dir.path() / "out/summary.json");
  std::stringstream text_of;
  text_of << in.rdbuf();
  const std::string summary = text_of.str();
  EXPECT_NE(summary.find("\"verdict\":\"not_assessed\""), std::string::npos) << summary;
  EXPECT_EQ(summary.find("\"verdict\":\"standing\""), std::string::npos) << summary;
}

// A column standing on a linear support joint, shaken for 0.2 s by a 5 Hz
// sine of 3 m/s^2, sways about its foot. Its peak drift ratio, the time
// of that peak and the verdict must not depend on how often history rows
// are written: a run with a row every 13 ms must report exactly what a run
// with a row at every step does, and that is the largest drift ratio of
// the every-step rows (the independent reference: the rows are the drift
// itself, written by the history, not by the peak tracking). The coarse
// run's own rows miss the peak, or the check would prove nothing. Before
// the peaks were taken at every step they were taken at rows only
// (geometry probe: a storey reported standing at 50 ms rows and damaged at
// 1 ms rows of one and the same run).
// Then the coarse run is stopped after its peak with a checkpoint and
// resumed: the resumed run must report the same peak, though no row before
// the stop holds it (the peaks travel in the checkpoint).
std::string swaying_column_case(const fs::path& out, double history_interval_s) {
  std::ostringstream interval;
  interval << history_interval_s;
  return "framequake_case: 1\n"
         "name: sway\n"
         "time: {dt_s: 1.0e-5, duration_s: 0.2}\n"
         "materials: [{name: wood, density_kg_per_m3: 450}]\n"
         "sections: [{name: col, width_m: 0.02, depth_m: 0.02}]\n"
         "nodes: [{id: a, xyz_m: [0, 0, 0]}, {id: b, xyz_m: [0, 0, 0.3]}]\n"
         "members: [{id: c, kind: column, nodes: [a, b], section: col, material: wood}]\n"
         "joint_types: [{name: base, layout: four_corner, normal: {law: linear, stiffness_N_per_m: 1.0e4},\n"
         "               shear: {law: linear, stiffness_N_per_m: 1.0e4}, fracture: {criterion: never}}]\n"
         "supports: [{node: a, joint_type: base}]\n"
         "ground_motion:\n"
         "  components: [{file: shake.txt, format: two_column, axis: x}]\n"
         "output: {folder: " + out.string() + ", frame_interval_s: 1.0, history_interval_s: " + interval.str() + "}\n";
}

// Storey 1's drift ratio (x, y) of every row of a history.csv.
std::vector<Eigen::Vector2d> storey1_ratio_rows(const fs::path& history) {
  std::ifstream in(history);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream h(line);
    for (std::string cell; std::getline(h, cell, ',');) header.push_back(cell);
  }
  const auto column = [&](const std::string& name) {
    return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t rx = column("storey1_drift_ratio_x_rad"), ry = column("storey1_drift_ratio_y_rad");
  EXPECT_LT(std::max(rx, ry), header.size());
  std::vector<Eigen::Vector2d> rows;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream r(line);
    for (std::string cell; std::getline(r, cell, ',');) v.push_back(std::stod(cell));
    rows.emplace_back(v[rx], v[ry]);
  }
  return rows;
}

double largest_storey1_ratio_of_rows(const fs::path& history) {
  double peak = 0.0;
  for (const Eigen::Vector2d& r : storey1_ratio_rows(history)) peak = std::max(peak, std::hypot(r.x(), r.y()));
  return peak;
}

double mean_storey1_ratio_x_of_rows(const fs::path& history) {
  const std::vector<Eigen::Vector2d> rows = storey1_ratio_rows(history);
  double sum = 0.0;
  for (const Eigen::Vector2d& r : rows) sum += r.x();
  return rows.empty() ? 0.0 : sum / double(rows.size());
}

// Stops a run once its simulated time reaches `at_s` (asked every 1000 steps).
class StopAt final : public StepObserver {
 public:
  StopAt(double at_s, std::atomic<bool>* stop) : at_s_(at_s), stop_(stop) {}
  void on_sample(const Simulation& sim) override {
    if (sim.time_s() >= at_s_) stop_->store(true);
  }

 private:
  double at_s_;
  std::atomic<bool>* stop_;
};

// A run stopped early felt the ground motion only up to the stop: its
// summary's ground_motion block and its report's PGA say so (they gave the
// planned window; new-features probe). A ramp record a(t) = 10 t m/s^2
// over 0.3 s, the run stopped at 0.05 s: 0.05 record seconds applied, peak
// 0.5 m/s^2.
TEST(StoreyDrift, AStoppedRunReportsTheGroundMotionItFelt) {
  TempDir dir;
  {
    std::ofstream record(dir.path() / "shake.txt");
    for (int k = 0; k <= 300; ++k) record << 0.001 * k << " " << 0.01 * k << "\n";
  }
  std::atomic<bool> stop{false};
  StopAt stopper(0.05, &stop);
  CaseRunOptions options;
  options.progress = &stopper;
  options.stop_requested = &stop;
  const CaseRunReport r =
      run_case(load_case_file(dir.write("ramp.yaml", swaying_column_case(dir.path() / "out", 0.01))), options);
  ASSERT_EQ(r.result.status, RunStatus::Stopped);
  ASSERT_NEAR(r.result.simulated_s, 0.05, 1e-12);
  EXPECT_NEAR(r.peak_ground_acceleration_mps2, 0.5, 1e-9);
  std::ifstream in(dir.path() / "out" / "summary.json");
  std::stringstream summary;
  summary << in.rdbuf();
  EXPECT_NE(summary.str().find("\"window_length_s\":0.05}"), std::string::npos) << summary.str();
  EXPECT_NE(summary.str().find("\"peak_horizontal_mps2\":0.5,"), std::string::npos) << summary.str();
}

// The residual's window is 3 RECORD seconds: at a ground motion time scale
// of 0.05 it is 0.15 simulated s of the 0.2 s run (to within two blocks of
// 15 steps and a step, class comment), and the residual is the mean of the
// every-step rows in it. With a window of a fixed simulated second it was
// the mean of the whole run, so a model and its full-scale original,
// alike by similitude, averaged different parts of their response
// (geometry probe, 2026-11-27). Frame B's record runs at 0.3162: 0.9486 s.
TEST(StoreyDrift, TheResidualsWindowIsInRecordSeconds) {
  TempDir dir;
  {
    std::ofstream record(dir.path() / "shake.txt");
    for (int k = 0; k <= 300; ++k)
      record << 0.001 * k << " " << 60.0 * std::sin(2.0 * M_PI * 5.0 * 0.001 * k) << "\n";
  }
  std::string text = swaying_column_case(dir.path() / "out", 1e-5);
  const std::string gm = "ground_motion:\n";
  text.replace(text.find(gm), gm.size(), gm + "  time_scale: 0.05\n");
  const CaseDef def = load_case_file(dir.write("scaled.yaml", text));
  EXPECT_NEAR(residual_drift_window_s(def), 0.15, 1e-15);
  const CaseRunReport r = run_case(def, {});
  ASSERT_EQ(r.storeys.size(), 1u);
  const StoreyDriftRecord& d = r.storeys[0].drift;
  EXPECT_NEAR(d.residual_window_s, 0.15, 2 * 15e-5 + 1e-5);
  // The mean of the rows (one per step, t = 0 .. 0.2 s) in the window.
  const std::vector<Eigen::Vector2d> rows = storey1_ratio_rows(dir.path() / "out/history.csv");
  ASSERT_EQ(rows.size(), 20001u);
  const std::size_t in_window = std::size_t(std::llround(d.residual_window_s / 1e-5)) + 1;
  double sum = 0.0, largest = 0.0;
  for (std::size_t k = rows.size() - in_window; k < rows.size(); ++k) sum += rows[k].x();
  for (const Eigen::Vector2d& row : rows) largest = std::max(largest, std::abs(row.x()));
  ASSERT_GT(largest, 1e-4) << "the column must sway";
  EXPECT_NEAR(d.residual_ratio_x_rad, sum / double(in_window), 1e-9 * largest);
  EXPECT_NEAR(residual_drift_window_s(load_case_file(fs::path(FQ_SOURCE_DIR) / "cases/frame_B.yaml")), 3.0 * 0.3162,
              1e-15);
}

TEST(StoreyDrift, PeaksAreTakenAtEveryStepWhateverTheHistoryIntervalAndSurviveAResume) {
  TempDir dir;
  {
    std::ofstream record(dir.path() / "shake.txt");
    for (int k = 0; k <= 300; ++k)
      record << 0.001 * k << " " << 3.0 * std::sin(2.0 * M_PI * 5.0 * 0.001 * k) << "\n";
  }
  const CaseRunReport every_step =
      run_case(load_case_file(dir.write("fine.yaml", swaying_column_case(dir.path() / "fine", 1e-5))), {});
  const CaseRunReport coarse =
      run_case(load_case_file(dir.write("coarse.yaml", swaying_column_case(dir.path() / "coarse", 0.013))), {});
  ASSERT_EQ(every_step.storeys.size(), 1u);
  ASSERT_EQ(coarse.storeys.size(), 1u);
  const StoreyDriftRecord& fine_peak = every_step.storeys[0].drift;
  const StoreyDriftRecord& coarse_peak = coarse.storeys[0].drift;
  const double reference = largest_storey1_ratio_of_rows(dir.path() / "fine/history.csv");
  ASSERT_GT(reference, 1e-3) << "the column must sway";
  EXPECT_EQ(fine_peak.peak_ratio_rad, reference);
  EXPECT_EQ(coarse_peak.peak_ratio_rad, reference);
  EXPECT_EQ(coarse_peak.peak_ratio_x_rad, fine_peak.peak_ratio_x_rad);
  EXPECT_EQ(coarse_peak.peak_time_s, fine_peak.peak_time_s);
  EXPECT_LT(largest_storey1_ratio_of_rows(dir.path() / "coarse/history.csv"), reference * (1.0 - 1e-6))
      << "the 13 ms rows must miss the peak for this test to prove anything";
  // The residual too: the run is shorter than the 3 s window, so it is the
  // mean of the drift ratio over every step, the mean of the every-step
  // rows (written to 9 significant digits or more).
  const double mean_of_rows = mean_storey1_ratio_x_of_rows(dir.path() / "fine/history.csv");
  EXPECT_NEAR(fine_peak.residual_ratio_x_rad, mean_of_rows, 1e-9 * reference);
  EXPECT_EQ(coarse_peak.residual_ratio_x_rad, fine_peak.residual_ratio_x_rad);
  EXPECT_EQ(coarse_peak.residual_window_s, fine_peak.residual_window_s);

  // Stopped after the peak, at a time no 13 ms row falls on, and resumed.
  const double stop_s = fine_peak.peak_time_s + 0.005;
  ASSERT_LT(stop_s, 0.19);
  std::atomic<bool> stop{false};
  StopAt stopper(stop_s, &stop);
  CaseRunOptions first;
  first.checkpoint_every_s = 0.05;
  first.progress = &stopper;
  first.stop_requested = &stop;
  const CaseDef resumed_def = load_case_file(dir.write("resumed.yaml", swaying_column_case(dir.path() / "resumed", 0.013)));
  const CaseRunReport stopped = run_case(resumed_def, first);
  ASSERT_EQ(stopped.result.status, RunStatus::Stopped);
  ASSERT_LT(largest_storey1_ratio_of_rows(dir.path() / "resumed/history.csv"), reference * (1.0 - 1e-6))
      << "the rows before the stop must not hold the peak";
  const CaseRunReport resumed = resume_case(dir.path() / "resumed", {});
  ASSERT_EQ(resumed.result.status, RunStatus::Completed);
  ASSERT_EQ(resumed.storeys.size(), 1u);
  EXPECT_EQ(resumed.storeys[0].drift.peak_ratio_rad, reference);
  EXPECT_EQ(resumed.storeys[0].drift.peak_time_s, fine_peak.peak_time_s);
  EXPECT_EQ(resumed.storeys[0].drift.residual_ratio_x_rad, fine_peak.residual_ratio_x_rad);
  EXPECT_EQ(resumed.storeys[0].drift.final_ratio_x_rad, coarse_peak.final_ratio_x_rad);
}

}  // namespace
}  // namespace fq
