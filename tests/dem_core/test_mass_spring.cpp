// Mass-spring oscillator through the step loop: a body tied to a fixed point
// by a linear spring (stiffness k) and optionally a dashpot (c), written here
// as a tiny ForceProvider.
//
// Closed form of the central-difference oscillator (no gravity, start at
// rest at x_0 = A). The scheme is the recurrence
//   x_{n+1} - 2 x_n + x_{n-1} = -(w dt)^2 x_n,   w = sqrt(k / m),
// and the start v(-1/2) = v0 - (dt/2) a_0 gives x_1 = A (1 - (w dt)^2 / 2).
// With b = 2 - (w dt)^2 and r + 1/r = b the solution is
//   x_n = (A / 2) (r^n + r^-n),
// i.e. x_n = A cos(n theta) with cos(theta) = 1 - (w dt)^2 / 2, equivalently
// sin(theta / 2) = w dt / 2, for w dt < 2 (frequency w~ = theta / dt > w:
// central difference shortens the period), and exponential growth by |r| > 1 per step for
// w dt > 2: dt_crit = 2 / w.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <vector>

#include "dem_core/simulation.h"

namespace {

using fq::BodyStore;
using fq::EnergyLedger;
using fq::Simulation;
using fq::SimulationSettings;
using fq::Vec3;

constexpr double kPi = std::numbers::pi;
// A 0.1 m cube of density 1000 kg/m^3: m = 1 kg.
constexpr double kMass = 1.0;
constexpr double kOmega = 2.0 * kPi;           // 1 Hz (rad/s)
constexpr double kStiffness = kMass * kOmega * kOmega;  // (N/m)
constexpr double kAmplitude = 0.01;            // initial displacement (m)
const Vec3 kAnchor(0.5, -0.2, 1.0);            // fixed point (m)
const Vec3 kDirection = Vec3(1.0, 2.0, -2.0) / 3.0;  // unit, oblique on purpose

// Spring and dashpot between body 0's centre and a fixed point. Forces at
// step n from x_n and v(n-1/2) (force_provider.h contract); energies booked
// from the laws: elastic (1/2) k |d_n|^2, dissipated += c |v(n-1/2)|^2 dt.
class AnchorSpring : public fq::ForceProvider {
 public:
  AnchorSpring(double k_N_per_m, double c_Ns_per_m) : k_(k_N_per_m), c_(c_Ns_per_m) {}
  const char* name() const override { return "anchor_spring"; }
  void accumulate_forces(BodyStore& bodies, const fq::StepInfo& step) override {
    const Vec3 d = bodies.position_m[0] - kAnchor;
    const Vec3 v = bodies.velocity_mps[0];
    bodies.force_N[0] += -k_ * d - c_ * v;
    displacement_m = d;
    elastic_J_ = 0.5 * k_ * d.squaredNorm();
    dissipated_J_ += c_ * v.squaredNorm() * step.dt_s;
  }
  void report_energy(EnergyLedger& ledger) const override {
    ledger.elastic_J += elastic_J_;
    ledger.dissipated_viscous_J += dissipated_J_;
  }
  fq::StiffestMode stiffest_mode(const BodyStore& bodies) const override {
    return {std::sqrt(k_ / bodies.mass_kg[0]), "anchor spring"};
  }
  Vec3 displacement_m = Vec3::Zero();  // d at the last force evaluation (m)

 private:
  double k_, c_;
  double elastic_J_ = 0.0, dissipated_J_ = 0.0;
};

struct Oscillator {
  std::unique_ptr<Simulation> sim;
  AnchorSpring* spring = nullptr;  // owned by sim
  // Signed displacement along kDirection of the current pose (m).
  double x() const { return (sim->bodies().position_m[0] - kAnchor).dot(kDirection); }
};

Oscillator make_oscillator(double dt_s, double duration_s, double c_Ns_per_m = 0.0) {
  fq::BoxBodyDef def;
  def.size_m = Vec3::Constant(0.1);
  def.density_kg_per_m3 = 1000.0;
  def.position_m = kAnchor + kAmplitude * kDirection;
  BodyStore store;
  store.add_box(def);
  SimulationSettings s;
  s.dt_s = dt_s;
  s.duration_s = duration_s;
  s.gravity_mps2 = Vec3::Zero();
  Oscillator o;
  o.sim = std::make_unique<Simulation>(std::move(store), s);
  auto spring = std::make_unique<AnchorSpring>(kStiffness, c_Ns_per_m);
  o.spring = spring.get();
  o.sim->add_force_provider(std::move(spring));
  return o;
}

// Discrete frequency of central difference: sin(w~ dt / 2) = w dt / 2.
double leapfrog_omega(double dt_s) { return 2.0 / dt_s * std::asin(0.5 * kOmega * dt_s); }

TEST(MassSpring, MassIsOneKilogram) { EXPECT_NEAR(fq::box_mass_kg(Vec3::Constant(0.1), 1000.0), kMass, 1e-15); }

TEST(MassSpring, PeriodIsTheCentralDifferencePeriod) {
  const double dt = 0.2 / kOmega;  // w dt = 0.2: the period is 1.7e-3 shorter than 2 pi / w
  const double periods = 100.0;
  Oscillator o = make_oscillator(dt, periods * 2.0 * kPi / kOmega);
  const double theta = leapfrog_omega(dt) * dt;
  // Upward zero crossings of x, located by linear interpolation between steps.
  std::vector<double> crossings;
  double x_prev = o.x();
  for (std::int64_t n = 1; n <= o.sim->total_steps(); ++n) {
    ASSERT_TRUE(o.sim->step());
    const double x = o.x();
    // The discrete solution is exactly A cos(n theta) (header); round-off
    // grows like n eps: 1e-12 of A over 3142 steps is a factor 3 above it.
    ASSERT_NEAR(x, kAmplitude * std::cos(double(n) * theta), 1e-12 * kAmplitude) << "step " << n;
    if (x_prev < 0.0 && x >= 0.0) crossings.push_back(dt * (double(n - 1) + x_prev / (x_prev - x)));
    x_prev = x;
  }
  ASSERT_GE(crossings.size(), 90u);
  const double measured = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  const double expected = 2.0 * kPi / leapfrog_omega(dt);
  const double continuous = 2.0 * kPi / kOmega;
  std::cout << "[period] measured " << measured << " s, central-difference " << expected << " s, continuous "
            << continuous << " s\n";
  // Linear interpolation across a zero of a sinusoid errs by about
  // (w dt)^2 / 24 of a step at most: 1.7e-3 dt over ~99 periods of 31 steps
  // is ~6e-7 of a period; 1e-5 is the tolerance, well below the shift.
  EXPECT_NEAR(measured / expected, 1.0, 1e-5);
  EXPECT_LT(measured / continuous - 1.0, -100.0 * 1e-5) << "the test must resolve the period shift";
}

TEST(MassSpring, LedgerEnergyHasBoundedErrorAndNoDriftOver1000Periods) {
  // Leapfrog conserves H~ = m v(n-1/2) . v(n+1/2) / 2 + k x_n^2 / 2 exactly.
  // The ledger's kinetic (KE(n-1/2) + KE(n+1/2)) / 2 exceeds
  // m v(n-1/2).v(n+1/2)/2 by m |v(n+1/2) - v(n-1/2)|^2 / 4 = (w dt)^2 k x_n^2 / 4,
  // so the ledger's balance error (no dissipation, no input) is exactly
  //   E_n - E_0 = ((w dt)^2 / 2) (k / 2) (x_n^2 - x_0^2),
  // an O((w dt)^2) oscillation between -(w dt)^2/2 E_0 and 0, with no drift.
  const double wdt = 0.1;
  const double dt = wdt / kOmega;
  const double periods = 1000.0;
  Oscillator o = make_oscillator(dt, periods * 2.0 * kPi / kOmega);
  struct Check : fq::StepObserver {
    const Oscillator* o = nullptr;
    double wdt = 0.0, e0 = 0.0, max_identity_error = 0.0, max_rel = 0.0;
    double max_rel_first_10 = 0.0, max_rel_last_10 = 0.0;
    std::int64_t steps_per_10_periods = 0, total = 0;
    void on_sample(const Simulation& sim) override {
      const EnergyLedger& l = sim.ledger();
      if (sim.steps_done() == 0) e0 = l.stored_J();
      const double x_n = o->spring->displacement_m.norm();  // ledger is at step n
      const double x_0 = kAmplitude;
      const double predicted = 0.5 * wdt * wdt * 0.5 * kStiffness * (x_n * x_n - x_0 * x_0);
      max_identity_error = std::max(max_identity_error, std::abs(l.balance_error_J() - predicted));
      const double rel = std::abs(l.balance_error_J()) / e0;
      max_rel = std::max(max_rel, rel);
      if (sim.steps_done() <= steps_per_10_periods) max_rel_first_10 = std::max(max_rel_first_10, rel);
      if (sim.steps_done() >= total - steps_per_10_periods) max_rel_last_10 = std::max(max_rel_last_10, rel);
    }
  } check;
  check.o = &o;
  check.wdt = wdt;
  check.total = o.sim->total_steps();
  check.steps_per_10_periods = check.total / 100;
  o.sim->add_observer(&check, 1);
  ASSERT_EQ(o.sim->run().status, fq::RunStatus::Completed);
  const double e0_expected = 0.5 * kStiffness * kAmplitude * kAmplitude * (1.0 + wdt * wdt / 4.0);
  EXPECT_NEAR(check.e0, e0_expected, 1e-14 * e0_expected);
  std::cout << "[energy] w dt = " << wdt << ": max |E - E0| / E0 over 1000 periods " << check.max_rel
            << " (closed form " << 0.5 * wdt * wdt / (1.0 + wdt * wdt / 4.0) << "), first 10 periods "
            << check.max_rel_first_10 << ", last 10 " << check.max_rel_last_10 << "\n";
  // The identity holds at every one of the 62832 steps to round-off
  // (n eps ~ 7e-12 of E0 at worst).
  EXPECT_LT(check.max_identity_error, 1e-10 * check.e0);
  // Bounded by the closed form (reached at x_n = 0) and attained: in every
  // half period some x_n = A cos(n theta) has |x_n| <= A sin(theta / 2) = A w dt / 2,
  // so the max over any window of periods lies in [bound (1 - (w dt)^2 / 4), bound],
  // in the last 10 periods as in the first 10: no drift.
  const double bound = 0.5 * wdt * wdt / (1.0 + wdt * wdt / 4.0);
  const double attained = bound * (1.0 - wdt * wdt / 4.0) * (1.0 - 1e-9);
  EXPECT_LE(check.max_rel, bound * (1.0 + 1e-9));
  EXPECT_GE(check.max_rel_first_10, attained);
  EXPECT_GE(check.max_rel_last_10, attained);
  EXPECT_LE(check.max_rel_last_10, bound * (1.0 + 1e-9));
}

TEST(MassSpring, DashpotBalanceErrorStaysWithinTheLagBound) {
  // Damping ratio 5 %, typical of a timber frame. Balance error sources
  // (each derived from the recurrence, relative to E_0 = k A^2 / 2):
  //  - spring bookkeeping, as in the undamped test: up to (w dt)^2 / 2;
  //  - the dashpot reads v(n-1/2), half a step behind the mean v_n:
  //    booking c |v(n-1/2)|^2 dt instead of the work c v(n-1/2) . v_n dt
  //    leaves (c dt / 4) |v_n|^2 (relative: zeta w dt, an O(dt) term) plus a
  //    sum (c dt^2 / 4) sum dt |a_k|^2 that accumulates to about
  //    (w dt)^2 / 4 when all the energy is gone;
  //  - a cross term of the spring bookkeeping with damping, zeta (w dt)^2.
  // Tolerance: (3/4)(w dt)^2 + zeta w dt (1 + w dt).
  const double zeta = 0.05;
  const double c = 2.0 * zeta * kMass * kOmega;  // (N s/m)
  const double wdt = 0.1;
  const double dt = wdt / kOmega;
  Oscillator o = make_oscillator(dt, 30.0 * 2.0 * kPi / kOmega, c);  // exp(-2 zeta w t) ~ 7e-9 at the end
  struct Check : fq::StepObserver {
    double max_rel = 0.0, final_dissipated = 0.0, final_stored = 0.0, initial = 0.0;
    void on_sample(const Simulation& sim) override {
      max_rel = std::max(max_rel, sim.ledger().balance_error_relative());
      final_dissipated = sim.ledger().dissipated_viscous_J;
      final_stored = sim.ledger().stored_J();
      initial = sim.ledger().initial_stored_J;
    }
  } check;
  o.sim->add_observer(&check, 1);
  ASSERT_EQ(o.sim->run().status, fq::RunStatus::Completed);
  const double tolerance = 0.75 * wdt * wdt + zeta * wdt * (1.0 + wdt);
  std::cout << "[dashpot] zeta = " << zeta << ", w dt = " << wdt << ": max relative balance error " << check.max_rel
            << " (tolerance " << tolerance << "); dissipated " << check.final_dissipated << " J of "
            << check.initial << " J\n";
  EXPECT_LE(check.max_rel, tolerance);
  // The energy did go into the dashpot (not a vacuous balance).
  EXPECT_LT(check.final_stored, 1e-6 * check.initial);
  EXPECT_NEAR(check.final_dissipated, check.initial, tolerance * check.initial);
}

TEST(MassSpring, PositionErrorConvergesAtSecondOrder) {
  // Exact: x(t) = A cos(w t). At a fixed time t_f the scheme's error is
  // A (cos(w~ t_f) - cos(w t_f)) ~ A sin(w t_f) t_f w^3 dt^2 / 24: order 2.
  const double t_f = 83.0 / 64.0;  // (s) a multiple of every dt below, not at a node
  const double dts[] = {1.0 / 64.0, 1.0 / 128.0, 1.0 / 256.0};
  double err[3];
  for (int k = 0; k < 3; ++k) {
    Oscillator o = make_oscillator(dts[k], t_f);
    for (std::int64_t n = 0; n < o.sim->total_steps(); ++n) ASSERT_TRUE(o.sim->step());
    ASSERT_DOUBLE_EQ(o.sim->time_s(), t_f);
    err[k] = std::abs(o.x() - kAmplitude * std::cos(kOmega * t_f));
  }
  const double p1 = std::log2(err[0] / err[1]), p2 = std::log2(err[1] / err[2]);
  std::cout << "[position] |x - A cos(w t)| at t = " << t_f << " s for dt = 1/64, 1/128, 1/256 s: " << err[0] << " "
            << err[1] << " " << err[2] << " m; order " << p1 << ", " << p2 << "\n";
  ::testing::Test::RecordProperty("position_order", std::to_string(p2));
  EXPECT_GE(p1, 1.8);
  EXPECT_LE(p1, 2.2);
  EXPECT_GE(p2, 1.8);
  EXPECT_LE(p2, 2.2);
}

TEST(MassSpring, CriticalTimeStepIsTwoOverOmega) {
  // Just below dt_crit = 2 / w: x_n = A cos(n theta), bounded by A.
  {
    const double dt = 0.99 * 2.0 / kOmega;
    const double theta = std::acos(1.0 - 0.5 * (kOmega * dt) * (kOmega * dt));
    Oscillator o = make_oscillator(dt, 2000.0 * dt);
    double max_abs = 0.0;
    for (std::int64_t n = 1; n <= 2000; ++n) {
      ASSERT_TRUE(o.sim->step());
      const double x = o.x();
      max_abs = std::max(max_abs, std::abs(x));
      // Round-off grows like n eps / sin(theta) (sin(theta) = 0.28 here):
      // ~3e-12 of A after 2000 steps; 1e-9 of A leaves a wide margin.
      ASSERT_NEAR(x, kAmplitude * std::cos(double(n) * theta), 1e-9 * kAmplitude) << "step " << n;
    }
    EXPECT_LE(max_abs, kAmplitude * (1.0 + 1e-9));
    EXPECT_GE(max_abs, 0.99 * kAmplitude);
  }
  // Just above: b = 2 - (w dt)^2 < -2, r = (b - sqrt(b^2 - 4)) / 2 with |r| > 1,
  // x_n = (A/2)(r^n + r^-n) grows by |r| per step, alternating in sign.
  {
    const double dt = 1.01 * 2.0 / kOmega;
    const double b = 2.0 - (kOmega * dt) * (kOmega * dt);
    const double r = 0.5 * (b - std::sqrt(b * b - 4.0));
    ASSERT_GT(std::abs(r), 1.3);
    Oscillator o = make_oscillator(dt, 60.0 * dt);
    for (std::int64_t n = 1; n <= 60; ++n) {
      ASSERT_TRUE(o.sim->step());
      const double expected = 0.5 * kAmplitude * (std::pow(r, double(n)) + std::pow(r, -double(n)));
      // Relative round-off grows like n eps: 1e-9 is far above it.
      ASSERT_NEAR(o.x(), expected, 1e-9 * std::abs(expected) + 1e-15 * kAmplitude) << "step " << n;
    }
    EXPECT_GT(std::abs(o.x()), 1e6 * kAmplitude);  // exponential growth: |r|^60 / 2 ~ 1e7
  }
}

}  // namespace
