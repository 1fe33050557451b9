// The integrators of integrator.h on problems with closed forms.
//
// (a) Convergence order on an undamped mass-spring oscillator (x = A cos wt
//     exactly): the position error at t = 1 period, at dt, dt/2, dt/4.
//     Expected orders from the methods' local truncation errors: central
//     difference 2, velocity Verlet 2, symplectic Euler 1 (its positions
//     are those of leapfrog started with v(-1/2) = v0 instead of
//     v0 - dt a0/2: an O(dt) phase error), forward Euler 1, RK4 4; the GSL
//     rk8pd reference within 1e-10 of A.
// (b) Stability on the same oscillator, by bisection of w dt: central
//     difference, velocity Verlet, symplectic Euler 2, RK4 2 sqrt(2) (the
//     imaginary-axis extent of its stability region), so RK4/CD = sqrt(2);
//     forward Euler multiplies the energy by exactly 1 + (w dt)^2 per step
//     (|1 + i w dt|^2), unstable for every dt.
// (c) Torque-free asymmetric top: world angular momentum exactly conserved
//     (dL/dt = T = 0 for every method), kinetic energy error within the
//     bound of each method's order, unit quaternion.
// (d) Multi-stage methods refuse providers that keep history.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "dem_core/simulation.h"

namespace {

using fq::BodyStore;
using fq::Integrator;
using fq::Simulation;
using fq::SimulationSettings;
using fq::Vec3;

constexpr double kPi = std::numbers::pi;
constexpr double kMass = 1.0;            // 0.1 m cube of 1000 kg/m^3 (kg)
constexpr double kOmega = 2.0 * kPi;     // (rad/s)
constexpr double kAmplitude = 0.01;      // (m)
const Vec3 kAnchor(0.3, -0.1, 0.7);
const Vec3 kDirection = Vec3(2.0, -1.0, 2.0) / 3.0;

// Linear spring from body 0's centre to a fixed point: no history, so
// multi-stage methods may evaluate it at trial states.
class AnchorSpring : public fq::ForceProvider {
 public:
  explicit AnchorSpring(double k_N_per_m, bool trial_ok = true) : k_(k_N_per_m), trial_ok_(trial_ok) {}
  const char* name() const override { return "anchor_spring"; }
  void accumulate_forces(BodyStore& b, const fq::StepInfo&) override {
    const Vec3 d = b.position_m[0] - kAnchor;
    b.force_N[0] += -k_ * d;
    elastic_J_ = 0.5 * k_ * d.squaredNorm();
  }
  void report_energy(fq::EnergyLedger& l) const override { l.elastic_J += elastic_J_; }
  bool supports_trial_states() const override { return trial_ok_; }

 private:
  double k_;
  bool trial_ok_;
  double elastic_J_ = 0.0;
};

std::unique_ptr<Simulation> oscillator(Integrator method, double dt_s, double duration_s, bool trial_ok = true) {
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
  s.integrator = method;
  auto sim = std::make_unique<Simulation>(std::move(store), s);
  sim->add_force_provider(std::make_unique<AnchorSpring>(kMass * kOmega * kOmega, trial_ok));
  return sim;
}

double displacement(const Simulation& sim) { return (sim.bodies().position_m[0] - kAnchor).dot(kDirection); }

// max_n |x_n - A cos(w t_n)| over one period T with `steps` steps (the
// maximum over the run sees phase errors, which the error at t = T, a
// crest of the cosine, shows only squared).
double period_error(Integrator method, int steps) {
  const double period = 2.0 * kPi / kOmega;
  const double dt = period / steps;
  auto sim = oscillator(method, dt, period);
  double worst = 0.0;
  for (int n = 1; n <= steps; ++n) {
    EXPECT_TRUE(sim->step());
    worst = std::max(worst, std::abs(displacement(*sim) - kAmplitude * std::cos(kOmega * dt * n)));
  }
  return worst;
}

struct OrderCase {
  Integrator method;
  double order;
  int steps;  // coarsest
};

TEST(Integrators, ConvergenceOrderOnMassSpring) {
  const OrderCase cases[] = {{Integrator::CentralDifference, 2, 64}, {Integrator::VelocityVerlet, 2, 64},
                             {Integrator::SymplecticEuler, 1, 64},   {Integrator::ForwardEuler, 1, 512},
                             {Integrator::RungeKutta4, 4, 32}};
  for (const OrderCase& c : cases) {
    const double e1 = period_error(c.method, c.steps);
    const double e2 = period_error(c.method, 2 * c.steps);
    const double e4 = period_error(c.method, 4 * c.steps);
    const double p1 = std::log2(e1 / e2), p2 = std::log2(e2 / e4);
    std::cout << "[order] " << fq::integrator_name(c.method) << ": errors " << e1 << ", " << e2 << ", " << e4
              << " m; observed orders " << p1 << ", " << p2 << " (expected " << c.order << ")\n";
    // Asymptotic regime: the observed order approaches the theoretical one
    // as dt halves; 0.1 leaves room for the next term of the error series.
    EXPECT_NEAR(p2, c.order, 0.1) << fq::integrator_name(c.method);
  }
  const double e_gsl = period_error(Integrator::GslRk8pd, 16);
  std::cout << "[order] gsl_rk8pd: error " << e_gsl << " m at 16 output steps per period\n";
  EXPECT_LT(e_gsl, 1e-10 * kAmplitude);
}

// Peak |x| over the second half of `steps` steps at w dt = wdt over the
// peak of the first half: 1 for a neutrally stable method, < 1 when it
// damps, exp(g steps / 2) when it grows by g per step.
double growth(Integrator method, double wdt, int steps) {
  const double dt = wdt / kOmega;
  auto sim = oscillator(method, dt, dt * steps);
  double peak_first = 0.0, peak_second = 0.0;
  for (int n = 0; n < steps; ++n) {
    if (!sim->step()) return HUGE_VAL;
    double& peak = n < steps / 2 ? peak_first : peak_second;
    peak = std::max(peak, std::abs(displacement(*sim)));
  }
  return std::isfinite(peak_second) ? peak_second / peak_first : HUGE_VAL;
}

// Bisection of the largest stable w dt in [lo, hi]: unstable when the
// second half's peak exceeds the first half's by 1.5 over 5000 steps. Near
// the limit the growth per step is proportional to the excess (RK4:
// |R| ~ 1 + 2.5 (w dt - 2 sqrt 2)), so an excess of 1e-4 shows.
double bisect_limit(Integrator method, double lo, double hi) {
  for (int it = 0; it < 18; ++it) {
    const double mid = 0.5 * (lo + hi);
    (growth(method, mid, 5000) < 1.5 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(Integrators, StabilityLimitsOfTheOscillator) {
  const double cd = bisect_limit(Integrator::CentralDifference, 1.0, 3.5);
  const double vv = bisect_limit(Integrator::VelocityVerlet, 1.0, 3.5);
  const double se = bisect_limit(Integrator::SymplecticEuler, 1.0, 3.5);
  const double rk4 = bisect_limit(Integrator::RungeKutta4, 1.0, 3.5);
  std::cout << "[stability] w dt limits: central_difference " << cd << ", velocity_verlet " << vv
            << ", symplectic_euler " << se << ", rk4 " << rk4 << " (ratio rk4/cd " << rk4 / cd << ")\n";
  EXPECT_NEAR(cd, 2.0, 5e-3);
  EXPECT_NEAR(vv, 2.0, 5e-3);
  EXPECT_NEAR(se, 2.0, 5e-3);
  EXPECT_NEAR(rk4, 2.0 * std::sqrt(2.0), 5e-3);
  EXPECT_NEAR(rk4 / cd, std::sqrt(2.0), 5e-3);
  for (Integrator m : {Integrator::CentralDifference, Integrator::VelocityVerlet, Integrator::SymplecticEuler,
                       Integrator::RungeKutta4})
    EXPECT_NEAR(fq::integrator_stability_factor(m), m == Integrator::RungeKutta4 ? rk4 : cd, 5e-3);
}

TEST(Integrators, ForwardEulerGainsEnergyAtEveryStep) {
  // E_{n+1} = (1 + (w dt)^2) E_n exactly for x' = v, v' = -w^2 x.
  for (double wdt : {0.01, 0.1}) {
    const int steps = 1000;
    const double dt = wdt / kOmega;
    auto sim = oscillator(Integrator::ForwardEuler, dt, dt * steps);
    sim->initialize();
    const double e0 = sim->ledger().stored_J();
    for (int n = 0; n < steps; ++n) ASSERT_TRUE(sim->step());
    sim->run();  // gathers provider energy (no steps left)
    const double expected = e0 * std::pow(1.0 + wdt * wdt, steps);
    EXPECT_NEAR(sim->ledger().stored_J() / expected, 1.0, 1e-9) << "w dt " << wdt;
    EXPECT_GT(sim->ledger().stored_J(), e0 * (1.0 + 0.5 * steps * wdt * wdt));
  }
}

TEST(Integrators, TorqueFreeTopConservesAngularMomentum) {
  // 0.1 x 0.2 x 0.35 m box (three different moments), generic spin.
  const Vec3 size(0.1, 0.2, 0.35);
  const fq::Quat q0(Eigen::AngleAxisd(0.9, Vec3(0.3, -0.5, 0.8).normalized()));
  const Vec3 w_body(1.2, -2.0, 3.1);  // (rad/s)
  const double dt = 1e-3, duration = 2.0;
  for (Integrator m : {Integrator::CentralDifference, Integrator::VelocityVerlet, Integrator::SymplecticEuler,
                       Integrator::ForwardEuler, Integrator::RungeKutta4, Integrator::GslRk8pd}) {
    fq::BoxBodyDef def;
    def.size_m = size;
    def.density_kg_per_m3 = 500.0;
    def.orientation = q0;
    def.angular_velocity_radps = q0 * w_body;
    BodyStore store;
    store.add_box(def);
    const Vec3 l0 = store.angular_momentum_Nms[0];
    const double ke0 = 0.5 * l0.dot(store.angular_velocity_radps[0]);
    SimulationSettings s;
    s.dt_s = dt;
    s.duration_s = duration;
    s.gravity_mps2 = Vec3::Zero();
    s.integrator = m;
    Simulation sim(std::move(store), s);
    double ke_err = 0.0;
    for (std::int64_t n = 0; n < sim.total_steps(); ++n) {
      ASSERT_TRUE(sim.step());
      const auto& b = sim.bodies();
      // Instantaneous kinetic energy from L and the pose (not the ledger,
      // whose central-difference definition mixes half steps).
      const Vec3 w = b.angular_velocity_from_momentum(0, b.orientation[0].toRotationMatrix(), b.angular_momentum_Nms[0]);
      ke_err = std::max(ke_err, std::abs(0.5 * b.angular_momentum_Nms[0].dot(w) / ke0 - 1.0));
    }
    const auto& b = sim.bodies();
    const double l_err = (b.angular_momentum_Nms[0] - l0).norm() / l0.norm();
    // |w| dt = 3.9e-3: second-order methods keep KE within (|w| dt)^2 = 1.5e-5
    // (a bounded oscillation for the splitting of rotation.h), RK4 within
    // (|w| dt)^4 t, rk8pd within its tolerance; forward Euler drifts at first
    // order, (|w| dt) per unit of |w| t ~ 3e-2 over 2 s.
    const double wdt = (q0 * w_body).norm() * dt;
    double bound = wdt * wdt;
    if (m == Integrator::RungeKutta4) bound = wdt * wdt * wdt * wdt * duration / dt * 1e-1;
    if (m == Integrator::GslRk8pd) bound = 1e-9;
    if (m == Integrator::ForwardEuler) bound = 10.0 * wdt * duration * (q0 * w_body).norm() ;
    std::cout << "[top] " << fq::integrator_name(m) << ": |dL|/|L| " << l_err << ", max |dKE|/KE " << ke_err
              << " (bound " << bound << "), |q| - 1 " << b.orientation[0].norm() - 1.0 << "\n";
    EXPECT_LT(l_err, 1e-14) << fq::integrator_name(m);
    EXPECT_LT(ke_err, bound) << fq::integrator_name(m);
    EXPECT_NEAR(b.orientation[0].norm(), 1.0, 1e-14) << fq::integrator_name(m);
  }
}

TEST(Integrators, MultiStageMethodsRefuseProvidersWithHistory) {
  for (Integrator m : {Integrator::RungeKutta4, Integrator::GslRk8pd}) {
    auto sim = oscillator(m, 1e-3, 1.0, /*trial_ok=*/false);
    EXPECT_NE(sim->integrator_refusal().find("anchor_spring"), std::string::npos);
    EXPECT_THROW(sim->initialize(), std::invalid_argument);
  }
  auto ok = oscillator(Integrator::VelocityVerlet, 1e-3, 1.0, false);
  EXPECT_EQ(ok->integrator_refusal(), "");
}

TEST(Integrators, NamesRoundTrip) {
  for (Integrator m : {Integrator::CentralDifference, Integrator::VelocityVerlet, Integrator::SymplecticEuler,
                       Integrator::RungeKutta4, Integrator::ForwardEuler, Integrator::GslRk8pd}) {
    Integrator back = Integrator::CentralDifference;
    ASSERT_TRUE(fq::parse_integrator(fq::integrator_name(m), back));
    EXPECT_EQ(back, m);
  }
  Integrator x;
  EXPECT_FALSE(fq::parse_integrator("rk45", x));
}

}  // namespace
