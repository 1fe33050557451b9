// The work_precision program's own measurement path (validation/
// work_precision_core.h: problem builder, sampling at t_j, error norm, order
// fit) on its mass-spring problem, against the orders the methods' local
// truncation errors predict: central difference and velocity Verlet 2,
// symplectic Euler 1 (positions of leapfrog started from v(-1/2) = v0, an
// O(dt) phase error; dem_core/README.md), RK4 4. A sampling offset of one
// step, or a reference evaluated at the wrong times, would give order 1 for
// every method; a wrong fit would miss these values. Nothing is timed.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "work_precision_core.h"

namespace {

using fq::Integrator;
using namespace fq::wp;

double measured_order(Integrator method, int first_level) {
  const Problem p = mass_spring_problem();
  const std::vector<double> exact = exact_samples(p);
  std::vector<double> dts, errors;
  for (int k = first_level; k < first_level + 3; ++k) {
    const Trial t{method, p.sample_dt_s * std::exp2(-k), 0.0};
    const Outcome o = run_trial(p, t, 1.0);
    EXPECT_EQ(o.status, TrialStatus::Ok) << fq::integrator_name(method) << ": " << o.note;
    dts.push_back(t.dt_s);
    errors.push_back(max_abs_difference(o.samples, exact));
  }
  return fitted_order(dts, errors);
}

TEST(WorkPrecision, FittedOrdersOnMassSpringMatchTheory) {
  // omega dt = 2 pi / 16 / 2^k: k = 3..5 is well inside the asymptotic range
  // (error < 1 % of the amplitude) and far above round-off for all four.
  EXPECT_NEAR(measured_order(Integrator::CentralDifference, 3), 2.0, 0.1);
  EXPECT_NEAR(measured_order(Integrator::VelocityVerlet, 3), 2.0, 0.1);
  EXPECT_NEAR(measured_order(Integrator::SymplecticEuler, 3), 1.0, 0.1);
  EXPECT_NEAR(measured_order(Integrator::RungeKutta4, 1), 4.0, 0.2);
}

TEST(WorkPrecision, OrderFitRecoversAPowerLaw) {
  // error = 3 dt^2.5 exactly: the least-squares slope is 2.5.
  const std::vector<double> dt = {1e-2, 5e-3, 2.5e-3, 1.25e-3};
  std::vector<double> e;
  for (double h : dt) e.push_back(3.0 * std::pow(h, 2.5));
  EXPECT_NEAR(fitted_order(dt, e), 2.5, 1e-12);
  EXPECT_TRUE(std::isnan(fitted_order({1e-2}, {1e-3})));
}

// The frame problems' largest step divides the record's sample interval in
// simulated time, so no sample (a kink of the piecewise-linear forcing)
// falls inside a step (work_precision_core.h; why:
// BaseExcitation.RungeKutta4* in tests/joints/test_base_excitation.cpp).
// Frame B plays the JMA Kobe record, sampled every 0.02 s, at time scale
// 0.3162 (cases/frame_B.yaml), from record second 7.
TEST(WorkPrecision, FrameStepsPutEveryRecordSampleOnAStepBoundary) {
  // (A path, not std::string + "...": GCC 12 at -O2 warned of a false
  // array bound in the inlined string concatenation, an error in CI.)
  const Problem p =
      frame_problem((std::filesystem::path(FQ_SOURCE_DIR) / "cases" / "frame_B.yaml").string(), true, true, 0.05, 7.0, 3.0);
  const double interval_s = 0.02 * 0.3162;
  const double steps_per_sample = interval_s / p.sample_dt_s;
  EXPECT_NEAR(steps_per_sample, std::round(steps_per_sample), 1e-9);
  // The largest such step within 0.8 of the leapfrog limit 2 / omega_max.
  const double dt_max = 0.8 * 2.0 / p.omega_max_radps;
  EXPECT_LE(p.sample_dt_s, dt_max);
  EXPECT_GT(interval_s / (std::round(steps_per_sample) - 1.0), dt_max);
  EXPECT_NE(p.step_rule.find("every record sample on a step boundary"), std::string::npos) << p.step_rule;
}

}  // namespace
