// Joint fracture criteria and the dashpot's damping ratio.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "dem_core/simulation.h"
#include "dem_core/state_io.h"
#include "joint_test_util.h"

namespace fq {
namespace {

TEST(JointFracture, StrainLimitBreaksJointAndReleasesPair) {
  // seed 001: broken when the joint springs' strain passes a limit. Linear
  // springs of reference length 0.1 m, limit 1 %: breaks past |delta| = 1 mm.
  BondedPairs bonded;
  BodyStore store = test::two_boxes();
  JointSystem js(&bonded);
  JointDef d;
  d.body_a = 0;
  d.body_b = 1;
  SpringDef k = linear_spring(1e6);
  k.reference_length_m = 0.1;
  d.layout = four_corner_layout(0.04, 0.04, 1.0, k, k);
  d.fracture.criterion = BreakCriterion::StrainLimit;
  d.fracture.strain_limit = 0.01;
  js.add_joint(store, d);
  js.prepare(store);
  const Vec3 rest = store.position_m[1];
  const Quat q = store.orientation[1];
  EventLog log;
  std::int64_t step = 0;
  for (double dx : {0.5e-3, 0.99e-3}) {
    const test::Wrench w = test::drive(js, store, 1, rest, q, Vec3(dx, 0, 0), Vec3::Zero(), Vec3::Zero(), step);
    EXPECT_NEAR(w.force_N.x(), -4e6 * dx, 1e-6);  // four shear springs in parallel
    js.finish_step(store, StepInfo{step++, 0.0, 1e-3}, log);
  }
  EXPECT_EQ(log.size(), 0u);
  EXPECT_TRUE(bonded.bonded(0, 1));
  test::drive(js, store, 1, rest, q, Vec3(1.01e-3, 0, 0), Vec3::Zero(), Vec3::Zero(), step);
  js.finish_step(store, StepInfo{step++, 0.0, 1e-3}, log);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log.all()[0].kind, EventKind::JointBroken);
  EXPECT_STREQ(log.all()[0].mode, "strain_limit");
  EXPECT_NEAR(log.all()[0].force_N, 4e6 * 1.01e-3, 1e-6);  // the resultant carried when it broke
  EXPECT_FALSE(bonded.bonded(0, 1));
  // A broken joint transmits nothing. Its springs' books: what they stored
  // at the break (k u^2 / 2, u = 1.01 mm) as dissipation at once, and at the
  // next evaluation the work of their force of the break over that step
  // (it acted for the whole step), the trapezoid of k u and 0 over the
  // increment 0.5 mm - u: k u^2 / 2 + k u (0.5 mm - u) / 2 = k u 0.5 mm / 2
  // per spring (test_fracture_energy.cpp closes the ledger with it).
  EnergyLedger at_break;
  js.report_energy(at_break);
  EXPECT_EQ(at_break.elastic_J, 0.0);
  EXPECT_NEAR(at_break.dissipated_plastic_J, 4 * 0.5 * 1e6 * 1.01e-3 * 1.01e-3, 1e-12);
  const test::Wrench w = test::drive(js, store, 1, rest, q, Vec3(0.5e-3, 0, 0), Vec3::Zero(), Vec3::Zero(), step);
  EXPECT_EQ(w.force_N.norm(), 0.0);
  EnergyLedger books;
  js.report_energy(books);
  EXPECT_EQ(books.elastic_J, 0.0);
  EXPECT_NEAR(books.dissipated_plastic_J, 4 * 0.5 * 1e6 * 1.01e-3 * 0.5e-3, 1e-12);
  // Booked once: a further step adds nothing.
  test::drive(js, store, 1, rest, q, Vec3(0.2e-3, 0, 0), Vec3::Zero(), Vec3::Zero(), step + 1);
  EnergyLedger later;
  js.report_energy(later);
  EXPECT_EQ(later.dissipated_plastic_J, books.dissipated_plastic_J);
}

// Trilinear law over a 0.1 m reference length: yield at 1 mm (1000 N),
// deleted past the ultimate strains given (1200 N there).
TrilinearParams breaking_law(double ultimate_strain_tension, double ultimate_strain_compression) {
  TrilinearParams t;
  t.yield_strain_tension = t.yield_strain_compression = 0.01;
  t.yield_force_tension_N = t.yield_force_compression_N = 1000.0;
  t.ultimate_strain_tension = ultimate_strain_tension;
  t.ultimate_strain_compression = ultimate_strain_compression;
  t.ultimate_force_tension_N = t.ultimate_force_compression_N = 1200.0;
  return t;
}

TEST(JointFracture, AllNormalSpringsDeletedNeedsEveryNormalSpring) {
  // Four trilinear normal springs; a rotation about t2 stretches the two at
  // +x beyond ultimate: the joint stays intact (two normal springs left)
  // until pure tension deletes the other two.
  BondedPairs bonded;
  BodyStore store = test::two_boxes();
  JointSystem js(&bonded);
  const TrilinearParams t = breaking_law(0.05, 0.1);  // 5 mm in tension, 10 mm in compression
  JointDef d;
  d.body_a = 0;
  d.body_b = 1;
  d.layout = four_corner_layout(0.04, 0.04, 1.0, trilinear_spring(t, 0.1), linear_spring(1e6));
  js.add_joint(store, d);
  js.prepare(store);
  const Vec3 rest = store.position_m[1];
  const Quat q = store.orientation[1];
  EventLog log;
  // Rotation phi2 = -0.15 rad about t2: normal deformation -phi2 x, so the
  // points at x = +0.04 m elongate by ~6 mm (> 5 mm, deleted) and those at
  // x = -0.04 m shorten by ~6 mm (< 10 mm, kept).
  test::drive(js, store, 1, rest, q, Vec3::Zero(), Vec3(0, -0.15, 0), Vec3::Zero(), 0);
  js.finish_step(store, StepInfo{0, 0.0, 1e-3}, log);
  EXPECT_EQ(log.count(EventKind::SpringDeleted), 2u);
  EXPECT_EQ(log.count(EventKind::JointBroken), 0u);
  EXPECT_TRUE(bonded.bonded(0, 1));
  test::drive(js, store, 1, rest, q, Vec3(0, 0, 0.0051), Vec3::Zero(), Vec3::Zero(), 1);
  js.finish_step(store, StepInfo{1, 0.0, 1e-3}, log);
  EXPECT_EQ(log.count(EventKind::SpringDeleted), 4u);
  EXPECT_EQ(log.count(EventKind::JointBroken), 1u);
  EXPECT_FALSE(bonded.bonded(0, 1));
  // Event order within the step: spring events (ascending spring), then the joint.
  EXPECT_EQ(log.all().back().kind, EventKind::JointBroken);
  // Its mode says how it failed: normal springs among the deleted.
  EXPECT_STREQ(log.all().back().mode, "normal_spring_deleted");
}

// A four-corner joint between the two boxes: linear normal springs,
// trilinear shear springs with an ultimate slip of 5 mm (strain 0.05 over
// 0.1 m), broken by any deleted spring.
void add_shear_breaking_joint(JointSystem& js, BodyStore& store) {
  const TrilinearParams t = breaking_law(0.05, 0.05);
  JointDef d;
  d.body_a = 0;
  d.body_b = 1;
  d.layout = four_corner_layout(0.04, 0.04, 1.0, linear_spring(1e6), trilinear_spring(t, 0.1));
  d.fracture.criterion = BreakCriterion::AnySpringDeleted;
  js.add_joint(store, d);
  js.prepare(store);
}

TEST(JointFracture, AJointThatSlidOutBreaksWithTheShearMode) {
  // Linear normal springs, trilinear shear springs (ultimate 5 mm): a slip
  // of 6 mm along x deletes the shear springs along x, and any_spring_deleted
  // breaks the joint with mode shear_spring_deleted (no normal spring went).
  BondedPairs bonded;
  BodyStore store = test::two_boxes();
  JointSystem js(&bonded);
  add_shear_breaking_joint(js, store);
  EventLog log;
  test::drive(js, store, 1, store.position_m[1], store.orientation[1], Vec3(0.006, 0, 0), Vec3::Zero(),
              Vec3::Zero(), 0);
  js.finish_step(store, StepInfo{0, 0.0, 1e-3}, log);
  ASSERT_EQ(log.count(EventKind::JointBroken), 1u);
  for (const Event& e : log.all()) {
    if (e.kind == EventKind::SpringDeleted) {
      EXPECT_STREQ(e.mode, "shear");
    }
  }
  EXPECT_STREQ(log.all().back().mode, "shear_spring_deleted");
}

TEST(JointFracture, SpringsOfABrokenJointAreNotReportedAsDeleted) {
  // As above, a slip of 6 mm along x (past the shear springs' 5 mm) and 2 mm
  // along y (inside it): the four shear springs along x are deleted and
  // break the joint (any_spring_deleted). The joint's other eight springs
  // (four linear normal springs, four shear springs along y) were not
  // deleted: they report JointBroken, not Deleted (retrofit probe: the
  // frames showed all 12 springs "deleted" where events.csv had 2), with
  // the strain ratio of their last evaluation: 2 mm / 5 mm for the shear
  // springs along y, 0 for the linear normal springs. A checkpoint keeps it.
  BondedPairs bonded;
  BodyStore store = test::two_boxes();
  JointSystem js(&bonded);
  add_shear_breaking_joint(js, store);
  EventLog log;
  test::drive(js, store, 1, store.position_m[1], store.orientation[1], Vec3(0.006, 0.002, 0), Vec3::Zero(),
              Vec3::Zero(), 0);
  js.finish_step(store, StepInfo{0, 0.0, 1e-3}, log);
  ASSERT_EQ(log.count(EventKind::JointBroken), 1u);
  ASSERT_EQ(log.count(EventKind::SpringDeleted), 4u);
  ASSERT_EQ(js.spring_count(), 12u);
  auto check = [&](const JointSystem& j, const char* when) {
    for (std::size_t s = 0; s < 12; ++s) {
      // Each point: normal, shear along t1 (x), shear along t2 (y).
      const std::size_t within = s % 3;
      if (within == 1) {
        EXPECT_EQ(j.spring_status(s), SpringStatus::Deleted) << when << " spring " << s;
      } else {
        EXPECT_EQ(j.spring_status(s), SpringStatus::JointBroken) << when << " spring " << s;
        EXPECT_NEAR(j.spring_strain_ratio(s), within == 2 ? 0.4 : 0.0, 1e-9) << when << " spring " << s;
      }
    }
  };
  check(js, "after the break");
  for (const Event& e : log.all()) {
    if (e.kind == EventKind::SpringDeleted) {
      EXPECT_EQ(e.spring_index % 3, 1) << "deleted: shear along x";
    }
  }
  StateWriter out;
  js.save_state(out);
  BondedPairs bonded2;
  BodyStore store2 = test::two_boxes();
  JointSystem js2(&bonded2);
  add_shear_breaking_joint(js2, store2);
  StateReader in(out.bytes());
  js2.load_state(in);
  check(js2, "after a checkpoint");
}

TEST(JointDashpot, DampingRatioGivesLogarithmicDecrement) {
  // One normal spring (no lever arm: pure translation, m_eff = m of the free
  // body) with zeta = 0.05: free decay has logarithmic decrement
  // 2 pi zeta / sqrt(1 - zeta^2) per period. The explicit dashpot uses
  // v(n-1/2); the resulting damping differs from zeta by O(w dt) = 2 %
  // at w dt = 0.02, hence the 5 % tolerance.
  BodyStore bodies = test::two_boxes();
  const double k = 1e6, zeta = 0.05, m = bodies.mass_kg[1];
  const double w = std::sqrt(k / m);
  SimulationSettings settings;
  settings.gravity_mps2 = Vec3::Zero();
  settings.dt_s = 0.02 / w;
  const double period = 2 * M_PI / (w * std::sqrt(1 - zeta * zeta));
  settings.duration_s = 3.2 * period;
  bodies.velocity_mps[1] = Vec3(0, 0, 0.01);
  Simulation sim(std::move(bodies), settings);
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs());
  JointDef d;
  d.body_a = 0;
  d.body_b = 1;
  SpringPointDef p;
  p.has_shear = false;
  p.normal = linear_spring(k, zeta);
  d.layout.points.push_back(p);
  const double z0 = sim.bodies().position_m[1].z();
  js->add_joint(sim.bodies(), d);
  sim.add_force_provider(std::move(js));
  sim.initialize();
  // Successive maxima of z - z0.
  std::vector<double> peaks;
  double prev2 = 0.0, prev1 = 0.0;
  while (sim.steps_done() < sim.total_steps()) {
    sim.step();
    const double z = sim.bodies().position_m[1].z() - z0;
    if (sim.steps_done() > 2 && prev1 > prev2 && prev1 >= z && prev1 > 0.0) peaks.push_back(prev1);
    prev2 = prev1;
    prev1 = z;
  }
  ASSERT_GE(peaks.size(), 3u);
  const double decrement = std::log(peaks[0] / peaks[2]) / 2.0;
  const double expected = 2 * M_PI * zeta / std::sqrt(1 - zeta * zeta);
  EXPECT_NEAR(decrement, expected, 0.05 * expected);
  std::printf("dashpot: log decrement %.5f, expected %.5f\n", decrement, expected);
}

// Body 0 to body 1 by two normal springs of stiffness k (N/m), each with a
// dashpot c (N s/m), at x = +-0.03 m from the centres: their torques
// cancel, so the free box only translates along the joint normal.
JointDef two_damped_normal_springs(double k, double c) {
  JointDef d;
  d.body_a = 0;
  d.body_b = 1;
  SpringPointDef p;
  p.has_shear = false;
  p.normal = linear_spring(k);
  p.normal.dashpot.coefficient_Nspm = c;
  p.normal.dashpot.damping_ratio = 0.0;
  for (double x : {0.03, -0.03}) {
    p.offset_m = Vec3(x, 0.0, 0.0);
    d.layout.points.push_back(p);
  }
  return d;
}

TEST(JointDashpot, ViscousBooksOfTwoStepsAreTheLeapfrogDashpotWork) {
  // Two normal springs, each with a dashpot of c = 40 N s/m, at opposite
  // offsets from the centres (their torques cancel exactly, so the box
  // does not turn), the free box translating along the joint normal (no
  // gravity). Each point's rate is then v_z of the box, its dashpot force
  // at step n is c v(n-1/2), and the ledger's dissipation of step n
  // (joint_system.h, Energy) is t_n = dt/2 (2 c v(n-1/2)^2 + 2 c v(n-1/2)
  // v(n+1/2)); after two steps the books report t_0/2 + t_1/2. Step 0's
  // forces are those Simulation::initialize evaluates at the initial
  // velocity v0, before it shifts v back half a step, so in t_0 v0 stands
  // for v(-1/2). The velocities are read from the bodies, so the expected
  // value uses nothing of the joint code. Before the first step: nothing
  // dissipated.
  BodyStore bodies = test::two_boxes();
  const double k = 1e5, c = 40.0;
  SimulationSettings settings;
  settings.gravity_mps2 = Vec3::Zero();
  settings.dt_s = 1e-4;
  settings.duration_s = 1.0;
  bodies.velocity_mps[1] = Vec3(0, 0, 0.02);
  Simulation sim(std::move(bodies), settings);
  auto owned = std::make_unique<JointSystem>(&sim.bonded_pairs());
  JointSystem* js = owned.get();
  js->add_joint(sim.bodies(), two_damped_normal_springs(k, c));
  sim.add_force_provider(std::move(owned));
  EXPECT_EQ(js->joint_viscous_J(0), 0.0);
  double v[3];
  v[0] = sim.bodies().velocity_mps[1].z();  // v0, at which step 0's forces are evaluated
  sim.initialize();
  for (int n = 0; n < 2; ++n) {
    sim.step();
    v[n + 1] = sim.bodies().velocity_mps[1].z();  // v(n+1/2)
    EXPECT_EQ(sim.bodies().angular_velocity_radps[1].norm(), 0.0);
  }
  const double dt = settings.dt_s;
  const double t0 = 0.5 * dt * 2.0 * (c * v[0] * v[0] + c * v[0] * v[1]);
  const double t1 = 0.5 * dt * 2.0 * (c * v[1] * v[1] + c * v[1] * v[2]);
  const double expected = 0.5 * t0 + 0.5 * t1;
  EXPECT_GT(expected, 0.0);
  EXPECT_NEAR(js->joint_viscous_J(0), expected, 1e-12 * expected);
  EnergyLedger books;
  js->report_energy(books);
  EXPECT_NEAR(books.dissipated_viscous_J, expected, 1e-12 * expected);
}

TEST(JointDashpot, ViscousBooksUnderRungeKuttaCountEachStepOnce) {
  // Classical RK4 evaluates the joints at three trial states within a step
  // and once more at its end; the books keep the leapfrog's rule (one term
  // per step, joint_system.h "Energy"), approximate to first order in dt
  // here (simulation.cpp). The reference is the mechanical energy the
  // oscillator lost, from its state alone: E0 - (m v^2 / 2 + K z^2 / 2),
  // which RK4 gives to fourth order. The box of the test above on its two
  // springs (K = 2e5 N/m, C = 80 N s/m: zeta = 0.126) from 0.02 m/s, over
  // two periods, at omega dt = 1/40 and 1/80: the books' error against the
  // loss is first order (halves with dt) and a few per cent; a term booked
  // at every trial evaluation would count each step up to four times.
  const double k = 1e5, c = 40.0, v0 = 0.02;
  auto relative_error = [&](double omega_dt) {
    BodyStore bodies = test::two_boxes();
    const double m = bodies.mass_kg[1];
    const double omega = std::sqrt(2.0 * k / m);
    SimulationSettings settings;
    settings.gravity_mps2 = Vec3::Zero();
    settings.integrator = Integrator::RungeKutta4;
    settings.dt_s = omega_dt / omega;
    settings.duration_s = 2.0 * (2.0 * M_PI / omega);
    bodies.velocity_mps[1] = Vec3(0, 0, v0);
    const double z_rest = bodies.position_m[1].z();
    Simulation sim(std::move(bodies), settings);
    auto owned = std::make_unique<JointSystem>(&sim.bonded_pairs());
    JointSystem* js = owned.get();
    js->add_joint(sim.bodies(), two_damped_normal_springs(k, c));
    sim.add_force_provider(std::move(owned));
    EXPECT_EQ(sim.run().status, RunStatus::Completed);
    const double v = sim.bodies().velocity_mps[1].z(), z = sim.bodies().position_m[1].z() - z_rest;
    const double lost = 0.5 * m * v0 * v0 - (0.5 * m * v * v + 0.5 * 2.0 * k * z * z);
    EXPECT_GT(lost, 0.5 * 0.5 * m * v0 * v0);  // two periods at zeta = 0.126 take most of it
    return (js->joint_viscous_J(0) - lost) / lost;
  };
  const double coarse = relative_error(1.0 / 40.0), fine = relative_error(1.0 / 80.0);
  std::printf("RK4 viscous books against the energy lost: %.3e at omega dt = 1/40, %.3e at 1/80\n", coarse, fine);
  EXPECT_LT(std::abs(coarse), 0.05);
  EXPECT_NEAR(coarse / fine, 2.0, 0.3);
}

// Why a joint system cannot serve rk4 or gsl_rk8pd (their trial states
// would yield or break springs): counted in words a user reads in the
// refusal, one or many (an integrator probe read "1 springs").
TEST(JointTrialStates, TheObstacleCountsSpringsAndJointsInTheirNumber) {
  BodyStore bodies = test::two_boxes();
  BondedPairs bonded;
  JointSystem js(&bonded);
  TrilinearParams p;
  p.yield_strain_tension = p.yield_strain_compression = 0.01;
  p.yield_force_tension_N = p.yield_force_compression_N = 10.0;
  p.ultimate_strain_tension = p.ultimate_strain_compression = 0.05;
  p.ultimate_force_tension_N = p.ultimate_force_compression_N = 15.0;
  JointDef d;
  d.body_a = 0;
  d.body_b = 1;
  SpringPointDef point;
  point.has_shear = false;
  point.normal = trilinear_spring(p, 0.01);
  d.layout.points.push_back(point);
  d.fracture.criterion = BreakCriterion::StrainLimit;
  d.fracture.strain_limit = 0.05;
  js.add_joint(bodies, d);
  EXPECT_FALSE(js.supports_trial_states());
  EXPECT_EQ(js.trial_state_obstacle(), "1 spring of law trilinear, 1 joint with fracture: strain_limit");
  js.add_joint(bodies, d);
  EXPECT_EQ(js.trial_state_obstacle(), "2 springs of law trilinear, 2 joints with fracture: strain_limit");
}

}  // namespace
}  // namespace fq
