// The stable-time-step estimate of a whole scene (case_runner.cpp,
// estimate_stable_time_step: one network of the joints' and the present
// contacts' spring-dashpots, dem_core/linearised_network.h) against the
// limit found by running central difference, for a body held by two
// providers at once: a 20 x 20 x 100 mm column on a four-corner support
// joint (1e6 N/m per spring) that also stands on the ground (contact
// k_n = 1e6 N/m per corner, friction 10 so nothing slides). Its joint and
// its contact act on the same degrees of freedom and add; taking the
// stiffer of the two alone, as the estimate did before 2026-11-26, put the
// limit 1.4 times too high (6.7e-5 s against 4.8e-5 s bisected).
//
// Runs: gravity on, no ground motion, small random velocities that excite
// every mode, 4000 steps. A run is unstable when its motion (displacement
// of the centre plus rotation times the half length) leaves 1e-5 m, far
// above the 1e-8 m of the gravity load and the perturbation: past the
// limit, at omega dt = 2 (1 + eps), central difference multiplies the top
// mode by about exp(2 sqrt(eps)) a step, so from the perturbation's
// 1e-10 m or so it passes 1e-5 m within 6 / sqrt(eps) steps, inside the
// run for every eps above 2.3e-6, far finer than the 10 % asked. With
// dashpots a run is also unstable when the speed of its last quarter does
// not fall below half that of the first. The bisected limit must lie
// within 10 % of the estimate (issue 6).
//
// (Undamped runs were also called unstable when the second half of the run
// peaked above twice the first half. The column starts unloaded, so its
// corner contacts open and close with the gravity sag every period, and
// that piecewise-linear motion hands energy from the vertical swing to the
// rocking: a stable run tripped that test at 0.87 of the estimate for 6 of
// 200 random perturbations, an audit found (stop 42), though its motion
// stayed below 2.1e-7 m for five times the run. Seed 11, the one the test
// uses, did not.)
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <sstream>
#include <string>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io_test_util.h"

namespace fq {
namespace {

using test::TempDir;

std::string column_case(double joint_damping_ratio, double restitution) {
  std::ostringstream s;
  s << "framequake_case: 1\n"
       "name: column_on_joint_and_ground\n"
       "time: {dt_s: 1.0e-6, duration_s: 1.0e-3}\n"
       "materials: [{name: wood, density_kg_per_m3: 450}]\n"
       "sections: [{name: col, width_m: 0.02, depth_m: 0.02}]\n"
       "nodes: [{id: base, xyz_m: [0, 0, 0]}, {id: top, xyz_m: [0, 0, 0.1]}]\n"
       "members: [{id: col, kind: column, nodes: [base, top], section: col, material: wood}]\n"
       "joint_types:\n"
       "  - name: s\n"
       "    layout: four_corner\n"
       "    corner_fraction: 1.0\n"
       "    normal: {law: linear, stiffness_N_per_m: 1.0e6, damping_ratio: "
    << joint_damping_ratio
    << "}\n"
       "    shear: {law: linear, stiffness_N_per_m: 1.0e6, damping_ratio: "
    << joint_damping_ratio
    << "}\n"
       "joints: {support_type: s}\n"
       "supports: [{node: base}]\n"
       "ground: {level_m: 0.0}\n"
       "contact:\n"
       "  ground: {normal_stiffness_N_per_m: 1.0e6, restitution: "
    << restitution << ", friction_coefficient: 10.0}\n";
  return s.str();
}

bool stable(const CaseDef& def, double dt_s, bool damped) {
  CaseDef d = def;
  d.time.dt_s = dt_s;
  const int steps = 4000;
  d.time.duration_s = dt_s * steps;
  Scene scene = build_scene(d);
  Simulation& sim = *scene.simulation;
  BodyStore& bodies = sim.bodies();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::size_t column = 0;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (bodies.is_fixed[b]) continue;
    column = b;
    bodies.velocity_mps[b] = 1e-5 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 w = 1e-3 * Vec3(u(rng), u(rng), u(rng));
    bodies.angular_velocity_radps[b] = w;
    bodies.angular_momentum_Nms[b] = bodies.rotation[b] * bodies.principal_inertia_kgm2[b].asDiagonal() *
                                     (bodies.rotation[b].transpose() * w);
  }
  const Vec3 x0 = bodies.position_m[column];
  const Quat q0 = bodies.orientation[column];
  const double half_length = bodies.half_extents_m[column].maxCoeff();
  double first = 0.0, last = 0.0;  // peak speeds of the first and last quarters (damped runs)
  for (int n = 0; n < steps; ++n) {
    if (!sim.step()) return false;
    const double motion = (bodies.position_m[column] - x0).norm() +
                          half_length * bodies.orientation[column].angularDistance(q0);
    if (!(motion < 1e-5)) return false;
    if (!damped || (n >= steps / 4 && n < 3 * steps / 4)) continue;
    const double speed = bodies.velocity_mps[column].norm() + half_length * bodies.angular_velocity_radps[column].norm();
    double& quarter = n < steps / 2 ? first : last;
    quarter = std::max(quarter, speed);
  }
  return !damped || last < 0.5 * first;
}

void check(double joint_damping_ratio, double restitution, const char* label) {
  TempDir dir;
  const CaseDef def = load_case_file(dir.write("column.yaml", column_case(joint_damping_ratio, restitution)));
  const Scene probe = build_scene(def);
  const double estimate = probe.stable_time_step.dt_crit_s;
  ASSERT_TRUE(std::isfinite(estimate));
  const bool damped = joint_damping_ratio > 0.0 || restitution < 1.0;
  double lo = 0.5 * estimate, hi = 1.5 * estimate;
  for (int it = 0; it < 12; ++it) {
    const double mid = 0.5 * (lo + hi);
    (stable(def, mid, damped) ? lo : hi) = mid;
  }
  const double bisected = 0.5 * (lo + hi);
  std::cout << "[" << label << "] estimate " << estimate << " s (" << probe.stable_time_step.stiffest_element
            << "), bisected " << bisected << " s, ratio " << bisected / estimate << "\n";
  EXPECT_NEAR(bisected / estimate, 1.0, 0.10) << label;
}

TEST(SceneStableStep, ColumnOnAJointAndOnTheGroundAddsBoth) { check(0.0, 1.0, "undamped joint and contact"); }

TEST(SceneStableStep, ColumnOnADampedJointAndADampedContact) { check(0.05, 0.5, "damped joint and contact"); }

// The refusal names the stiffest joint by its name (node:member_a-member_b,
// as events.csv and `info --joints` give it), not only by its id, which
// changes from case to case (stable-step probe).
TEST(SceneStableStep, TheStiffestJointIsNamed) {
  TempDir dir;
  std::string text = column_case(0.0, 1.0);
  text = text.substr(0, text.find("ground: {level_m"));  // the joint alone
  const Scene scene = build_scene(load_case_file(dir.write("column.yaml", text)));
  const std::string& where = scene.stable_time_step.stiffest_element;
  EXPECT_NE(where.find("joint 0 "), std::string::npos) << where;
  EXPECT_NE(where.find("named 'base:ground-col'"), std::string::npos) << where;
}

// RK4 on a heavily overdamped spring: a 10 g member on a single-point
// support joint, k = 100 N/m (omega = 100 rad/s) with a damping ratio of 20,
// gravity along the member. Its fast root decays at s = omega (zeta +
// sqrt(zeta^2 - 1)) = 3997.5 1/s, and RK4 is stable on it only while s dt
// <= 2.7853 (the negative real axis of its stability region): dt <=
// 6.9676e-4 s, closed form. 2 sqrt 2 times the leapfrog network's damped
// limit gave 7.067e-4 s, 1.4 % above it, and a run at that step blew up
// (integrator probe); the estimate must now lie at or below the closed
// form, within 0.1 % (lambda_max(C~) = c / m = 4000 1/s bounds s), a run at
// it must stay bounded and one 1 % past the closed form must not. With 5 %
// damping the damped leapfrog limit still sets it (the dashpots are not
// named).
std::string overdamped_member_case(double damping_ratio) {
  std::ostringstream s;
  s << "framequake_case: 1\n"
       "time: {dt_s: 1.0e-4, duration_s: 0.5, integrator: rk4, gravity_mps2: [9.80665, 0, 0]}\n"
       "materials: [{name: w, density_kg_per_m3: 1000}]\n"
       "sections: [{name: s, width_m: 0.01, depth_m: 0.01}]\n"
       "nodes: [{id: a, xyz_m: [0, 0, 0.5]}, {id: b, xyz_m: [0.1, 0, 0.5]}]\n"
       "members: [{id: m, kind: other, nodes: [a, b], section: s, material: w}]\n"
       "joint_types:\n"
       "  - {name: lin, layout: single_point,\n"
       "     normal: {law: linear, stiffness_N_per_m: 100.0, damping_ratio: "
    << damping_ratio
    << "},\n"
       "     shear: {law: linear, stiffness_N_per_m: 100.0}}\n"
       "joints: {support_type: lin}\n"
       "supports: [{node: a}]\n";
  return s.str();
}

bool rk4_run_stays_bounded(const CaseDef& def, double dt_s) {
  CaseDef d = def;
  d.time.dt_s = dt_s;
  d.time.duration_s = 2000 * dt_s;
  Scene scene = build_scene(d);
  Simulation& sim = *scene.simulation;
  const BodyId member = BodyId(sim.bodies().size() - 1);
  const Vec3 x0 = sim.bodies().position_m[member];
  for (int n = 0; n < 2000; ++n) {
    if (!sim.step()) return false;
    // The static stretch under gravity is m g / k = 1 mm; a divergence leaves it far behind.
    if (!((sim.bodies().position_m[member] - x0).norm() < 0.01)) return false;
  }
  return true;
}

TEST(SceneStableStep, Rk4OnAnOverdampedSpringIsLimitedByItsFastestDecay) {
  TempDir dir;
  const CaseDef def = load_case_file(dir.write("overdamped.yaml", overdamped_member_case(20.0)));
  const Scene probe = build_scene(def);
  const double omega = 100.0, zeta = 20.0;
  const double closed_form = 2.785293563405282 / (omega * (zeta + std::sqrt(zeta * zeta - 1.0)));
  const double estimate = probe.stable_time_step.dt_crit_s;
  std::cout << "rk4, zeta 20: estimate " << estimate << " s, closed form " << closed_form << " s ("
            << probe.stable_time_step.stiffest_element << ")\n";
  EXPECT_LE(estimate, closed_form);
  EXPECT_GT(estimate, 0.999 * closed_form);
  EXPECT_NE(probe.stable_time_step.stiffest_element.find("the dashpots"), std::string::npos);
  EXPECT_TRUE(rk4_run_stays_bounded(def, estimate));
  EXPECT_FALSE(rk4_run_stays_bounded(def, 1.01 * closed_form));
  const Scene light = build_scene(load_case_file(dir.write("light.yaml", overdamped_member_case(0.05))));
  EXPECT_EQ(light.stable_time_step.stiffest_element.find("the dashpots"), std::string::npos)
      << light.stable_time_step.stiffest_element;
}

}  // namespace
// Frame A forced to 20 times its time step (2e-4 s, about 8.6 times its
// stable estimate) blows up: its members reach rms speeds of 1 600 m/s
// within 12 ms and travel kilometres. The energy guard measured the runaway
// against a scale holding the gravity work, which the runaway raises
// itself, and the run "completed" (stress probe); it now stops as unstable
// once the free mass's rms speed passes 100 m/s (1000 m/s until 2026-11-27;
// dem_core/src/simulation.cpp).
TEST(SceneStableStep, AFrameForcedFarPastItsStableStepStopsAsUnstable) {
  test::TempDir dir;
  CaseDef def = load_case_file(std::filesystem::path(FQ_SOURCE_DIR) / "cases" / "frame_A.yaml");
  def.time.dt_s = 2.0e-4;
  def.time.duration_s = 0.2;
  CaseRunOptions options;
  options.allow_unstable_time_step = true;
  options.output_folder = dir.path() / "out";
  const CaseRunReport report = run_case(def, options);
  EXPECT_EQ(report.result.status, RunStatus::Unstable) << report.result.message;
  EXPECT_NE(report.result.message.find("rms speed of 100 m/s"), std::string::npos) << report.result.message;
}

}  // namespace fq
