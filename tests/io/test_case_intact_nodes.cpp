// contact.intact_nodes (io/case_def.h, cases/README.md "Contact across
// intact joints"): which contacts act across connections that still hold.
// Expected values are closed forms of statics (springs in parallel, a
// column's weight carried by its joint's four normal springs alone) and the
// definition of the modes; none is taken from a run of the program.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "dem_core/state_io.h"
#include "io/case_file.h"
#include "io/case_runner.h"
#include "io_test_util.h"

namespace fq {
namespace {

using test::TempDir;

constexpr double kG = 9.80665;  // m/s^2, the engine's default gravity

// The end of every case here: a support at node base, the ground at z = 0, and
// contacts of 1e6 N/m per point under the given contact.intact_nodes.
std::string supported_on_the_ground(const std::string& mode) {
  return "supports: [{node: base}]\n"
         "ground: {level_m: 0.0}\n"
         "contact:\n"
         "  intact_nodes: " + mode + "\n"
         "  ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.3, friction_coefficient: 0.4}\n"
         "  default: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.3, friction_coefficient: 0.4}\n";
}

// A 10 x 10 x 200 mm column of wood (450 kg/m^3) on a support joint of four
// corner points, each with a linear normal spring of 1e5 N/m, on a ground
// whose contact has 1e6 N/m.
std::string supported_column(const std::string& mode) {
  return "framequake_case: 1\n"
         "time: {dt_s: 1.0e-5, duration_s: 0.1}\n"
         "materials: [{name: wood, density_kg_per_m3: 450}]\n"
         "sections: [{name: s, width_m: 0.01, depth_m: 0.01}]\n"
         "nodes:\n"
         "  - {id: base, xyz_m: [0, 0, 0]}\n"
         "  - {id: top, xyz_m: [0, 0, 0.2]}\n"
         "members:\n"
         "  - {id: post, kind: column, nodes: [base, top], section: s, material: wood}\n"
         "joint_types:\n"
         "  - name: tenon\n"
         "    layout: four_corner\n"
         "    normal: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
         "    shear: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
         "joints: {support_type: tenon}\n"
         + supported_on_the_ground(mode);
}

// A tenon's normal springs that crush under a 10 x 10 x 200 mm wooden
// column (0.088 N): deleted past 0.008 N (1e-5 m), so four of them hold at
// most 0.032 N, a third of its weight.
const std::string kCrushingNormal =
    "    normal:\n"
    "      law: trilinear\n"
    "      reference_length_m: 0.01\n"
    "      yield_strain_tension: 0.0001\n"
    "      yield_force_tension_N: 0.005\n"
    "      ultimate_strain_tension: 0.001\n"
    "      ultimate_force_tension_N: 0.008\n"
    "      yield_strain_compression: 0.0001\n"
    "      yield_force_compression_N: 0.005\n"
    "      ultimate_strain_compression: 0.001\n"
    "      ultimate_force_compression_N: 0.008\n"
    "      damping_ratio: 0.05\n";

struct Settled {
  double weight_N = 0.0;
  double settlement_m = 0.0;  // downward
  double ground_force_N = 0.0;
  std::size_t contacts = 0;
  double balance_error = 0.0;
};

Settled settle(const std::string& mode) {
  TempDir dir;
  Scene scene = build_scene(load_case_file(dir.write("post.yaml", supported_column(mode))));
  Simulation& sim = *scene.simulation;
  const BodyId post = 1;
  EXPECT_EQ(sim.bodies().info[post].name, "post");
  const double z0_m = sim.bodies().position_m[post].z();
  const RunResult r = sim.run();
  EXPECT_EQ(r.status, RunStatus::Completed);
  Settled s;
  s.weight_N = sim.bodies().mass_kg[post] * kG;
  s.settlement_m = z0_m - sim.bodies().position_m[post].z();
  s.ground_force_N = scene.contacts->ground_normal_force_N();
  s.contacts = scene.contacts->contact_count();
  s.balance_error = sim.ledger().balance_error_relative();
  return s;
}

// The support joint's four normal springs (k = 1e5 N/m each, along the
// column) carry the column's weight alone while the ground is kept away
// (none): the column settles by m g / (4 k) (2.2e-7 m). The settling time is
// far inside the run: omega = sqrt(4 k / m) = 6.7e3 rad/s, and the group's
// damping ratio 0.05 sqrt(4) = 0.1 decays the drop's oscillation by e every
// 1.5 ms (cases/README.md, damping_ratio), 67 times in 0.1 s.
TEST(IntactNodes, UnderNoneASupportedColumnRestsOnItsJointAlone) {
  const Settled s = settle("none");
  EXPECT_EQ(s.contacts, 0u);
  EXPECT_EQ(s.ground_force_N, 0.0);
  EXPECT_NEAR(s.settlement_m, s.weight_N / (4.0 * 1.0e5), 1e-3 * s.weight_N / (4.0 * 1.0e5));
  EXPECT_LT(s.balance_error, 1e-6);
}

// With the ground bearing (touch, the default, and ground_only) the foot's
// contact and the joint's springs carry the weight in parallel: the ground
// force and the springs' 4 k d add up to m g (statics), and the ground, a
// face contact of four points summing to 4 k_n = 4e6 N/m (contacts/README.md)
// against the joint's 4 k = 4e5 N/m, takes 4e6 / 4.4e6 = 10/11 of it.
TEST(IntactNodes, UnderTouchAndGroundOnlyTheGroundBearsBesideTheJoint) {
  for (const char* mode : {"touch", "ground_only"}) {
    SCOPED_TRACE(mode);
    const Settled s = settle(mode);
    EXPECT_GT(s.contacts, 0u);
    EXPECT_NEAR(s.ground_force_N, s.weight_N * 10.0 / 11.0, 1e-3 * s.weight_N);
    EXPECT_NEAR(s.ground_force_N + 4.0 * 1.0e5 * s.settlement_m, s.weight_N, 1e-3 * s.weight_N);
  }
}

// Under none a supported column whose support tenon crushes (kCrushingNormal)
// stands on the ground from the break on: it starts from the overlap its
// tenon let it sink into the ground (reference depth, contact_system.h), so the ground
// then carries its weight (statics) and the break adds no energy. Started
// from zero reference instead, the contact would push the foot out with
// k d^2 / 2 per point, about 5e-5 J against the 9e-3 J of the energy scale.
TEST(IntactNodes, UnderNoneAColumnWhoseSupportBreaksStandsOnTheGroundFromItsOverlap) {
  std::string text = supported_column("none");
  const std::string weak_normal =
      kCrushingNormal +
      "    fracture: {criterion: any_spring_deleted}\n";
  const std::string strong_normal = "    normal: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n";
  const auto at = text.find(strong_normal);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, strong_normal.size(), weak_normal);
  TempDir dir;
  Scene scene = build_scene(load_case_file(dir.write("post.yaml", text)));
  Simulation& sim = *scene.simulation;
  const BodyId post = 1;
  const double z0_m = sim.bodies().position_m[post].z();
  // Fastest upward motion after the break, and the downward speed at it.
  double break_time_s = -1.0, speed_at_break_mps = 0.0, fastest_up_mps = 0.0;
  while (sim.steps_done() < sim.total_steps()) {
    ASSERT_TRUE(sim.step());
    const double vz = sim.bodies().velocity_mps[post].z();
    if (break_time_s < 0.0 && scene.joints->joint_status(0) == JointStatus::Broken) {
      break_time_s = sim.time_s();
      speed_at_break_mps = std::abs(vz);
    }
    if (break_time_s >= 0.0) fastest_up_mps = std::max(fastest_up_mps, vz);
  }
  const RunResult r = sim.run();
  EXPECT_EQ(r.status, RunStatus::Completed);
  ASSERT_EQ(scene.joints->joint_status(0), JointStatus::Broken);
  // The crushing column meets the ground at its own speed (about 0.01 m/s)
  // and rebounds with at most the restitution (0.3) of it; 0.5 leaves room
  // for the gravity it gains during the ~1 ms contact. Kicked out of a 1e-5 m
  // overlap by its four corners it would leave at sqrt(4 k d^2 / m), about
  // 0.2 m/s (0.12 m/s measured with the soft start taken out).
  EXPECT_GT(speed_at_break_mps, 0.0);
  EXPECT_LT(fastest_up_mps, 0.5 * speed_at_break_mps);
  const double weight_N = sim.bodies().mass_kg[post] * kG;
  EXPECT_NEAR(scene.contacts->ground_normal_force_N(), weight_N, 0.02 * weight_N);
  EXPECT_LT(z0_m - sim.bodies().position_m[post].z(), 1e-4);
  EXPECT_LT(sim.ledger().balance_error_relative(), 1e-5);
}

// A post and a light brace footed at the same support node, each with its
// own crushing support tenon and joined to each other by a soft joint (a
// triangle of joints at one node). When the post's support breaks, the post
// must stand on the ground from then on, whatever the brace's support does:
// the post and the ground are joined directly, so that joint alone decides
// (a hold through the brace kept the post falling through the ground for
// 11 ms, 0.64-0.70 mm deep, until the brace's support broke too; review probe).
TEST(IntactNodes, UnderNoneAPostWhoseSupportBreaksStandsOnTheGroundBesideASupportedBrace) {
  const std::string text =
      "framequake_case: 1\n"
      "time: {dt_s: 2.0e-6, duration_s: 0.05}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}, {name: light, density_kg_per_m3: 45}]\n"
      "sections: [{name: s, width_m: 0.01, depth_m: 0.01}, {name: b, width_m: 0.005, depth_m: 0.005}]\n"
      "nodes:\n"
      "  - {id: base, xyz_m: [0, 0, 0]}\n"
      "  - {id: top, xyz_m: [0, 0, 0.2]}\n"
      "  - {id: tip, xyz_m: [0.1, 0, 0.1]}\n"
      "members:\n"
      "  - {id: post, kind: column, nodes: [base, top], section: s, material: wood}\n"
      "  - {id: brace, kind: beam, nodes: [base, tip], section: b, material: light, trim_m: [0.012, 0]}\n"
      "joint_types:\n"
      "  - name: soft\n"
      "    layout: four_corner\n"
      "    normal: {law: linear, stiffness_N_per_m: 1.0, damping_ratio: 0.05}\n"
      "    shear: {law: linear, stiffness_N_per_m: 1.0, damping_ratio: 0.05}\n"
      "  - name: crush\n"
      "    layout: four_corner\n" +
      kCrushingNormal +
      "    shear: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
      "    fracture: {criterion: any_spring_deleted}\n"
      "joints: {support_type: crush, rules: [{kinds: [column, beam], type: soft}]}\n" +
      supported_on_the_ground("none");
  TempDir dir;
  Scene scene = build_scene(load_case_file(dir.write("post_and_brace.yaml", text)));
  Simulation& sim = *scene.simulation;
  const BodyId post = 1;
  ASSERT_EQ(sim.bodies().info[post].name, "post");
  std::size_t post_support = scene.joint_names.size();
  for (std::size_t j = 0; j < scene.joint_names.size(); ++j)
    if (scene.joint_names[j] == "base:ground-post") post_support = j;
  ASSERT_LT(post_support, scene.joint_names.size());
  // Lowest corner of the post (m): an upright 10 x 10 x 200 mm box.
  const auto lowest_z = [&] { return sim.bodies().position_m[post].z() - 0.1; };
  double deepest_after_break_m = 0.0;
  bool broken = false;
  while (sim.steps_done() < sim.total_steps()) {
    ASSERT_TRUE(sim.step());
    broken = broken || scene.joints->joint_status(post_support) == JointStatus::Broken;
    if (broken) deepest_after_break_m = std::min(deepest_after_break_m, lowest_z());
  }
  ASSERT_TRUE(broken) << "the post's support must crush under its weight";
  // At most the crush it had at the break (1e-5 m, the tenon's ultimate
  // deformation) and m g / (4 k_n) beyond it: far from the 0.64-0.70 mm of a post
  // that fell through.
  EXPECT_GT(deepest_after_break_m, -5e-5);
  double ground_on_post_N = 0.0;
  for (const ContactPoint& c : scene.contacts->contacts())
    if (c.body_b == post && c.body_a == 0) ground_on_post_N += c.force_N().z();
  const double weight_N = sim.bodies().mass_kg[post] * kG;
  EXPECT_NEAR(ground_on_post_N, weight_N, 0.05 * weight_N);
}

// A node whose hub is a beam: column1 below, column2 on top of it, both
// tenoned into the beam (joints.hub_kind: beam), so the two columns touch end
// to end without a joint between them. Column2's tenon is weak in
// compression (kCrushingNormal), so under ground_only, with nothing else
// under it, it crushes and
// breaks within milliseconds; only then may the columns touch.
std::string stacked_columns(const std::string& mode) {
  return "framequake_case: 1\n"
         "time: {dt_s: 1.0e-5, duration_s: 0.3}\n"
         "materials: [{name: wood, density_kg_per_m3: 450}]\n"
         "sections: [{name: s, width_m: 0.01, depth_m: 0.01}]\n"
         "nodes:\n"
         "  - {id: base, xyz_m: [0, 0, 0]}\n"
         "  - {id: mid, xyz_m: [0, 0, 0.2]}\n"
         "  - {id: top, xyz_m: [0, 0, 0.4]}\n"
         "  - {id: tip, xyz_m: [0.1, 0, 0.2]}\n"
         "members:\n"
         "  - {id: beam, kind: beam, nodes: [mid, tip], section: s, material: wood, trim_m: [0.005, 0]}\n"
         "  - {id: column1, kind: column, nodes: [base, mid], section: s, material: wood}\n"
         "  - {id: column2, kind: column, nodes: [mid, top], section: s, material: wood}\n"
         "joint_types:\n"
         "  - name: strong\n"
         "    layout: four_corner\n"
         "    normal: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
         "    shear: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
         "  - name: weak\n"
         "    layout: four_corner\n"
         + kCrushingNormal +
         "    shear: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
         "    fracture: {criterion: any_spring_deleted}\n"
         "joints:\n"
         "  hub_kind: beam\n"
         "  default_type: strong\n"
         "  support_type: strong\n"
         "  overrides: [{node: mid, members: [column2, beam], type: weak}]\n"
         + supported_on_the_ground(mode);
}

bool touching(const ContactSystem& contacts, BodyId a, BodyId b) {
  for (const ContactPoint& c : contacts.contacts())
    if ((c.body_a == a && c.body_b == b) || (c.body_a == b && c.body_b == a)) return true;
  return false;
}

TEST(IntactNodes, ColumnsJoinedThroughAHubTouchOnlyOnceATenonBreaks) {
  TempDir dir;
  Scene scene = build_scene(load_case_file(dir.write("stack.yaml", stacked_columns("ground_only"))));
  Simulation& sim = *scene.simulation;
  const BodyId column1 = 2, column2 = 3;
  ASSERT_EQ(sim.bodies().info[column1].name, "column1");
  ASSERT_EQ(sim.bodies().info[column2].name, "column2");
  // The weak tenon: column2 into the beam at mid.
  std::size_t weak = scene.joint_names.size();
  for (std::size_t j = 0; j < scene.joint_names.size(); ++j)
    if (scene.joint_types[j] == "weak") weak = j;
  ASSERT_LT(weak, scene.joint_names.size());
  const double z0_m = sim.bodies().position_m[column2].z();

  double break_time_s = -1.0;
  bool touched_while_held = false;
  while (sim.steps_done() < sim.total_steps()) {
    ASSERT_TRUE(sim.step());
    const bool held = scene.joints->joint_status(weak) != JointStatus::Broken;
    if (held && touching(*scene.contacts, column1, column2)) touched_while_held = true;
    if (!held && break_time_s < 0.0) break_time_s = sim.time_s();
  }
  const RunResult done = sim.run();
  EXPECT_EQ(done.status, RunStatus::Completed);
  EXPECT_FALSE(touched_while_held) << "columns joined through the beam touched while both tenons held";
  ASSERT_GT(break_time_s, 0.0) << "the weak tenon must crush under column2's weight";
  EXPECT_LT(break_time_s, 0.05);

  // After the break column2 stands on column1 through contact: the contact
  // between them carries its weight (statics; 0.25 s after the break, with
  // the contact's restitution 0.3, the drop has died out), and it has not
  // fallen through: it started from the overlap the joint had let it sink
  // (reference depth) and sank at most m g / (4 k_n) (2.2e-8 m) further.
  ASSERT_TRUE(touching(*scene.contacts, column1, column2));
  double carried_N = 0.0;
  for (const ContactPoint& c : scene.contacts->contacts())
    if ((c.body_a == column1 && c.body_b == column2) || (c.body_a == column2 && c.body_b == column1))
      carried_N += std::abs(c.force_N().z());
  const double weight_N = sim.bodies().mass_kg[column2] * kG;
  EXPECT_NEAR(carried_N, weight_N, 0.02 * weight_N);
  EXPECT_LT(z0_m - sim.bodies().position_m[column2].z(), 1e-4);
  // The release adds no energy (the pair starts from its overlap, contact_system.h).
  EXPECT_LT(sim.ledger().balance_error_relative(), 1e-5);
}

// A run resumed from a checkpoint taken while the weak tenon still holds
// releases the held pair at the same step as the uninterrupted run, and one
// resumed after the release keeps it released; both end in the same state,
// bit for bit: the checkpoint carries the bonded pairs, the scene rebuilt
// from the case carries which joints hold them.
TEST(IntactNodes, AResumedRunReleasesTheHeldPairAsTheUninterruptedOne) {
  TempDir dir;
  const CaseDef def = load_case_file(dir.write("stack.yaml", stacked_columns("ground_only")));
  Scene reference = build_scene(def);
  const RunResult r = reference.simulation->run();
  ASSERT_EQ(r.status, RunStatus::Completed);
  std::int64_t break_step = -1;
  for (const Event& e : reference.simulation->events().all())
    if (e.kind == EventKind::JointBroken) break_step = e.step;
  ASSERT_GT(break_step, 50) << "the first checkpoint must come before the tenon breaks";
  // Before the break (the scene rebuilt from the case holds the pair) and
  // 200 steps after it (the checkpoint must say the pair was released: a
  // freshly built scene still holds it).
  for (const std::int64_t checkpoint_step : {std::int64_t(50), break_step + 200}) {
    SCOPED_TRACE(checkpoint_step);
    Scene first = build_scene(def);
    for (std::int64_t k = 0; k < checkpoint_step; ++k) ASSERT_TRUE(first.simulation->step());
    StateWriter saved;
    first.simulation->save_state(saved);
    Scene resumed = build_scene(def);
    StateReader in(saved.bytes());
    resumed.simulation->load_state(in);
    const RunResult rest = resumed.simulation->run();
    ASSERT_EQ(rest.status, RunStatus::Completed);
    EXPECT_EQ(resumed.simulation->state_hash(), reference.simulation->state_hash());
    EXPECT_TRUE(touching(*resumed.contacts, 2, 3));
  }
}

// Under touch, the default, the same columns bear on each other end to end
// from the first steps: their contact is part of the intact frame.
TEST(IntactNodes, UnderTouchColumnsJoinedThroughAHubBearOnEachOther) {
  TempDir dir;
  Scene scene = build_scene(load_case_file(dir.write("stack.yaml", stacked_columns("touch"))));
  Simulation& sim = *scene.simulation;
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(sim.step());
  EXPECT_TRUE(touching(*scene.contacts, 2, 3));
}

// The mode is a choice of model that changes results: a run's summary.json
// and `info` say which one it ran.
TEST(IntactNodes, SummaryAndInfoNameTheMode) {
  for (const char* mode : {"touch", "ground_only", "none"}) {
    SCOPED_TRACE(mode);
    TempDir dir;
    const CaseDef def = load_case_file(dir.write("post.yaml", supported_column(mode)));
    CaseRunOptions options;
    options.output_folder = dir.path() / "out";
    (void)run_case(def, options);
    const std::string summary = test::file_text(dir.path() / "out" / "summary.json");
    EXPECT_NE(summary.find(std::string("\"contact_intact_nodes\": \"") + mode + "\""), std::string::npos);
    std::ostringstream info;
    describe_case(def, info);
    EXPECT_NE(info.str().find(std::string("contacts    across intact joints: ") + mode + " ("), std::string::npos)
        << info.str();
  }
}

TEST(IntactNodes, HoldingAPairNeedsTwoJointsWithOneCommonBody) {
  TempDir dir;
  Scene scene = build_scene(load_case_file(dir.write("stack.yaml", stacked_columns("touch"))));
  ASSERT_EQ(scene.joints->joint_count(), 3u);  // support, beam-column1, beam-column2
  EXPECT_THROW(scene.joints->hold_pair_through(0, 0), std::invalid_argument);
  EXPECT_THROW(scene.joints->hold_pair_through(0, 7), std::invalid_argument);
  // The support (ground-column1) and the beam's tenon into column2 share no body.
  std::size_t support = 3, weak = 3;
  for (std::size_t j = 0; j < 3; ++j) {
    if (scene.joint_names[j].find("ground") != std::string::npos) support = j;
    if (scene.joint_types[j] == "weak") weak = j;
  }
  ASSERT_LT(support, 3u);
  ASSERT_LT(weak, 3u);
  EXPECT_THROW(scene.joints->hold_pair_through(support, weak), std::invalid_argument);
  // Once the scene has stepped, holds can no longer be added.
  ASSERT_TRUE(scene.simulation->step());
  std::size_t lower = 3;
  for (std::size_t j = 0; j < 3; ++j)
    if (j != support && j != weak) lower = j;
  EXPECT_THROW(scene.joints->hold_pair_through(lower, weak), std::logic_error);
}

}  // namespace
}  // namespace fq
