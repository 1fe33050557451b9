// The warnings of a run that ran but may not mean what it seems
// (io/case_runner.h, kWarn*): a time step forced above the stable estimate,
// an energy ledger that does not close, dashpots that gained energy, bodies
// that overlap at the start, a frame without columns.
//
// The dashpot check is tested against a closed form. A 0.1 m cube resting
// flat on the ground sits on four corner contacts (k_n each, dashpot c =
// 2 zeta sqrt(k_n m / 4) each, zeta from the restitution: contact_params.h),
// so its bounce is one damped oscillator, omega_b = sqrt(4 k_n / m). Central
// difference with a dashpot reading v(n-1/2) keeps it bounded only for
//   dt <= dt_b = (2 / omega_b) (sqrt(1 + zeta^2) - zeta)
// (the same limit the joints' estimate uses: test_stable_time_step.cpp).
// The engine's estimate is lower (it is set by the cube's stiffest contact
// mode: contacts/README.md), but a cube settling straight down under
// gravity excites only the bounce, so runs forced past the
// estimate show the bounce limit: below dt_b the dashpots dissipate what
// the settling gives them; above it the bounce grows until the cube leaves
// the ground, and the dashpots, now pushing with the velocity of the step
// before, which has the other sign, gain energy.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io/json_writer.h"
#include "io/utf8_text.h"
#include "io_test_util.h"

namespace fq {
namespace {

constexpr double kMass_kg = 450.0 * 0.1 * 0.1 * 0.1;
constexpr double kNormalStiffness_Npm = 1.0e6;
constexpr double kRestitution = 0.5;

std::string cube_case(double dt_s, double normal_stiffness_Npm = kNormalStiffness_Npm) {
  std::ostringstream s;
  s.precision(17);
  s << "framequake_case: 1\n"
       "name: cube_on_ground\n"
       "time: {dt_s: "
    << dt_s
    << ", duration_s: 0.2}\n"
       "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
       "ground: {level_m: 0.0}\n"
       "blocks: [{id: cube, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.05], material: spruce}]\n"
       "contact:\n"
       "  ground: {normal_stiffness_N_per_m: "
    << normal_stiffness_Npm << ", restitution: " << kRestitution
    << ", friction_coefficient: 0.4}\n"
       "output: {frame_interval_s: 0.1, history_interval_s: 0.01}\n";
  return s.str();
}

// The bounce limit of the damped cube (header).
double bounce_limit_s() {
  const double l = std::log(kRestitution);
  const double zeta = -l / std::sqrt(M_PI * M_PI + l * l);
  const double omega = std::sqrt(4.0 * kNormalStiffness_Npm / kMass_kg);
  return 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
}

struct Outcome {
  CaseRunReport report;
  std::string summary;  // summary.json
};

Outcome run_cube(const test::TempDir& dir, double dt_s, const std::string& name,
                 std::optional<Integrator> integrator = std::nullopt) {
  const CaseDef def = load_case_file(dir.write(name + ".yaml", cube_case(dt_s)));
  CaseRunOptions options;
  options.integrator = integrator;
  options.output_folder = dir.path() / name;
  options.allow_unstable_time_step = true;
  Outcome o;
  std::vector<std::string> seen;
  options.on_warning = [&](const std::string& w) { seen.push_back(w); };
  o.report = run_case(def, options);
  EXPECT_EQ(seen, o.report.warnings) << "every warning is also passed to on_warning as it arises";
  std::ifstream in(dir.path() / name / "summary.json");
  std::ostringstream text;
  text << in.rdbuf();
  o.summary = text.str();
  return o;
}

std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

bool mentions(const std::vector<std::string>& warnings, const std::string& part) {
  for (const std::string& w : warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

// The value of `column` in the last row of a run's history.csv (NaN when
// the column or a row is missing).
double last_history_value(const std::filesystem::path& run_folder, const std::string& column) {
  std::ifstream history(run_folder / "history.csv");
  std::string header, row, last;
  std::getline(history, header);
  while (std::getline(history, row)) last = row;
  const std::size_t at = header.find(column);
  if (at == std::string::npos || last.empty()) return std::nan("");
  const auto index = std::count(header.begin(), header.begin() + std::ptrdiff_t(at), ',');
  std::stringstream cells(last);
  std::string cell;
  for (std::ptrdiff_t k = 0; k <= index; ++k) std::getline(cells, cell, ',');
  return std::stod(cell);
}

TEST(RunWarnings, ContactsPressedPastTheirLimitAreNamedWithDepthAndBodies) {
  // The cube (0.45 kg, half-thickness 50 mm) set down touching the ground
  // on four corner springs sinks at least to its static depth m g / (4 k)
  // and at most to twice it. At k = 220 N/m the static depth is 5.0 mm,
  // 10 % of its half-thickness, past the 5 % limit
  // (kWarnContactPressRatio); at the case's 1e6 N/m twice it is 2.2 um,
  // 4.4e-5: no warning, the peak still in summary.json.
  const test::TempDir dir;
  const double static_soft_m = kMass_kg * kStandardGravity_mps2 / (4.0 * 220.0);
  ASSERT_GT(static_soft_m / 0.05, 2.0 * kWarnContactPressRatio);
  const CaseDef soft = load_case_file(dir.write("soft.yaml", cube_case(1e-4, 220.0)));
  CaseRunOptions options;
  options.output_folder = dir.path() / "soft";
  const CaseRunReport r = run_case(soft, options);
  EXPECT_TRUE(mentions(r.warnings, "contacts pressed 'cube' ")) << testing::PrintToString(r.warnings);
  EXPECT_TRUE(mentions(r.warnings, " mm into the ground at t = "));
  EXPECT_TRUE(mentions(r.warnings, " % of the 50 mm half-thickness of 'cube' (the largest fraction of the run; more "
                                   "than 5 %): "));
  const std::string summary = file_text(dir.path() / "soft" / "summary.json");
  const std::smatch m = [&] {
    std::smatch found;
    std::regex_search(summary, found, std::regex("\"contact_press_peak\": \\{\"depth_m\": ([0-9.e+-]+), "
                                                 "\"half_thickness_m\": 0.05, \"ratio\": ([0-9.e+-]+), "
                                                 "\"time_s\": [0-9.e+-]+, \"body_a\": \"ground\", \"body_b\": \"cube\", "
                                                 "\"measured_body\": \"cube\"\\}"));
    return found;
  }();
  ASSERT_EQ(m.size(), 3u) << summary;
  EXPECT_GE(std::stod(m[1]), static_soft_m);
  EXPECT_LE(std::stod(m[1]), 2.0 * static_soft_m);

  const CaseDef stiff = load_case_file(dir.write("stiff.yaml", cube_case(1e-4)));
  options.output_folder = dir.path() / "stiff";
  const CaseRunReport q = run_case(stiff, options);
  EXPECT_FALSE(mentions(q.warnings, "contacts pressed")) << testing::PrintToString(q.warnings);
  const std::string stiff_summary = file_text(dir.path() / "stiff" / "summary.json");
  EXPECT_NE(stiff_summary.find("\"contact_press_peak\": {\"depth_m\": "), std::string::npos);

  // The limit itself: a press of exactly 5 % is not warned about, one just
  // past it is; two boxes are named as a pair.
  BodyStore bodies;
  for (const char* name : {"beam", "column"}) {
    BoxBodyDef b;
    b.name = name;
    b.position_m = Vec3(0, 0, double(bodies.size()));
    bodies.add_box(b);
  }
  ContactPressPeak peak{kWarnContactPressRatio, 0.25e-3, 5e-3, 1.5, 0, 1, 0};
  EXPECT_EQ(contact_press_warning(peak, bodies), "");
  peak.ratio = 0.06;
  peak.depth_m = 0.3e-3;
  EXPECT_EQ(contact_press_warning(peak, bodies).rfind("contacts pressed 'beam' and 'column' 0.3 mm into each other at "
                                                      "t = 1.500 s, 6 % of the 5 mm half-thickness of 'beam', the "
                                                      "thinner free box of the two (the largest fraction of the run; "
                                                      "more than 5 %): ",
                                                      0),
            0u)
      << contact_press_warning(peak, bodies);
  // A press early in the run keeps its time's digits: 0.57 ms is not
  // written as "0.001 s" (stop 40's probe); 0.1 s and later to the ms.
  {
    ContactPressPeak early = peak;
    early.time_s = 0.57e-3;
    EXPECT_NE(contact_press_warning(early, bodies).find(" at t = 0.00057 s, 6 % "), std::string::npos)
        << contact_press_warning(early, bodies);
    early.time_s = 1e-5;  // one step
    EXPECT_NE(contact_press_warning(early, bodies).find(" at t = 0.000010 s, 6 % "), std::string::npos)
        << contact_press_warning(early, bodies);
    early.time_s = 0.1;
    EXPECT_NE(contact_press_warning(early, bodies).find(" at t = 0.100 s, 6 % "), std::string::npos)
        << contact_press_warning(early, bodies);
  }
  // A pair that started inside each other says so, with its overlap at the
  // start, whichever order the overlap list names the two in (the house
  // probe's brace read as pressed 9.1 mm into a roof beam it started
  // 10 mm inside, in a warning that did not say so); another pair's
  // overlap changes nothing.
  const std::string plain = contact_press_warning(peak, bodies);
  EXPECT_EQ(contact_press_warning(peak, bodies, {InitialOverlap{0, 2, 4e-3}}), plain);
  const std::string overlapped = contact_press_warning(peak, bodies, {InitialOverlap{1, 0, 10.1e-3}});
  EXPECT_EQ(contact_press_warning(peak, bodies, {InitialOverlap{0, 1, 10.1e-3}}), overlapped);
  EXPECT_EQ(overlapped.rfind(plain + ". These two already overlapped by 10.1 mm at the start (one of the pairs of "
                                     "the warning that bodies overlap at the start), and the 0.3 mm is beyond that; ",
                             0),
            0u)
      << overlapped;
  EXPECT_NE(overlapped.find("trim the members, turn their sections or move the blocks so that they do not start "
                            "inside each other"),
            std::string::npos)
      << overlapped;
}

TEST(RunWarnings, DashpotsGainEnergyJustAboveTheClosedFormBounceLimitAndNotJustBelow) {
  test::TempDir dir;
  const double dt_b = bounce_limit_s();
  const Outcome below = run_cube(dir, 0.95 * dt_b, "below");
  const Outcome above = run_cube(dir, 1.05 * dt_b, "above");
  ASSERT_EQ(below.report.result.status, RunStatus::Completed);
  ASSERT_EQ(above.report.result.status, RunStatus::Completed);
  // Both are above the engine's estimate (a stiffer mode), so both carry
  // the forced-step warning; only the run past the bounce limit has
  // dashpots that gained energy.
  const double estimate = below.report.stable_time_step.dt_crit_s;
  ASSERT_LT(estimate, 0.95 * dt_b) << "the cube's stiffest contact mode sets a lower estimate than its bounce";
  EXPECT_TRUE(mentions(below.report.warnings, "the run was forced"));
  EXPECT_TRUE(mentions(above.report.warnings, "the run was forced"));
  EXPECT_FALSE(mentions(below.report.warnings, "dashpots gained")) << "dt = 0.95 dt_b must dissipate";
  EXPECT_TRUE(mentions(above.report.warnings, "dashpots gained")) << "dt = 1.05 dt_b must be flagged";
  // And the warnings are in summary.json, as a list of strings.
  EXPECT_NE(above.summary.find("\"warnings\": [\"dt_s = "), std::string::npos) << above.summary;
  EXPECT_NE(above.summary.find("the dashpots gained"), std::string::npos);
}

TEST(RunWarnings, ForcedStepNamesItsFactorAndTheStiffestElementAndASoundRunHasNone) {
  test::TempDir dir;
  const Outcome sound = run_cube(dir, 1e-5, "sound");
  EXPECT_TRUE(sound.report.warnings.empty());
  EXPECT_NE(sound.summary.find("\"warnings\": []"), std::string::npos) << sound.summary;

  const double estimate = sound.report.stable_time_step.dt_crit_s;
  const Outcome forced = run_cube(dir, 1.25 * estimate, "forced");
  ASSERT_FALSE(forced.report.warnings.empty());
  const std::string& w = forced.report.warnings.front();
  EXPECT_NE(w.find("is 1.25 times the stable time step of central_difference"), std::string::npos) << w;
  EXPECT_NE(w.find(sound.report.stable_time_step.stiffest_element), std::string::npos) << w;

  // Forward Euler has no estimated stable step (estimate 0 s): the warning
  // says so instead of a factor.
  const Outcome euler = run_cube(dir, 1e-5, "euler", Integrator::ForwardEuler);
  ASSERT_FALSE(euler.report.warnings.empty());
  EXPECT_NE(euler.report.warnings.front().find("has no estimated stable limit with forward_euler"), std::string::npos)
      << euler.report.warnings.front();
}

TEST(RunWarnings, LedgerChecksFireAtTheirThresholds) {
  // The ledger's terms set by hand: the checks' thresholds are the
  // documented ones (case_runner.h), in both directions.
  EnergyLedger l;
  l.work_ground_motion_J = 1.0;
  l.dissipated_viscous_J = 0.5;
  l.kinetic_J = 0.5;  // closes exactly: stored + dissipated - input = 0
  l.update_scale();
  EXPECT_TRUE(energy_warnings(l).empty());

  EnergyLedger open = l;
  open.kinetic_J = 0.5 + 2.0 * kWarnBalanceErrorRelative * open.scale_J;
  open.update_scale();
  ASSERT_GT(std::fabs(open.balance_error_relative()), kWarnBalanceErrorRelative);
  const std::vector<std::string> w = energy_warnings(open);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("energy balance does not close"), std::string::npos) << w[0];

  EnergyLedger nearly = l;
  nearly.kinetic_J = 0.5 + 0.5 * kWarnBalanceErrorRelative * nearly.scale_J;
  nearly.update_scale();
  EXPECT_TRUE(energy_warnings(nearly).empty());

  // Dashpots that gained twice the threshold, with the balance kept closed
  // by the kinetic energy they gave.
  EnergyLedger gained = l;
  gained.dissipated_viscous_J = -2.0 * kWarnViscousGainRelative;
  gained.kinetic_J = 1.0 + 2.0 * kWarnViscousGainRelative;
  gained.update_scale();
  ASSERT_LT(std::fabs(gained.balance_error_relative()), 1e-12);
  const std::vector<std::string> g = energy_warnings(gained);
  ASSERT_EQ(g.size(), 1u);
  EXPECT_NE(g[0].find("the dashpots gained"), std::string::npos) << g[0];

  EnergyLedger small_gain = gained;
  small_gain.dissipated_viscous_J = -0.5 * kWarnViscousGainRelative * small_gain.scale_J;
  small_gain.kinetic_J = 1.0 - small_gain.dissipated_viscous_J;
  small_gain.update_scale();
  EXPECT_TRUE(energy_warnings(small_gain).empty());

  // A scene without dashpots: the viscous book is the contact springs'
  // discretisation error, and a negative one is no dashpot's doing.
  EXPECT_TRUE(energy_warnings(gained, /*has_dashpots=*/false).empty());
  // ... but a large one, of either sign, says the contacts are not resolved.
  for (const double sign : {-1.0, 1.0}) {
    EnergyLedger unresolved = l;
    unresolved.dissipated_viscous_J = sign * 2.0 * kWarnContactDiscretisationRelative;
    unresolved.kinetic_J = 1.0 - unresolved.dissipated_viscous_J;
    unresolved.update_scale();
    ASSERT_LT(std::fabs(unresolved.balance_error_relative()), 1e-12);
    const std::vector<std::string> u = energy_warnings(unresolved, /*has_dashpots=*/false);
    ASSERT_EQ(u.size(), 1u) << sign;
    EXPECT_NE(u[0].find("discretisation error"), std::string::npos) << u[0];
    EnergyLedger resolved = unresolved;
    resolved.dissipated_viscous_J = sign * 0.5 * kWarnContactDiscretisationRelative * resolved.scale_J;
    resolved.kinetic_J = 1.0 - resolved.dissipated_viscous_J;
    resolved.update_scale();
    EXPECT_TRUE(energy_warnings(resolved, /*has_dashpots=*/false).empty()) << sign;
  }
  // Forward Euler's balance warning does not advise a smaller dt_s.
  const std::vector<std::string> euler = energy_warnings(open, true, Integrator::ForwardEuler);
  ASSERT_EQ(euler.size(), 1u);
  EXPECT_NE(euler[0].find("run again with another integrator"), std::string::npos) << euler[0];
  EXPECT_EQ(euler[0].find("smaller dt_s"), std::string::npos) << euler[0];
  // gsl_rk8pd's motion is resolved by its own sub-steps; only the ledger's
  // once-per-step books are not (a probe's elastic frame at dt_s = 0.01 s
  // was told "the time step does not resolve the motion").
  const std::vector<std::string> gsl = energy_warnings(open, true, Integrator::GslRk8pd);
  ASSERT_EQ(gsl.size(), 1u);
  EXPECT_NE(gsl[0].find("ledger open rather than the motion wrong"), std::string::npos) << gsl[0];
  EXPECT_EQ(gsl[0].find("does not resolve the motion"), std::string::npos) << gsl[0];
}

// Which cases have a dashpot: a joint spring with a damping ratio or a
// coefficient, or a contact with restitution below 1 (ground, default
// pair or a listed pair).
TEST(RunWarnings, CaseHasDashpotsWhereAJointOrAContactDampsIt) {
  CaseDef none;
  EXPECT_FALSE(case_has_dashpots(none));
  CaseDef elastic_contacts;
  elastic_contacts.contact.emplace();
  elastic_contacts.contact->default_pair.restitution = 1.0;
  elastic_contacts.contact->ground = ContactParams{};
  elastic_contacts.contact->ground->restitution = 1.0;
  EXPECT_FALSE(case_has_dashpots(elastic_contacts));
  CaseDef damped_ground = elastic_contacts;
  damped_ground.contact->ground->restitution = 0.5;
  EXPECT_TRUE(case_has_dashpots(damped_ground));
  // A pair's restitution counts only where two bodies of its materials
  // exist: a lone block on elastic ground has no dashpot, whatever the
  // default pair's restitution (a probe got "the dashpots gained" from a
  // 1 cm cube on ground with restitution 1).
  CaseDef lone_block = elastic_contacts;
  lone_block.contact->default_pair.restitution = 0.5;
  lone_block.blocks.push_back({});
  lone_block.blocks.back().material = "spruce";
  EXPECT_FALSE(case_has_dashpots(lone_block));
  CaseDef two_blocks = lone_block;
  two_blocks.blocks.push_back(two_blocks.blocks.back());
  EXPECT_TRUE(case_has_dashpots(two_blocks));
  // Two bodies of different materials: their pair's entry decides, and the
  // default pair's restitution (0.5 here) no longer matters.
  CaseDef mixed = lone_block;
  mixed.members.push_back({});
  mixed.members.back().material = "oak";
  EXPECT_TRUE(case_has_dashpots(mixed));
  mixed.contact->pairs.push_back({});
  mixed.contact->pairs.back().material_1 = "oak";
  mixed.contact->pairs.back().material_2 = "spruce";
  mixed.contact->pairs.back().params.restitution = 1.0;
  EXPECT_FALSE(case_has_dashpots(mixed));
  CaseDef damped_pair = mixed;
  damped_pair.contact->pairs.back().params.restitution = 0.9;
  EXPECT_TRUE(case_has_dashpots(damped_pair));
  CaseDef damped_joint;
  damped_joint.joint_types.push_back({});
  EXPECT_FALSE(case_has_dashpots(damped_joint));
  damped_joint.joint_types.back().shear.dashpot.damping_ratio = 0.05;
  EXPECT_TRUE(case_has_dashpots(damped_joint));
  CaseDef coefficient_joint;
  coefficient_joint.joint_types.push_back({});
  coefficient_joint.joint_types.back().diagonal.dashpot.coefficient_Nspm = 3.0;
  EXPECT_TRUE(case_has_dashpots(coefficient_joint));
}

TEST(RunWarnings, BodiesOverlappingAtTheStartAreNamedWithTheirDepth) {
  // Two blocks 1.5 mm into each other (centres 0.0985 m apart, 0.1 m cubes)
  // and a third touching the second face to face: one pair overlaps.
  test::TempDir dir;
  const std::string text =
      "framequake_case: 1\n"
      "time: {dt_s: 1.0e-5, duration_s: 0.01}\n"
      "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
      "ground: {level_m: 0.0}\n"
      "blocks:\n"
      "  - {id: left, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.05], material: spruce}\n"
      "  - {id: middle, size_m: [0.1, 0.1, 0.1], center_m: [0.0985, 0, 0.05], material: spruce}\n"
      "  - {id: right, size_m: [0.1, 0.1, 0.1], center_m: [0.1985, 0, 0.05], material: spruce}\n"
      "contact:\n"
      "  ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.5, friction_coefficient: 0.4}\n"
      "  default: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.5, friction_coefficient: 0.4}\n"
      "output: {frame_interval_s: 0.01, history_interval_s: 0.001}\n";
  const CaseDef def = load_case_file(dir.write("overlap.yaml", text));
  CaseRunOptions options;
  options.output_folder = dir.path() / "overlap";
  const CaseRunReport report = run_case(def, options);
  ASSERT_EQ(report.result.status, RunStatus::Completed);
  ASSERT_EQ(report.warnings.size(), 1u);
  const std::string& w = report.warnings.front();
  EXPECT_NE(w.find("1 pair of bodies not held by a joint overlap at the start ('left' and 'middle' by 1.5 mm)"),
            std::string::npos)
      << w;
  EXPECT_EQ(w.find("'right'"), std::string::npos) << "touching is not overlapping: " << w;
  // info says it before any run (a house probe found info silent where run
  // warned of 60 overlapping pairs).
  std::ostringstream info;
  describe_case(def, info);
  EXPECT_NE(info.str().find("warning     1 pair of bodies not held by a joint overlap at the start ('left' and "
                            "'middle' by 1.5 mm)"),
            std::string::npos)
      << info.str();
}

// A king post drawn standing on the top face of a beam 20 mm deep and
// 10 mm wide (its foot 10 mm above the beam's axis, beyond the 5 mm the
// old test of the inscribed circle reached): no joint holds it to the
// beam, which the warning names (geometry probe). A post 3 mm above the
// face is clear of the beam (1 mm allowance) and not named.
TEST(RunWarnings, ANodeOnAMembersFaceIsNamed) {
  test::TempDir dir;
  auto warning_for = [&](double foot_z_m) {
    std::ostringstream text;
    text << "framequake_case: 1\n"
            "time: {dt_s: 1.0e-5, duration_s: 0.001}\n"
            "materials: [{name: wood, density_kg_per_m3: 450}]\n"
            "sections: [{name: beam, width_m: 0.010, depth_m: 0.020}]\n"
            "nodes:\n"
            "  - {id: a, xyz_m: [0, 0, 0.3]}\n"
            "  - {id: b, xyz_m: [0.6, 0, 0.3]}\n"
            "  - {id: foot, xyz_m: [0.3, 0, "
         << foot_z_m
         << "]}\n"
            "  - {id: ridge, xyz_m: [0.3, 0, 0.45]}\n"
            "members:\n"
            "  - {id: tie_beam, kind: beam, nodes: [a, b], section: beam, material: wood}\n"
            "  - {id: king_post, kind: other, nodes: [foot, ridge], section: beam, material: wood}\n";
    return nodes_inside_members_warning(load_case_file(dir.write("king_post.yaml", text.str())));
  };
  const std::string on_face = warning_for(0.31);
  EXPECT_NE(on_face.find("node 'foot' (line 8) inside or on member 'tie_beam' (line 11)"), std::string::npos)
      << on_face;
  EXPECT_EQ(warning_for(0.313), "");
}

TEST(RunWarnings, ANodeInsideAMemberIsNamedAndTheShippedFramesHaveNone) {
  // A column drawn through the floor node m1 (from m0 to m2) and a beam
  // ending at m1: no joint holds the beam to the column there. A second
  // beam ends 0.5 mm from the column's axis at mid-height of its other
  // column (inside it), a third node lies beside a column, 20 mm off its
  // axis (outside its 10 mm section): only the first two are inside.
  test::TempDir dir;
  const std::string text =
      "framequake_case: 1\n"
      "time: {dt_s: 1.0e-5, duration_s: 0.001}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}]\n"
      "sections: [{name: s, width_m: 0.010, depth_m: 0.010}]\n"
      "nodes:\n"
      "  - {id: m0, xyz_m: [0, 0, 0]}\n"
      "  - {id: m1, xyz_m: [0, 0, 0.3]}\n"
      "  - {id: m2, xyz_m: [0, 0, 0.6]}\n"
      "  - {id: n0, xyz_m: [0.5, 0, 0]}\n"
      "  - {id: n1, xyz_m: [0.5005, 0, 0.3]}\n"
      "  - {id: n2, xyz_m: [0.5, 0, 0.6]}\n"
      "  - {id: beside, xyz_m: [0.52, 0, 0.3]}\n"
      "  - {id: far, xyz_m: [1.0, 0, 0.3]}\n"
      "members:\n"
      "  - {id: col_m, kind: column, nodes: [m0, m2], section: s, material: wood}\n"
      "  - {id: col_n, kind: column, nodes: [n0, n2], section: s, material: wood}\n"
      "  - {id: beam_1, kind: beam, nodes: [m1, n1], section: s, material: wood}\n"
      "  - {id: beam_2, kind: beam, nodes: [beside, far], section: s, material: wood}\n";
  const CaseDef def = load_case_file(dir.write("through.yaml", text));
  const std::string w = nodes_inside_members_warning(def);
  EXPECT_NE(w.find("2 nodes lie inside or on a member"), std::string::npos) << w;
  EXPECT_NE(w.find("node 'm1' (line 7) inside or on member 'col_m' (line 15)"), std::string::npos) << w;
  EXPECT_NE(w.find("node 'n1' (line 10) inside or on member 'col_n' (line 16)"), std::string::npos) << w;
  EXPECT_EQ(w.find("'beside'"), std::string::npos) << w;
  EXPECT_NE(w.find("through.yaml"), std::string::npos) << w;
  // The shipped frames join every member at its ends.
  for (const char* name : {"frame_A.yaml", "frame_B.yaml", "frame_C.yaml"}) {
    const CaseDef shipped = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / name);
    EXPECT_EQ(nodes_inside_members_warning(shipped), "") << name;
  }
}

// A portal: two columns on support joints, a beam between their tops. The
// beam's end nodes are moved to show the two mistakes a probe made by hand:
// a beam drawn 10 mm above the column tops (joined to nothing) and one end
// typed 2 mm off the column's node (joined at one end only).
std::string portal_case(double beam_a_z_m, double beam_b_z_m) {
  std::ostringstream text;
  text << "framequake_case: 1\n"
          "time: {dt_s: 1.0e-5, duration_s: 0.001}\n"
          "materials: [{name: wood, density_kg_per_m3: 450}]\n"
          "sections: [{name: s, width_m: 0.010, depth_m: 0.020}]\n"
          "nodes:\n"
          "  - {id: a0, xyz_m: [0, 0, 0]}\n"
          "  - {id: b0, xyz_m: [0.5, 0, 0]}\n"
          "  - {id: a1, xyz_m: [0, 0, 0.3]}\n"
          "  - {id: b1, xyz_m: [0.5, 0, 0.3]}\n"
          "  - {id: a2, xyz_m: [0, 0, "
       << beam_a_z_m << "]}\n  - {id: b2, xyz_m: [0.5, 0, " << beam_b_z_m
       << "]}\n"
          "members:\n"
          "  - {id: col_a, kind: column, nodes: [a0, a1], section: s, material: wood}\n"
          "  - {id: col_b, kind: column, nodes: [b0, b1], section: s, material: wood}\n"
          "  - {id: beam, kind: beam, nodes: ["
       << (beam_a_z_m == 0.3 ? "a1" : "a2") << ", " << (beam_b_z_m == 0.3 ? "b1" : "b2")
       << "], section: s, material: wood}\n"
          "joint_types: [{name: j, layout: four_corner,\n"
          "               normal: {law: linear, stiffness_N_per_m: 1.0e5},\n"
          "               shear: {law: linear, stiffness_N_per_m: 1.0e5}}]\n"
          "joints: {default_type: j, support_type: j}\n"
          "supports: [{node: a0}, {node: b0}]\n";
  return text.str();
}

// A joint still holding whose bodies have turned more than three quarters
// of a whole turn against each other along their quaternions' path is
// warned of (a frame probe, stop 41: a support spun a whole turn kept an
// undefined half-way frame, booked a balance error of 8e-3 and in a portal
// blew up). The portal's beam turned by theta about its own axis from the
// joints' common start (their frames' quaternions start equal): the turn
// is theta, 2 acos(cos(theta / 2)), for both beam-column joints; 350 deg is
// warned of, with the larger named, 200 deg (past a half turn, where the
// frame is still continuous) and 10 deg are not.
TEST(RunWarnings, AJointTurnedNearAWholeTurnIsWarnedOf) {
  test::TempDir dir;
  const CaseDef def = load_case_file(dir.write("portal.yaml", portal_case(0.3, 0.3)));
  auto turned = [&](double deg) {
    Scene scene = build_scene(def);
    BodyStore& bodies = scene.simulation->bodies();
    BodyId beam = kNoBody;
    for (BodyId b = 0; b < BodyId(bodies.size()); ++b)
      if (bodies.info[std::size_t(b)].name == "beam") beam = b;
    EXPECT_NE(beam, kNoBody);
    const double rad = deg * std::numbers::pi / 180.0;
    bodies.orientation[std::size_t(beam)] =
        Quat(Eigen::AngleAxisd(rad, Vec3::UnitX())) * bodies.orientation[std::size_t(beam)];
    bodies.update_rotations();
    std::vector<double> turns;
    for (std::size_t j = 0; j < scene.joints->joint_count(); ++j)
      if (scene.joints->joint_body_a(j) == beam || scene.joints->joint_body_b(j) == beam)
        turns.push_back(scene.joints->relative_turn_rad(bodies, j));
    EXPECT_EQ(turns.size(), 2u);
    for (const double t : turns) EXPECT_NEAR(t, rad, 1e-9) << deg;
    return whole_turn_joints_warning(*scene.joints, bodies, scene.joint_names);
  };
  const std::string w = turned(350.0);
  EXPECT_EQ(w.rfind("joint '", 0), 0u) << w;
  EXPECT_NE(w.find("' and 1 other still holding at the end have turned their two bodies more than three quarters of "
                   "a whole turn against each other (350 deg the most): "),
            std::string::npos)
      << w;
  EXPECT_EQ(turned(200.0), "");
  EXPECT_EQ(turned(10.0), "");
}

// A node no member ends at (a leftover, or the end a member was meant to
// have) is named with its line; the shipped cases use every node.
TEST(RunWarnings, NodesNoMemberEndsAtAreNamed) {
  test::TempDir dir;
  auto post = [](bool spare_node) {
    return std::string("framequake_case: 1\n"
                       "time: {dt_s: 1.0e-5, duration_s: 0.001}\n"
                       "materials: [{name: wood, density_kg_per_m3: 450}]\n"
                       "sections: [{name: s, width_m: 0.010, depth_m: 0.020}]\n"
                       "nodes:\n"
                       "  - {id: a0, xyz_m: [0, 0, 0]}\n"
                       "  - {id: a1, xyz_m: [0, 0, 0.3]}\n") +
           (spare_node ? "  - {id: spare, xyz_m: [0.5, 0, 0.3]}\n" : "") +
           "members: [{id: post, kind: column, nodes: [a0, a1], section: s, material: wood}]\n";
  };
  const std::string w = unused_nodes_warning(load_case_file(dir.write("spare.yaml", post(true))));
  EXPECT_NE(w.find("1 node is the end of no member ('spare' (line 8))"), std::string::npos) << w;
  EXPECT_NE(w.find("spare.yaml"), std::string::npos) << w;
  EXPECT_EQ(unused_nodes_warning(load_case_file(dir.write("all_used.yaml", post(false)))), "");
  for (const char* name : {"frame_A.yaml", "frame_B.yaml", "frame_C.yaml", "demo_portal_frame.yaml",
                           "demo_breaking_cantilever.yaml", "demo_falling_block.yaml"}) {
    const CaseDef shipped = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / name);
    EXPECT_EQ(unused_nodes_warning(shipped), "") << name;
  }
}

TEST(RunWarnings, NearlyCoincidentEndNodesAreNamed) {
  test::TempDir dir;
  // Beam end b 2 mm above the column top: closer than half the thinner
  // section size (5 mm), so not meant as a separate node.
  const CaseDef typo = load_case_file(dir.write("typo.yaml", portal_case(0.3, 0.302)));
  const std::string w = near_nodes_warning(typo);
  EXPECT_NE(w.find("1 pair of member end nodes"), std::string::npos) << w;
  EXPECT_NE(w.find("nodes 'b1' (line 9) and 'b2' (line 11) 2 mm apart"), std::string::npos) << w;
  EXPECT_NE(w.find("typo.yaml"), std::string::npos) << w;
  // 6 mm apart, beyond half the thinner section: a separate node on purpose.
  EXPECT_EQ(near_nodes_warning(load_case_file(dir.write("apart.yaml", portal_case(0.3, 0.306)))), "");
  EXPECT_EQ(near_nodes_warning(load_case_file(dir.write("joined.yaml", portal_case(0.3, 0.3)))), "");
  for (const char* name : {"frame_A.yaml", "frame_B.yaml", "frame_C.yaml"}) {
    const CaseDef shipped = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / name);
    EXPECT_EQ(near_nodes_warning(shipped), "") << name;
  }
}

// Section sizes typed in millimetres against nodes in metres (a probe's 10
// x 20 "m" columns) make every member wider than long; the portal in
// metres, the shipped cases and the demos give no warning.
TEST(RunWarnings, MembersWiderThanLongAreNamedWithTheirSection) {
  test::TempDir dir;
  std::string in_mm = portal_case(0.3, 0.3);
  const std::string from = "width_m: 0.010, depth_m: 0.020";
  in_mm.replace(in_mm.find(from), from.size(), "width_m: 10, depth_m: 20");
  const std::string w = stout_members_warning(load_case_file(dir.write("in_mm.yaml", in_mm)));
  // Columns 0.3 m long, the beam 0.5 m: the columns are the stoutest (20 / 0.3).
  EXPECT_NE(w.find("3 members have a section wider than they are long"), std::string::npos) << w;
  EXPECT_NE(w.find("'col_a' (line 13), is 0.3 m long with a side of 20 m, section 's'"), std::string::npos) << w;
  EXPECT_NE(w.find("typed in millimetres"), std::string::npos) << w;
  EXPECT_EQ(stout_members_warning(load_case_file(dir.write("in_m.yaml", portal_case(0.3, 0.3)))), "");
  // Wider than long but under a metre (0.5 x 0.8 m on 0.3 and 0.5 m
  // members): a stub or block-like member, not a unit slip (review probe:
  // a 15 mm stub of a 20 mm section was warned).
  std::string squat = portal_case(0.3, 0.3);
  squat.replace(squat.find(from), from.size(), "width_m: 0.5, depth_m: 0.8");
  EXPECT_EQ(stout_members_warning(load_case_file(dir.write("squat.yaml", squat))), "");
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(FQ_SOURCE_DIR) / "cases")) {
    if (e.path().extension() != ".yaml") continue;
    EXPECT_EQ(stout_members_warning(load_case_file(e.path())), "") << e.path();
  }
}

// Coordinates typed in millimetres against sections in metres (a probe's
// slip: a 290 m column of 10 mm) make members 1000 times too slender; the
// portal in metres, the shipped cases and the demos give no warning.
TEST(RunWarnings, MembersAThousandTimesLongerThanThickAreNamed) {
  test::TempDir dir;
  std::string in_mm = portal_case(0.3, 0.3);
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"[0.5, 0, 0]", "[500, 0, 0]"},
                                 {"[0, 0, 0.3]", "[0, 0, 300]"},
                                 {"[0.5, 0, 0.3]", "[500, 0, 300]"}}) {
    for (std::size_t at = in_mm.find(from); at != std::string::npos; at = in_mm.find(from, at + to.size()))
      in_mm.replace(at, from.size(), to);
  }
  const std::string w = slender_members_warning(load_case_file(dir.write("in_mm.yaml", in_mm)));
  // Columns 300 m / 0.01 m = 30 000, the beam 500 m / 0.01 m = 50 000.
  EXPECT_NE(w.find("3 members are more than 1000 times longer"), std::string::npos) << w;
  EXPECT_NE(w.find("'beam' (line 15), is 500 m long and 0.01 m thin, 5e+04 times"), std::string::npos) << w;
  EXPECT_NE(w.find("typed in millimetres"), std::string::npos) << w;
  EXPECT_EQ(slender_members_warning(load_case_file(dir.write("in_m.yaml", portal_case(0.3, 0.3)))), "");
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(FQ_SOURCE_DIR) / "cases")) {
    if (e.path().extension() != ".yaml") continue;
    EXPECT_EQ(slender_members_warning(load_case_file(e.path())), "") << e.path();
  }
}

// A member of kind column lying flat spans no storey, so the drift
// assessment leaves it out; that is said, naming it (it was silent:
// geometry probe). The portal's beam given kind column is named; a column
// leaning by 0.2 m over its 0.3 m height still spans one and is not; the
// shipped cases and demos give no warning.
TEST(RunWarnings, AHorizontalColumnIsNamed) {
  test::TempDir dir;
  std::string flat = portal_case(0.3, 0.3);
  const std::string beam_line = "  - {id: beam, kind: beam,";
  flat.replace(flat.find(beam_line), beam_line.size(), "  - {id: beam, kind: column,");
  const std::string w = horizontal_columns_warning(load_case_file(dir.write("flat.yaml", flat)));
  EXPECT_NE(w.find("1 member of kind column lies nearer horizontal than vertical ('beam' (line 15))"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("left out of the drift assessment"), std::string::npos) << w;
  EXPECT_EQ(horizontal_columns_warning(load_case_file(dir.write("portal.yaml", portal_case(0.3, 0.3)))), "");
  // A "column" rising 2 mm over 0.5 m (new-features probe: it made a storey
  // 2 mm tall) is named too.
  std::string sloping = flat;
  sloping.replace(sloping.find("{id: b2, xyz_m: [0.5, 0, 0.3]}"), 30, "{id: b2, xyz_m: [0.5, 0, 0.302]}");
  sloping.replace(sloping.find("nodes: [a1, b1], section: s"), 27, "nodes: [a1, b2], section: s");
  EXPECT_NE(horizontal_columns_warning(load_case_file(dir.write("sloping.yaml", sloping))).find("'beam' (line 15)"),
            std::string::npos);
  std::string leaning = portal_case(0.3, 0.3);
  leaning.replace(leaning.find("{id: a1, xyz_m: [0, 0, 0.3]}"), 28, "{id: a1, xyz_m: [0.2, 0, 0.3]}");
  EXPECT_EQ(horizontal_columns_warning(load_case_file(dir.write("leaning.yaml", leaning))), "");
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(FQ_SOURCE_DIR) / "cases")) {
    if (e.path().extension() != ".yaml") continue;
    EXPECT_EQ(horizontal_columns_warning(load_case_file(e.path())), "") << e.path();
  }
}

// A frame without a member of kind column has no storeys, so a run gives
// no storey drift and no verdict; it said nothing (geometry probe: posts
// given kind other). The portal with its columns given kind other is
// warned of, by run (summary.json's warnings) and by info, which says it
// has no storeys; the portal as it is, a case of blocks only (no frame to
// assess) and the shipped cases are not.
// A one-bay portal whose beam runs `plan_deg` from world x, its columns
// of section width x depth (m) with `roll_deg`.
std::string turned_portal_case(double plan_deg, double width_m, double depth_m, double roll_deg) {
  const double c = 0.49 * std::cos(plan_deg * M_PI / 180.0), s = 0.49 * std::sin(plan_deg * M_PI / 180.0);
  std::ostringstream t;
  t.precision(17);
  t << "framequake_case: 1\n"
       "time: {dt_s: 1.0e-5, duration_s: 0.01}\n"
       "materials: [{name: wood, density_kg_per_m3: 450}]\n"
       "sections: [{name: col, width_m: " << width_m << ", depth_m: " << depth_m
    << "}, {name: beam, width_m: 0.01, depth_m: 0.01}]\n"
       "nodes:\n"
       "  - {id: bw, xyz_m: [0, 0, 0]}\n"
       "  - {id: tw, xyz_m: [0, 0, 0.29]}\n"
       "  - {id: te, xyz_m: [" << c << ", " << s << ", 0.29]}\n"
       "  - {id: be, xyz_m: [" << c << ", " << s << ", 0]}\n"
       "members:\n"
       "  - {id: cw, kind: column, nodes: [bw, tw], section: col, material: wood, roll_deg: " << roll_deg << "}\n"
       "  - {id: ce, kind: column, nodes: [be, te], section: col, material: wood, roll_deg: " << roll_deg << "}\n"
       "  - {id: b, kind: beam, nodes: [tw, te], section: beam, material: wood}\n";
  return t.str();
}

// A frame drawn at 30 degrees in plan keeps its rectangular columns' width
// along world x (cases/README.md), so they bend about other axes than its
// beams: the torsion probe's turned frame drifted 1.54 times the aligned
// one with no warning. The warning names each column and the roll_deg that
// aligns it (30, or -60 + 90: the nearest quarter turn); a square section,
// an aligned plan, or the roll given are not warned about, nor are the
// shipped cases.
TEST(RunWarnings, ARectangularColumnTurnedAgainstItsBeamsIsNamedWithTheRollThatAlignsIt) {
  test::TempDir dir;
  auto warning_for = [&](double plan_deg, double width_m, double depth_m, double roll_deg) {
    const CaseDef def = load_case_file(dir.write("portal.yaml", turned_portal_case(plan_deg, width_m, depth_m, roll_deg)));
    return turned_column_sections_warning(def, build_scene(def));
  };
  const std::string w = warning_for(30.0, 0.01, 0.02, 0.0);
  EXPECT_NE(w.find("2 columns of rectangular section are turned against every member framing into them"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("'cw' (line 11), 30 deg off: roll_deg 30"), std::string::npos) << w;
  EXPECT_NE(w.find("'ce' (line 12), 30 deg off: roll_deg 30"), std::string::npos) << w;
  // 70 degrees is 20 short of a quarter turn: roll_deg -20 aligns the depth.
  EXPECT_NE(warning_for(70.0, 0.01, 0.02, 0.0).find("-20 deg off: roll_deg -20"), std::string::npos);
  EXPECT_EQ(warning_for(30.0, 0.01, 0.02, 30.0), "");
  EXPECT_EQ(warning_for(30.0, 0.02, 0.02, 0.0), "");
  EXPECT_EQ(warning_for(0.0, 0.01, 0.02, 0.0), "");
  EXPECT_EQ(warning_for(90.0, 0.01, 0.02, 0.0), "");
  EXPECT_EQ(warning_for(4.0, 0.01, 0.02, 0.0), "");  // within the 5 degree tolerance
  for (const char* name : {"frame_A.yaml", "frame_B.yaml", "frame_C.yaml", "demo_portal_frame.yaml"}) {
    const CaseDef shipped = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / name);
    EXPECT_EQ(turned_column_sections_warning(shipped, build_scene(shipped)), "") << name;
  }
}

TEST(RunWarnings, AFrameWithoutColumnsIsToldItGetsNoStoreys) {
  test::TempDir dir;
  std::string posts = portal_case(0.3, 0.3);
  for (const char* id : {"col_a", "col_b"}) {
    const std::string from = std::string("{id: ") + id + ", kind: column,";
    posts.replace(posts.find(from), from.size(), std::string("{id: ") + id + ", kind: other,");
  }
  const CaseDef def = load_case_file(dir.write("posts.yaml", posts));
  const std::string w = no_columns_warning(def);
  EXPECT_NE(w.find("posts.yaml: no member is of kind column, so the case has no storeys and the run gives no storey "
                   "drift and no verdict"),
            std::string::npos)
      << w;
  CaseRunOptions options;
  options.output_folder = dir.path() / "posts";
  const CaseRunReport report = run_case(def, options);
  EXPECT_TRUE(report.storeys.empty());
  EXPECT_TRUE(mentions(report.warnings, "no member is of kind column")) << report.warnings.size();
  std::ostringstream info;
  describe_case(def, info);
  EXPECT_NE(info.str().find("storeys     none: no column spans a storey"), std::string::npos) << info.str();
  EXPECT_NE(info.str().find("warning     " + w), std::string::npos) << info.str();

  EXPECT_EQ(no_columns_warning(load_case_file(dir.write("portal.yaml", portal_case(0.3, 0.3)))), "");
  EXPECT_EQ(no_columns_warning(load_case_file(dir.write("cube.yaml", cube_case(1e-5)))), "");
  // A block given kind column spans no storey (storeys come from members
  // only): said, alone or after the members' warning (input probe, stop
  // 41: a case of column blocks got no storeys and no word why).
  std::string column_block = cube_case(1e-5);
  const std::string block = "{id: cube, ";
  ASSERT_NE(column_block.find(block), std::string::npos);
  column_block.replace(column_block.find(block), block.size(), "{id: cube, kind: column, ");
  const CaseDef block_def = load_case_file(dir.write("block_column.yaml", column_block));
  EXPECT_EQ(no_columns_warning(block_def),
            (dir.path() / "block_column.yaml").string() +
                ": block 'cube' (line " + std::to_string(block_def.blocks[0].line) +
                ") is of kind column, but storeys are found from members (between two nodes) only, so it spans no "
                "storey and its drift is not assessed; make a post a member between two nodes to have it assessed");
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(FQ_SOURCE_DIR) / "cases")) {
    if (e.path().extension() != ".yaml") continue;
    const CaseDef shipped = load_case_file(e.path());
    if (shipped.members.empty()) continue;
    EXPECT_EQ(no_columns_warning(shipped), "") << e.path();
  }
}

// The portal demo's case text, its record given by absolute path (so that
// the text can be written into a temporary folder).
std::string portal_demo_text() {
  const std::filesystem::path cases = std::filesystem::path(FQ_SOURCE_DIR) / "cases";
  std::string portal = file_text(cases / "demo_portal_frame.yaml");
  const std::string record = "file: ground_motions/";
  portal.replace(portal.find(record), record.size(), "file: " + (cases / "ground_motions").string() + "/");
  return portal;
}

// A ground without contact.ground holds nothing up: the cube of cube_case,
// 5 cm above it at its centre, falls through it under gravity (free fall:
// g t^2 / 2 = 0.196 m in the 0.2 s run, so its centre ends below the
// surface), and run and info say why before it starts. With the contact it
// rests. A frame whose every member is held through joints to a support is
// not warned (the portal demo with a ground section: a contact would change
// its results), blocks beside supports without a ground section are, and
// no shipped case is.
TEST(RunWarnings, AGroundWithoutContactIsToldItHoldsNothing) {
  test::TempDir dir;
  std::string text = cube_case(1e-5);
  const std::string contact = text.substr(text.find("contact:\n"), text.find("output:") - text.find("contact:\n"));
  text.replace(text.find(contact), contact.size(), "");
  const CaseDef def = load_case_file(dir.write("cube.yaml", text));
  const std::string w = ground_without_contact_warning(def, build_scene(def));
  EXPECT_NE(w.find("cube.yaml:5: the case has a ground (ground.level_m = 0 m) but no contact with it "
                   "(contact.ground), so nothing rests on it: 1 body no joint holds to a support ('cube') falls "
                   "through its surface"),
            std::string::npos)
      << w;
  CaseRunOptions options;
  options.output_folder = dir.path() / "cube";
  const CaseRunReport report = run_case(def, options);
  EXPECT_TRUE(mentions(report.warnings, "but no contact with it (contact.ground)")) << report.warnings.size();
  std::ostringstream info;
  describe_case(def, info);
  EXPECT_NE(info.str().find("warning     " + w), std::string::npos) << info.str();
  // It fell: the largest displacement at the end is the free fall's
  // (max_displacement_m of the last row of history.csv).
  EXPECT_NEAR(last_history_value(dir.path() / "cube", "max_displacement_m"), 0.5 * 9.80665 * 0.2 * 0.2, 1e-6);

  const CaseDef rests = load_case_file(dir.write("rests.yaml", cube_case(1e-5)));
  EXPECT_EQ(ground_without_contact_warning(rests, build_scene(rests)), "");
  // The portal demo, every member held through its joints to the supports,
  // given a ground section: nothing falls at the start.
  const std::filesystem::path cases = std::filesystem::path(FQ_SOURCE_DIR) / "cases";
  const std::string portal = portal_demo_text();
  const CaseDef grounded = load_case_file(dir.write("portal.yaml", portal + "ground: {level_m: 0.0}\n"));
  EXPECT_EQ(ground_without_contact_warning(grounded, build_scene(grounded)), "");
  // The same demo with a free block beside it and no ground section: the
  // supports make a ground body, and the block falls through it.
  const CaseDef with_block = load_case_file(dir.write(
      "portal_block.yaml", portal + "blocks: [{id: crate, size_m: [0.05, 0.05, 0.05], center_m: [2.0, 0, 0.025], "
                                    "material: wood}]\n"));
  const std::string block_warning = ground_without_contact_warning(with_block, build_scene(with_block));
  EXPECT_NE(block_warning.find("the case has a ground but no contact with it (contact.ground), so nothing rests on "
                               "it: 1 body no joint holds to a support ('crate') falls"),
            std::string::npos)
      << block_warning;
  for (const auto& e : std::filesystem::directory_iterator(cases)) {
    if (e.path().extension() != ".yaml") continue;
    const CaseDef shipped = load_case_file(e.path());
    EXPECT_EQ(ground_without_contact_warning(shipped, build_scene(shipped)), "") << e.path();
  }
}

// A frame held by nothing (the portal demo without its supports, no
// ground section, no fixed block) falls freely under gravity from the
// start: run and info warn before it starts. Free fall is the check that
// it does: the largest displacement after 0.1 s is g t^2 / 2 = 0.049 m.
// Without gravity, with its supports, and for the shipped cases: no warning.
TEST(RunWarnings, AFrameNothingHoldsUpIsToldItFalls) {
  test::TempDir dir;
  const std::filesystem::path cases = std::filesystem::path(FQ_SOURCE_DIR) / "cases";
  const std::string portal = portal_demo_text();
  const std::string supports = "supports:\n  - {node: base_w}\n  - {node: base_e}\n";
  ASSERT_NE(portal.find(supports), std::string::npos);
  const CaseDef held = load_case_file(dir.write("held.yaml", portal));
  EXPECT_EQ(nothing_holds_the_frame_warning(held, build_scene(held)), "");
  std::string loose_text = portal;
  loose_text.replace(loose_text.find(supports), supports.size(), "");
  // The ground motion out, so that the fall is gravity's alone.
  loose_text = loose_text.substr(0, loose_text.find("ground_motion:"));
  const std::string time = "time:\n";
  ASSERT_NE(loose_text.find(time), std::string::npos);
  loose_text.replace(loose_text.find(time), time.size(), "time:\n  duration_s: 0.1\n");
  const CaseDef loose = load_case_file(dir.write("loose.yaml", loose_text));
  const std::string w = nothing_holds_the_frame_warning(loose, build_scene(loose));
  EXPECT_NE(w.find("loose.yaml: nothing holds the frame up (no supports, no ground section, no contact.ground and no "
                   "fixed block), so under gravity (9.80665 m/s^2) it falls freely from the start"),
            std::string::npos)
      << w;
  std::ostringstream info;
  describe_case(loose, info);
  EXPECT_NE(info.str().find("nothing holds the frame up"), std::string::npos) << info.str();
  CaseRunOptions options;
  options.output_folder = dir.path() / "loose";
  const CaseRunReport report = run_case(loose, options);
  EXPECT_TRUE(mentions(report.warnings, "nothing holds the frame up")) << report.warnings.size();
  EXPECT_NEAR(last_history_value(dir.path() / "loose", "max_displacement_m"), 0.5 * 9.80665 * 0.1 * 0.1, 1e-6);
  // Standing on a contact with the ground (contact.ground alone puts its
  // surface at z = 0, where the portal's feet are), it is held up (docs
  // audit: such a frame was told it falls).
  const CaseDef standing = load_case_file(dir.write(
      "standing.yaml", loose_text + "contact: {ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.3, "
                                    "friction_coefficient: 0.5}}\n"));
  EXPECT_EQ(nothing_holds_the_frame_warning(standing, build_scene(standing)), "");
  // Weightless, it does not fall.
  std::string weightless = loose_text;
  weightless.replace(weightless.find(time), time.size(), "time:\n  gravity_mps2: [0, 0, 0]\n");
  const CaseDef floating = load_case_file(dir.write("weightless.yaml", weightless));
  EXPECT_EQ(nothing_holds_the_frame_warning(floating, build_scene(floating)), "");
  for (const auto& e : std::filesystem::directory_iterator(cases)) {
    if (e.path().extension() != ".yaml") continue;
    const CaseDef shipped = load_case_file(e.path());
    EXPECT_EQ(nothing_holds_the_frame_warning(shipped, build_scene(shipped)), "") << e.path();
  }
}

// A storey whose columns have lost every joint stands on loose posts, and
// its drift verdict says nothing of a frame any more (a house probe's storey
// read "damaged" with all 18 of its column joints broken). A squat post
// (100 mm cube of wood, 4.4 N) on a support whose shear springs fail at
// 0.15 N, under a ground acceleration ramped to 0.6 g: more than friction
// (mu = 0.3) carries, so the support breaks and the post slides on the
// ground; it cannot topple below g b / h = 1 g (statics), so it stands, and
// the run says the verdict is a loose post's. With strong shear springs
// nothing breaks and nothing is said.
TEST(RunWarnings, AStoreyOnLoosePostsIsToldItsVerdictIsThePostsDrift) {
  test::TempDir dir;
  {
    std::ofstream ramp(dir.path() / "ramp.txt");
    for (int i = 0; i <= 500; ++i) ramp << 0.001 * i << " " << 0.6 * 9.80665 * std::min(1.0, 0.01 * i) << "\n";
  }
  const auto post = [](double ultimate_shear_N) {
    std::ostringstream law;
    law << "law: trilinear, reference_length_m: 0.010, yield_strain_tension: 0.001, yield_force_tension_N: "
        << ultimate_shear_N / 1.5 << ", ultimate_strain_tension: 0.002, ultimate_force_tension_N: " << ultimate_shear_N
        << ", yield_strain_compression: 0.001, yield_force_compression_N: " << ultimate_shear_N / 1.5
        << ", ultimate_strain_compression: 0.002, ultimate_force_compression_N: " << ultimate_shear_N
        << ", damping_ratio: 0.05";
    return "framequake_case: 1\n"
           "name: post\n"
           "time: {dt_s: 1.0e-5, duration_s: 0.3}\n"
           "materials: [{name: wood, density_kg_per_m3: 450}]\n"
           "sections: [{name: sq100, width_m: 0.1, depth_m: 0.1}]\n"
           "nodes: [{id: foot, xyz_m: [0, 0, 0]}, {id: head, xyz_m: [0, 0, 0.1]}]\n"
           "members: [{id: post, kind: column, nodes: [foot, head], section: sq100, material: wood}]\n"
           "joint_types:\n"
           "  - name: weak\n"
           "    layout: four_corner\n"
           "    normal: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
           "    shear: {" + law.str() + "}\n"
           "    fracture: {criterion: any_spring_deleted}\n"
           "joints: {support_type: weak}\n"
           "supports: [{node: foot}]\n"
           "ground: {level_m: 0.0}\n"
           "contact: {ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.3, friction_coefficient: 0.3}}\n"
           "ground_motion: {components: [{file: ramp.txt, format: two_column, unit: m/s2, axis: x}]}\n"
           "output: {frame_interval_s: 0.1, history_interval_s: 0.01}\n";
  };
  CaseRunOptions options;
  options.output_folder = dir.path() / "weak";
  const CaseRunReport loose = run_case(load_case_file(dir.write("weak.yaml", post(0.15))), options);
  ASSERT_EQ(loose.joints.broken, 1);
  ASSERT_EQ(loose.storeys.size(), 1u);
  EXPECT_EQ(loose.storeys[0].verdict, StoreyVerdict::Standing);
  EXPECT_TRUE(mentions(loose.warnings, "storey 1: every joint of its column is broken (1 joint), so it stands, if at "
                                       "all, as a loose post on its contacts; its verdict (standing) follows the "
                                       "post's drift"))
      << testing::PrintToString(loose.warnings);
  options.output_folder = dir.path() / "strong";
  const CaseRunReport held = run_case(load_case_file(dir.write("strong.yaml", post(1.0e4))), options);
  EXPECT_EQ(held.joints.broken, 0);
  EXPECT_FALSE(mentions(held.warnings, "loose post")) << testing::PrintToString(held.warnings);
}

TEST(RunWarnings, AMemberNoJointHoldsIsNamed) {
  test::TempDir dir;
  const CaseDef floating = load_case_file(dir.write("floating.yaml", portal_case(0.31, 0.31)));
  const std::string w = unjoined_members_warning(floating, build_scene(floating));
  EXPECT_NE(w.find("1 member is held by no joint or support ('beam' (line 15))"), std::string::npos) << w;
  // Joined at one end only: held.
  const CaseDef one_end = load_case_file(dir.write("one_end.yaml", portal_case(0.3, 0.31)));
  EXPECT_EQ(unjoined_members_warning(one_end, build_scene(one_end)), "");
  const CaseDef joined = load_case_file(dir.write("joined.yaml", portal_case(0.3, 0.3)));
  EXPECT_EQ(unjoined_members_warning(joined, build_scene(joined)), "");
  for (const char* name : {"frame_A.yaml", "frame_B.yaml", "frame_C.yaml"}) {
    const CaseDef shipped = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / name);
    EXPECT_EQ(unjoined_members_warning(shipped, build_scene(shipped)), "") << name;
  }
}

std::filesystem::path shipped_case(const char* name) { return std::filesystem::path(FQ_SOURCE_DIR) / "cases" / name; }

// A shipped case's text, to be edited and written elsewhere: its records,
// named relative to its folder, are given as absolute paths.
std::string shipped_case_text_to_copy(const char* name) {
  const std::filesystem::path file = shipped_case(name);
  std::ifstream in(file);
  std::stringstream all;
  all << in.rdbuf();
  std::string text = all.str();
  for (std::size_t r = text.find("file: ground_motions/"); r != std::string::npos;
       r = text.find("file: ground_motions/", r + 1))
    text.replace(r, 6, "file: " + (file.parent_path() / "").string());
  return text;
}

// Frame C with its East brace's head node moved 12 mm off the corner it
// should reach (acceptance probe): that node is the end of the brace alone
// and no support holds it, so the brace is joined at its foot only. The
// shipped frame C, whose braces end at a column node and at a supported
// foot node, gets no warning.
TEST(RunWarnings, ABraceJoinedAtOneEndOnlyIsNamed) {
  test::TempDir dir;
  const std::filesystem::path shipped_c = shipped_case("frame_C.yaml");
  std::string text = shipped_case_text_to_copy("frame_C.yaml");
  const std::string brace = "{id: brace_e, kind: brace, nodes: [brace_e0, ne1],";
  const std::size_t at = text.find(brace);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, brace.size(), "{id: brace_e, kind: brace, nodes: [brace_e0, brace_e1],");
  const std::string nodes_key = "\nnodes:\n";
  const std::size_t nodes_at = text.find(nodes_key);
  ASSERT_NE(nodes_at, std::string::npos);
  text.insert(nodes_at + nodes_key.size(), "  - {id: brace_e1, xyz_m: [0.51, -0.012, 0.29]}\n");
  const CaseDef off = load_case_file(dir.write("frame_C_off.yaml", text));
  const std::string w = brace_free_ends_warning(off, build_scene(off));
  EXPECT_NE(w.find("frame_C_off.yaml: 1 brace is joined at one end only ('brace_e' (line "), std::string::npos) << w;
  EXPECT_NE(w.find("at node 'brace_e1'"), std::string::npos) << w;
  const CaseDef c = load_case_file(shipped_c);
  EXPECT_EQ(brace_free_ends_warning(c, build_scene(c)), "");
  // The head moved to the middle of the first-floor beam instead, which is
  // not split there: the node lies inside that beam, which the node-inside-
  // member warning names with its own advice (split the beam); the brace
  // warning does not say it again (review probe: two warnings, contrary
  // advice).
  std::string mid = text;
  const std::string off_node = "  - {id: brace_e1, xyz_m: [0.51, -0.012, 0.29]}\n";
  const std::size_t off_at = mid.find(off_node);
  ASSERT_NE(off_at, std::string::npos);
  mid.replace(off_at, off_node.size(), "  - {id: brace_e1, xyz_m: [0.255, 0.0, 0.29]}\n");
  const CaseDef midspan = load_case_file(dir.write("frame_C_midspan.yaml", mid));
  EXPECT_NE(nodes_inside_members_warning(midspan).find("node 'brace_e1'"), std::string::npos);
  EXPECT_EQ(brace_free_ends_warning(midspan, build_scene(midspan)), "");
}

// Frame C with its East brace's foot put on the column's supported base
// node se0 (retrofit probe) instead of a foot node of its own: the brace is
// then joined to the column there and to the ground, with no word of it.
// The shipped cases give no warning.
TEST(RunWarnings, ABraceFootOnAColumnsSupportedNodeIsNamed) {
  test::TempDir dir;
  std::string text = shipped_case_text_to_copy("frame_C.yaml");
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"{id: brace_e, kind: brace, nodes: [brace_e0, ne1],",
                                            "{id: brace_e, kind: brace, nodes: [se0, ne1],"},
        {"  - {node: brace_e0, joint_type: brace_end}", ""},
        {"  - {id: brace_e0,", "  - {id: brace_e0_unused,"}}) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const CaseDef moved = load_case_file(dir.write("frame_C_foot_on_column.yaml", text));
  const std::string w = brace_on_supported_node_warning(moved, build_scene(moved));
  EXPECT_NE(w.find("frame_C_foot_on_column.yaml: 1 brace ends at a supported node where another member ends too "
                   "('brace_e' (line "),
            std::string::npos)
      << w;
  EXPECT_NE(w.find(") at node 'se0' with 'column1_se'): such a brace is joined both to that member"), std::string::npos)
      << w;
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(FQ_SOURCE_DIR) / "cases")) {
    if (e.path().extension() != ".yaml") continue;
    const CaseDef c = load_case_file(e.path());
    EXPECT_EQ(brace_on_supported_node_warning(c, build_scene(c)), "") << e.path();
  }
}

// Frame C joins its members to the floor beams (hub_kind: beam), so a brace
// head at a node meets the beam as its hub and a rule for [column, brace]
// makes no joint (retrofit probe: such a rule was silently ignored). The
// shipped frame C's rules all make joints.
TEST(RunWarnings, AJointRuleThatMakesNoJointIsNamed) {
  test::TempDir dir;
  const std::filesystem::path shipped_c = shipped_case("frame_C.yaml");
  std::string text = shipped_case_text_to_copy("frame_C.yaml");
  const std::string rules = "  rules:\n";
  const std::size_t at = text.find(rules);
  ASSERT_NE(at, std::string::npos);
  text.insert(at + rules.size(), "    - {kinds: [column, brace], type: brace_end}\n");
  const int rule_line = int(std::count(text.begin(), text.begin() + long(at + rules.size()), '\n')) + 1;
  const std::string w = unused_joint_rules_warning(load_case_file(dir.write("frame_C_rule.yaml", text)));
  EXPECT_NE(w.find("frame_C_rule.yaml: 1 joint rule makes no joint ([column, brace] (line " +
                   std::to_string(rule_line) + "))"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("the first member of kind beam there"), std::string::npos) << w;
  EXPECT_EQ(unused_joint_rules_warning(load_case_file(shipped_c)), "");
  // The same rule in a joints mapping written on one line, the line the
  // default type's joints were tagged with: still named (docs probe).
  std::string flow = shipped_case_text_to_copy("frame_C.yaml");
  const std::string block = "joints:\n  hub_kind: beam\n  default_type: tenon_new\n  support_type: tenon_new\n"
                            "  rules:\n    - {kinds: [beam, brace], type: brace_end}";
  const std::size_t from = flow.find(block);
  ASSERT_NE(from, std::string::npos);
  flow.replace(from, block.size(),
               "joints: {hub_kind: beam, default_type: tenon_new, support_type: tenon_new, rules: [{kinds: [beam, "
               "brace], type: brace_end}, {kinds: [column, brace], type: brace_end}]}");
  const int joints_line = int(std::count(flow.begin(), flow.begin() + long(from), '\n')) + 1;
  const std::string one_line = unused_joint_rules_warning(load_case_file(dir.write("frame_C_flow.yaml", flow)));
  EXPECT_NE(one_line.find("1 joint rule makes no joint ([column, brace] (line " + std::to_string(joints_line) + "))"),
            std::string::npos)
      << one_line;
}

TEST(RunWarnings, AVerticalRecordAppliedHorizontallyAndTheReverseAreNamed) {
  // Two PEER records whose headers name their components, "UP" and "090",
  // applied along x and along z: the vertical one along x and the
  // horizontal one along z are warned about, the other two pairings are
  // not; the shipped frames (JMA Kobe NS, "0" in its header, along x)
  // have none.
  test::TempDir dir;
  const std::string samples = "NPTS=    5, DT= .0100 SEC\n 0.0 0.001 0.002 0.001 0.0\n";
  std::ofstream(dir.path() / "up.at2") << "PEER NGA STRONG MOTION DATABASE RECORD\nSome quake, 1/1/2000, Station, UP\n"
                                          "ACCELERATION TIME SERIES IN UNITS OF G\n" << samples;
  std::ofstream(dir.path() / "h090.at2") << "PEER NGA STRONG MOTION DATABASE RECORD\nSome quake, 1/1/2000, Station, 090\n"
                                            "ACCELERATION TIME SERIES IN UNITS OF G\n" << samples;
  auto warnings_for = [&](const std::string& file, const std::string& axis) {
    const std::string text =
        "framequake_case: 1\n"
        "time: {dt_s: 1.0e-4, duration_s: 0.01}\n"
        "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
        "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: spruce}]\n"
        "ground_motion: {components: [{file: " + file + ", format: peer_at2, axis: " + axis + "}]}\n";
    const CaseDef def = load_case_file(dir.write("gm.yaml", text));
    return ground_motion_direction_warnings(build_scene(def).simulation->ground_motion());
  };
  const auto up_x = warnings_for("up.at2", "x");
  ASSERT_EQ(up_x.size(), 1u);
  EXPECT_NE(up_x[0].find("is a vertical component ('UP' in its header"), std::string::npos) << up_x[0];
  EXPECT_NE(up_x[0].find("up.at2"), std::string::npos) << up_x[0];
  EXPECT_TRUE(warnings_for("up.at2", "z").empty());
  EXPECT_TRUE(warnings_for("up.at2", "[0.2, 0, -1]").empty());
  const auto h_z = warnings_for("h090.at2", "-z");
  ASSERT_EQ(h_z.size(), 1u);
  EXPECT_NE(h_z[0].find("is a horizontal component ('090'"), std::string::npos) << h_z[0];
  EXPECT_TRUE(warnings_for("h090.at2", "y").empty());
  // "Mostly" is a side of 45 degrees above the horizontal: 42 degrees up
  // ([1, 0, 0.9]) is mostly horizontal (a 30 degree cut called it mostly
  // vertical), 50 degrees up is mostly vertical, 45 degrees is neither.
  EXPECT_TRUE(warnings_for("h090.at2", "[1, 0, 0.9]").empty());
  EXPECT_EQ(warnings_for("up.at2", "[1, 0, 0.9]").size(), 1u);
  EXPECT_EQ(warnings_for("h090.at2", "[1, 0, 1.2]").size(), 1u);
  EXPECT_TRUE(warnings_for("up.at2", "[1, 0, 1.2]").empty());
  EXPECT_TRUE(warnings_for("h090.at2", "[0, 1, 1]").empty());
  EXPECT_TRUE(warnings_for("up.at2", "[0, 1, 1]").empty());
  for (const char* name : {"frame_A.yaml", "frame_B.yaml", "frame_C.yaml"}) {
    const CaseDef shipped = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / name);
    EXPECT_TRUE(ground_motion_direction_warnings(build_scene(shipped).simulation->ground_motion()).empty()) << name;
  }
}

// A time step longer than the record's sample interval as the run plays it
// (dt x time_scale) steps over samples: a 5 m/s^2 spike sampled at 0.01 s,
// between steps of 0.02 s, is never applied (the motion at the step times
// 0, 0.02, 0.04... is zero: linear interpolation between zero samples), and
// the warning says so with both peaks. At dt = 0.01 s every sample is a
// step; at time_scale 0.5 the same dt is twice the played interval
// (stable-step probe: no warning, and summary.json gave 5 m/s^2 as the peak).
TEST(RunWarnings, AStepLongerThanTheRecordsSamplesIsNamedWithThePeakItApplies) {
  test::TempDir dir;
  std::ofstream(dir.path() / "spike.txt") << "0 0\n0.01 5\n0.02 0\n0.03 0\n0.04 0\n0.05 0\n0.06 0\n0.07 0\n0.08 0\n";
  auto warning_for = [&](double dt_s, double time_scale, const char* integrator = "central_difference") {
    std::ostringstream text;
    text << "framequake_case: 1\n"
            "time: {dt_s: " << dt_s << ", duration_s: 0.08, integrator: " << integrator << "}\n"
            "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
            "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: spruce}]\n"
            "ground_motion: {time_scale: " << time_scale
         << ", components: [{file: spike.txt, format: two_column, axis: x}]}\n";
    const CaseDef def = load_case_file(dir.write("gm.yaml", text.str()));
    return ground_motion_sampling_warning(*build_scene(def).simulation);
  };
  const std::string w = warning_for(0.02, 1.0);
  EXPECT_NE(w.find("time.dt_s = 0.02 s is longer than the sample interval of"), std::string::npos) << w;
  EXPECT_NE(w.find("= 0.01 s)"), std::string::npos) << w;
  EXPECT_NE(w.find("applies a peak ground acceleration of 0 m/s^2 along x where the record holds 5 m/s^2"),
            std::string::npos)
      << w;
  EXPECT_EQ(warning_for(0.01, 1.0), "");
  EXPECT_EQ(warning_for(0.001, 1.0), "");
  // gsl_rk8pd evaluates the motion at its own sub-steps within dt_s: the
  // spike between its steps of 0.02 s is met, and no warning is given.
  EXPECT_EQ(warning_for(0.02, 1.0, "gsl_rk8pd"), "");
  const std::string scaled = warning_for(0.01, 0.5);
  EXPECT_NE(scaled.find("x time_scale 0.5 = 0.005 s"), std::string::npos) << scaled;
  // Steps at 0, 0.01, 0.02... simulated s play the record at 0, 0.02,
  // 0.04... record s: the spike at 0.01 record s is missed again.
  EXPECT_NE(scaled.find("peak ground acceleration of 0 m/s^2"), std::string::npos) << scaled;
  // The shipped frames play Kobe's 0.02 s samples at 0.3162 x 0.02 s, far
  // longer than their 1e-5 s step.
  for (const char* name : {"frame_A.yaml", "frame_B.yaml", "frame_C.yaml"}) {
    const CaseDef shipped = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / name);
    EXPECT_EQ(ground_motion_sampling_warning(*build_scene(shipped).simulation), "") << name;
  }
}

// rk4 is fourth order only where the forcing is smooth within each step; a
// record is linear between its samples, so a sample inside a step (or the
// window's end, where the motion stops) costs it an error of order dt^2
// there (BaseExcitation.RungeKutta4* in tests/joints/test_base_excitation.cpp
// measures both orders against the exact oscillator). The warning names the
// first such time and, for an evenly sampled record whose window starts on
// a sample, a step that divides the played interval. Record: samples every
// 0.01 s.
TEST(RunWarnings, RungeKutta4WithRecordSamplesInsideItsStepsIsToldTheStepThatAvoidsThem) {
  test::TempDir dir;
  std::ofstream(dir.path() / "spike.txt") << "0 0\n0.01 5\n0.02 0\n0.03 1\n0.04 0\n0.05 2\n0.06 0\n0.07 0\n0.08 0\n";
  auto warning_for = [&](const char* integrator, double dt_s, const std::string& window) {
    std::ostringstream text;
    text << "framequake_case: 1\n"
            "time: {dt_s: " << dt_s << ", duration_s: 0.08, integrator: " << integrator << "}\n"
            "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
            "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: spruce}]\n"
            "ground_motion: {time_scale: 1.0" << window
         << ", components: [{file: spike.txt, format: two_column, axis: x}]}\n";
    const CaseDef def = load_case_file(dir.write("gm.yaml", text.str()));
    return runge_kutta_sampling_warning(*build_scene(def).simulation);
  };
  // 0.01 s / 4: every sample on a step boundary.
  EXPECT_EQ(warning_for("rk4", 0.0025, ""), "");
  // 0.003 s: the sample at 0.01 s is 3.33 steps in; 0.01 / ceil(0.01 / 0.003) = 0.0025 s.
  const std::string w = warning_for("rk4", 0.003, "");
  EXPECT_NE(w.find("at dt_s = 0.003 s a sample of"), std::string::npos) << w;
  EXPECT_NE(w.find("(at t = 0.01 s; the record is linear between its samples"), std::string::npos) << w;
  EXPECT_NE(w.find("falls inside a step"), std::string::npos) << w;
  EXPECT_NE(w.find("give dt_s = 0.0025 s,"), std::string::npos) << w;
  // Central difference is second order whatever the samples: not warned.
  EXPECT_EQ(warning_for("central_difference", 0.003, ""), "");
  // A window ending between samples (0.044 s, 17.6 steps of 0.0025 s): the
  // motion stops inside a step.
  const std::string end = warning_for("rk4", 0.0025, ", window_length_s: 0.044");
  EXPECT_NE(end.find("the end of the window of"), std::string::npos) << end;
  EXPECT_NE(end.find("(at t = 0.044 s) falls inside a step"), std::string::npos) << end;
  // Where the forcing is zero and flat (the record's last samples are
  // zeros) an end inside a step (0.075 s, 37.5 steps of 0.002 s) bends
  // nothing; at 0.045 s (a = 1 m/s^2 there) it does.
  EXPECT_EQ(warning_for("rk4", 0.002, ", window_length_s: 0.075"), "");
  EXPECT_NE(warning_for("rk4", 0.002, ", window_length_s: 0.045").find("(at t = 0.045 s) falls inside a step"),
            std::string::npos);
  // A window starting between samples (record time 0.005 s): the samples
  // play at 0.005, 0.015, ... s, which steps of 0.002 s miss (2.5 steps
  // in). A step must divide 0.005 s as well as 0.01 s: 0.005 / ceil(0.005 /
  // 0.002) = 0.005 / 3 (review probe: no step was suggested).
  const std::string start = warning_for("rk4", 0.002, ", window_start_s: 0.005");
  EXPECT_NE(start.find("(at t = 0.005 s;"), std::string::npos) << start;
  EXPECT_NE(start.find("give dt_s = 0.00166666666666667 s,"), std::string::npos) << start;
  EXPECT_EQ(warning_for("rk4", 0.005 / 3.0, ", window_start_s: 0.005"), "");
}

// The integrator probe's cases: a suggested dt_s, typed back as printed,
// must clear the warning over a long run (time_scale 0.3162, 20 record s,
// 14 000 steps); a window ending inside a step is told to end on a sample,
// not given its own dt_s back; two records sampled at 0.02 and 0.01 s get
// one step that divides both.
TEST(RunWarnings, RungeKutta4SuggestionsClearTheWarningForLongRunsWindowEndsAndTwoRecords) {
  test::TempDir dir;
  {
    std::ofstream coarse(dir.path() / "coarse.txt"), fine(dir.path() / "fine.txt");
    for (int k = 0; k <= 1000; ++k) coarse << 0.02 * k << " " << std::sin(0.37 * k) << "\n";
    for (int k = 0; k <= 2000; ++k) fine << 0.01 * k << " " << std::cos(0.23 * k) << "\n";
  }
  auto warning_for = [&](const std::string& dt_s, const std::string& motion) {
    const std::string text = "framequake_case: 1\ntime: {dt_s: " + dt_s + ", integrator: rk4}\n"
                             "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
                             "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: spruce}]\n"
                             "ground_motion: " + motion + "\n";
    return runge_kutta_sampling_warning(*build_scene(load_case_file(dir.write("gm.yaml", text))).simulation);
  };
  auto suggested = [](const std::string& w) {
    const std::string key = "give dt_s = ";
    const auto at = w.find(key);
    return at == std::string::npos ? std::string() : w.substr(at + key.size(), w.find(' ', at + key.size()) - at - key.size());
  };
  // Played interval 0.02 x 0.3162 = 0.006324 s; 0.006324 / ceil(0.006324 / 0.0005) = 0.006324 / 13.
  const std::string scaled = "{time_scale: 0.3162, components: [{file: coarse.txt, format: two_column, axis: x}]}";
  const std::string w = warning_for("0.0005", scaled);
  const std::string dt = suggested(w);
  ASSERT_FALSE(dt.empty()) << w;
  EXPECT_NEAR(std::stod(dt), 0.006324 / 13.0, 1e-15) << w;
  EXPECT_EQ(warning_for(dt, scaled), "");
  // Typed to 10 digits, as a user may: 14 000 steps put the last sample
  // about 1e-6 of a step off a boundary, which costs nothing (counted as on
  // it within 1e-4 of a step).
  char ten_digits[32];
  std::snprintf(ten_digits, sizeof ten_digits, "%.10g", std::stod(dt));
  EXPECT_EQ(warning_for(ten_digits, scaled), "") << ten_digits;
  // The window ends at 19.99 record s (6.320838 s), inside a step of
  // 0.006324 / 13 s although every sample is on a boundary.
  const std::string cut =
      "{time_scale: 0.3162, window_length_s: 19.99, components: [{file: coarse.txt, format: two_column, axis: x}]}";
  const std::string end = warning_for(dt, cut);
  EXPECT_NE(end.find("the end of the window of"), std::string::npos) << end;
  EXPECT_NE(end.find("give the window's length (window_length_s, or --window-length of compare and sweep) a whole "
                     "number of the record's samples (0.02 s)"),
            std::string::npos)
      << end;
  EXPECT_EQ(end.find("give dt_s"), std::string::npos) << end;
  // Two records: 0.01 / 3 = 0.00333 s divides both 0.01 s and 0.02 s. The
  // earliest sample inside a step is named, the fine record's at 0.01 s,
  // not the first component's at 0.02 s (review probe).
  const std::string both =
      "{components: [{file: coarse.txt, format: two_column, axis: x}, {file: fine.txt, format: two_column, axis: y}]}";
  const std::string two = warning_for("0.0045", both);
  EXPECT_NEAR(std::stod(suggested(two)), 0.01 / 3.0, 1e-15) << two;
  EXPECT_NE(two.find("fine.txt (at t = 0.01 s;"), std::string::npos) << two;
  EXPECT_EQ(warning_for(suggested(two), both), "");
  // A window starting between samples of the coarse record (1.01 s): the
  // step must divide the first sample's 0.01 s and the 0.02 s interval.
  const std::string between =
      "{window_start_s: 1.01, components: [{file: coarse.txt, format: two_column, axis: x}]}";
  const std::string off = warning_for("0.003", between);
  EXPECT_NEAR(std::stod(suggested(off)), 0.0025, 1e-15) << off;
  EXPECT_EQ(warning_for(suggested(off), between), "");
  // An unevenly sampled record (gaps of 0.01 and 0.015 s): 0.01 / 34 divides both.
  {
    std::ofstream uneven(dir.path() / "uneven.txt");
    double t = 0.0;
    for (int k = 0; k < 200; ++k, t += (k % 2 ? 0.01 : 0.015)) uneven << t << " " << std::sin(0.3 * k) << "\n";
  }
  const std::string gaps = "{components: [{file: uneven.txt, format: two_column, axis: x}]}";
  const std::string u = warning_for("0.0003", gaps);
  EXPECT_NEAR(std::stod(suggested(u)), 0.01 / 34.0, 1e-15) << u;
  EXPECT_EQ(warning_for(suggested(u), gaps), "");
  // A window that ends on a sample (the record's own end at 20 s, from 19.9
  // s), in a run that goes on past it: the step alone is advised, not a
  // window of whole samples, which it already is (review probe).
  const std::string past_end = "framequake_case: 1\ntime: {dt_s: 0.003, duration_s: 0.2, integrator: rk4}\n"
                               "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
                               "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: spruce}]\n"
                               "ground_motion: {window_start_s: 19.9, components: [{file: coarse.txt, "
                               "format: two_column, axis: x}]}\n";
  const std::string ends = runge_kutta_sampling_warning(*build_scene(load_case_file(dir.write("end.yaml", past_end))).simulation);
  EXPECT_NE(ends.find("give dt_s = 0.00285714285714286 s,"), std::string::npos) << ends;  // 0.02 / 7
  EXPECT_EQ(ends.find("window_length_s"), std::string::npos) << ends;
}

// record_aligned_step_s: the step divides the played interval and the time
// of the first played sample; records whose played intervals have no
// common step have none.
TEST(RunWarnings, RecordAlignedStepDividesIntervalsAndTheFirstSamplesTime) {
  auto component = [](double record_dt_s, double time_scale, double start_s) {
    GroundMotionComponent c;
    c.record.dt_s = record_dt_s;
    c.record.acceleration_mps2.assign(100, 0.0);
    c.time_scale = time_scale;
    c.window_start_s = start_s;
    return c;
  };
  GroundMotion one;
  one.add_component(component(0.02, 0.5, 0.2));
  // 0.01 s played: 0.01 / ceil(0.01 / 0.003) = 0.0025 s.
  EXPECT_NEAR(record_aligned_step_s(one, 0.003), 0.0025, 1e-17);
  // From record time 0.21 s the first sample (0.22 s) plays at 0.005 s:
  // 0.005 / ceil(0.005 / 0.003) = 0.0025 s, which divides 0.01 s too; at
  // most 0.002 s: 0.005 / 3, which 0.01 s holds 6 times.
  GroundMotion off;
  off.add_component(component(0.02, 0.5, 0.21));
  EXPECT_NEAR(record_aligned_step_s(off, 0.003), 0.0025, 1e-15);
  EXPECT_NEAR(record_aligned_step_s(off, 0.002), 0.005 / 3.0, 1e-15);
  GroundMotion mixed;
  mixed.add_component(component(0.02, 0.5, 0.2));
  mixed.add_component(component(0.02, 0.5 * std::sqrt(2.0), 0.2));  // intervals in the ratio sqrt 2
  EXPECT_EQ(record_aligned_step_s(mixed, 0.003), 0.0);
}

// A record header in Latin-1 ("D\xFCzce", as older files carry) reaches
// summary.json through the vertical-component warning that quotes it. The
// file must be UTF-8 JSON holding "Düzce" (records probe: the raw byte FC
// made json.loads fail). Checked by this library's validator and,
// independently, by Python's json reading the bytes as strict UTF-8.
TEST(RunWarnings, ALatin1RecordHeaderReachesSummaryJsonAsUtf8) {
  test::TempDir dir;
  dir.write("duzce_up.at2", "PEER NGA STRONG MOTION DATABASE RECORD\n"
                            "D\xFCzce, Turkey, 11/12/1999, D\xFCzce, UP\n"
                            "ACCELERATION TIME SERIES IN UNITS OF G\n"
                            "NPTS=    5, DT= .0100 SEC\n 0.0 0.001 0.002 0.001 0.0\n");
  const CaseDef def = load_case_file(dir.write(
      "duzce.yaml",
      "framequake_case: 1\n"
      "name: duzce\n"
      "time: {dt_s: 1.0e-4, duration_s: 0.01}\n"
      "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
      "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: spruce}]\n"
      "ground_motion: {components: [{file: duzce_up.at2, format: peer_at2, axis: x}]}\n"
      "output: {frame_interval_s: 0.01, history_interval_s: 0.01}\n"));
  CaseRunOptions options;
  options.output_folder = dir.path() / "run";
  const CaseRunReport report = run_case(def, options);
  // "D" U+00FC "zce" in UTF-8, U+00FC = C3 BC.
  const std::string duzce = "D\xC3\xBCzce, Turkey, 11/12/1999, D\xC3\xBCzce, UP";
  ASSERT_TRUE(mentions(report.warnings, duzce)) << (report.warnings.empty() ? "" : report.warnings[0]);
  const std::filesystem::path summary_file = dir.path() / "run" / "summary.json";
  std::ifstream in(summary_file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string summary = text.str();
  EXPECT_TRUE(is_valid_utf8(summary));
  EXPECT_TRUE(json_is_valid(summary));
  EXPECT_NE(summary.find(duzce), std::string::npos) << summary;
  if (std::system("/usr/bin/python3 -c 'import json' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 not available for the independent check";
  const std::string cmd =
      "/usr/bin/python3 -c \"import json,sys; d=json.loads(open(sys.argv[1],'rb').read().decode('utf-8')); "
      "sys.exit(0 if any('D\\u00fczce, Turkey' in w for w in d['warnings']) else 1)\" '" +
      summary_file.string() + "'";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << summary;
}

// info lists a storey's first 12 columns and counts the rest, like its
// other lists (a 35x35 grid printed 1296 names a storey, 12 KB a line;
// scale probe). A row of 15 columns, c00 to c14, tops at 0.39 m joined by
// beams; c01 and c13 stand on a 0.1 m step, so they are 0.29 m tall: c01,
// listed, keeps its height note, c13 is one of the 3 not listed.
TEST(RunWarnings, InfoListsAStoreysFirstTwelveColumns) {
  test::TempDir dir;
  std::ostringstream text;
  text << "framequake_case: 1\n"
          "time: {dt_s: 1.0e-5, duration_s: 0.001}\n"
          "materials: [{name: wood, density_kg_per_m3: 450}]\n"
          "sections: [{name: s, width_m: 0.010, depth_m: 0.020}]\n"
          "nodes:\n";
  char id[8];
  for (int k = 0; k < 15; ++k) {
    std::snprintf(id, sizeof id, "%02d", k);
    text << "  - {id: f" << id << ", xyz_m: [" << 0.5 * k << ", 0, " << (k == 1 || k == 13 ? 0.1 : 0.0) << "]}\n"
         << "  - {id: t" << id << ", xyz_m: [" << 0.5 * k << ", 0, 0.39]}\n";
  }
  text << "members:\n";
  for (int k = 0; k < 15; ++k) {
    std::snprintf(id, sizeof id, "%02d", k);
    text << "  - {id: c" << id << ", kind: column, nodes: [f" << id << ", t" << id << "], section: s, material: wood}\n";
    if (k == 0) continue;
    char prev[8];
    std::snprintf(prev, sizeof prev, "%02d", k - 1);
    text << "  - {id: b" << id << ", kind: beam, nodes: [t" << prev << ", t" << id << "], section: s, material: wood}\n";
  }
  std::ostringstream info;
  describe_case(load_case_file(dir.write("row.yaml", text.str())), info);
  EXPECT_NE(info.str().find("1 from z = 0 to 0.39 m, 15 columns: c00, c01 (0.29 m), c02, c03, c04, c05, c06, c07, c08, "
                            "c09, c10, c11, ... and 3 more\n"),
            std::string::npos)
      << info.str();
  EXPECT_EQ(info.str().find("c12"), std::string::npos) << info.str();
}

// Sets `stop` once the run has taken `steps` steps; counts its calls and
// the largest gap in steps between two of them.
class StepCounter final : public StepObserver {
 public:
  StepCounter(std::atomic<bool>* stop, std::int64_t steps) : stop_(stop), steps_(steps) {}
  void on_sample(const Simulation& sim) override {
    if (calls > 0) largest_gap = std::max(largest_gap, sim.steps_done() - last_step);
    last_step = sim.steps_done();
    ++calls;
    if (stop_ && sim.steps_done() >= steps_) stop_->store(true);
  }
  std::int64_t calls = 0, last_step = 0, largest_gap = 0;

 private:
  std::atomic<bool>* stop_;
  std::int64_t steps_;
};

// The output estimate bounds the frames to come: frame B with a frame
// every 20 steps and a row every step says it at its tenth row, when frame
// 0 (every velocity and force zero, so it compresses best) is the only
// frame; frames 1 to 3 on disk are each at most the size it gave. (It took
// frame 0's own size, 4.5-5 times too small at scale; scale probe.) 1e7
// steps of frames of some kB is above the 1 GB that earns a note (or a
// warning where the disk has less free).
TEST(RunWarnings, TheOutputEstimateBoundsTheFramesAfterAnAllZeroFrameZero) {
  test::TempDir dir;
  CaseDef def = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / "frame_B.yaml");
  def.time.duration_s = 1e7 * def.time.dt_s;
  def.output.history_interval_s = def.time.dt_s;
  def.output.frame_interval_s = 20 * def.time.dt_s;
  std::atomic<bool> stop{false};
  StepCounter stopper(&stop, 3 * 20);  // frames 0 to 3, then the stop's frame
  CaseRunOptions options;
  options.output_folder = dir.path() / "b";
  options.stop_requested = &stop;
  options.progress = &stopper;
  std::vector<std::string> said;
  options.on_note = [&](const std::string& n) { said.push_back(n); };
  options.on_warning = [&](const std::string& w) { said.push_back(w); };
  run_case(def, options);
  std::smatch m;
  const std::regex estimate("this run will write up to about [0-9.]+ [GM]B more output \\(([0-9]+) frames of up to "
                            "about ([0-9.e+]+) kB");
  const auto it = std::find_if(said.begin(), said.end(), [&](const std::string& s) { return std::regex_search(s, m, estimate); });
  ASSERT_NE(it, said.end()) << said.size();
  const double frame_bytes = std::stod(m[2].str()) * 1e3;
  EXPECT_GE(std::stod(m[1].str()), 1e7 / 20 - 1);  // the frames still to come
  for (std::size_t k = 1; k <= 3; ++k) {
    const auto path = frame_path(dir.path() / "b", k);
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    EXPECT_LE(double(std::filesystem::file_size(path)), frame_bytes) << path << " against " << *it;
  }
}

// The progress observer is asked after every step, whatever the output
// intervals: asked every 1000 steps, which at dt = 1e-5 s were also the
// history rows of 0.01 s, the display of a 19k-body frame changed every
// 15-20 s (scale probe). 2000 steps with one row and one frame at the
// start and one at the end: asked at step 0 and after each step.
TEST(RunWarnings, ProgressIsAskedEveryStepWhateverTheOutputIntervals) {
  test::TempDir dir;
  CaseDef def = load_case_file(dir.write("cube.yaml", cube_case(1e-5)));
  def.time.duration_s = 2000 * 1e-5;
  def.output.history_interval_s = 1.0;
  def.output.frame_interval_s = 1.0;
  StepCounter counter(nullptr, 0);
  CaseRunOptions options;
  options.output_folder = dir.path() / "cube";
  options.progress = &counter;
  run_case(def, options);
  EXPECT_EQ(counter.last_step, 2000);
  EXPECT_EQ(counter.calls, 2001);
  EXPECT_EQ(counter.largest_gap, 1);
}

}  // namespace
// A floor that slid because its joint broke says so (closed-form probe,
// stop 41): in the shipped breaking cantilever the arm, storey 1's
// "floor", falls when its weak tenon to the column breaks, which read as a
// floor sliding on a joint soft in shear. Of the column's two joints (its
// support and that tenon) one broke: the warning counts them, as
// events.csv does.
TEST(RunWarnings, AFloorThatSlidOffABrokenJointSaysTheJointBroke) {
  const test::TempDir dir;
  const CaseDef def = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / "demo_breaking_cantilever.yaml");
  CaseRunOptions options;
  options.output_folder = dir.path() / "cantilever";
  const CaseRunReport r = run_case(def, options);
  ASSERT_EQ(r.joints.broken, 1u);
  EXPECT_TRUE(mentions(r.warnings, "the floor slid up to ")) << testing::PrintToString(r.warnings);
  EXPECT_TRUE(mentions(r.warnings, " on its column tops (1 of the 2 joints holding its column broke; events.csv "
                                   "lists them); "))
      << testing::PrintToString(r.warnings);
  EXPECT_FALSE(mentions(r.warnings, "soft in shear")) << testing::PrintToString(r.warnings);
}

}  // namespace fq
