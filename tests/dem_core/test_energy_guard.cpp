// The energy blow-up guard of the step loop (simulation.cpp, kBlowUpFactor).
//
// A provider with a negative-stiffness spring injects energy: a body of mass
// m pushed away from an anchor with force +k d has, released from rest at
// d = x0, the closed form d(t) = x0 cosh(w t), v(t) = x0 w sinh(w t),
// w = sqrt(k/m). Without gravity or ground motion, and starting from
// almost no kinetic energy, the guard's ceiling is an rms speed of 100 m/s
// over all free mass M, so it must fire when KE = (1/2) m v^2 first
// exceeds (1/2) M (100 m/s)^2, i.e. at
// t* = asinh(100 sqrt(M / m) / (x0 w)) / w (closed form above). The
// same spring with positive stiffness (a harmonic oscillator, which cannot
// gain energy) must run to the end.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "dem_core/simulation.h"

namespace {

using fq::BodyStore;
using fq::RunResult;
using fq::RunStatus;
using fq::Simulation;
using fq::SimulationSettings;
using fq::Vec3;

// Two equal boxes, the first spinning slowly (so it has some kinetic energy
// but is not the one that runs away).
BodyStore two_boxes() {
  BodyStore store;
  fq::BoxBodyDef def;
  def.size_m = Vec3(0.1, 0.1, 0.1);
  def.density_kg_per_m3 = 450.0;
  def.name = "calm";
  def.position_m = Vec3(0.0, 0.0, 1.0);
  def.angular_velocity_radps = Vec3(0.0, 0.0, 0.5);
  store.add_box(def);
  def.name = "runaway";
  def.angular_velocity_radps = Vec3::Zero();
  def.position_m = Vec3(1.0, 0.0, 1.0);
  store.add_box(def);
  return store;
}

// Spring along x between body `body` and a fixed anchor, force k d with
// d = x - anchor_x: stiffness_Npm < 0 pushes the body away (energy source).
class AxialSpring : public fq::ForceProvider {
 public:
  AxialSpring(fq::BodyId body, double anchor_x_m, double stiffness_Npm)
      : body_(body), anchor_x_m_(anchor_x_m), k_(stiffness_Npm) {}
  const char* name() const override { return "axial_spring"; }
  void accumulate_forces(BodyStore& bodies, const fq::StepInfo&) override {
    const double d = bodies.position_m[std::size_t(body_)].x() - anchor_x_m_;
    bodies.force_N[std::size_t(body_)].x() -= k_ * d;
    elastic_J_ = 0.5 * k_ * d * d;
  }
  void report_energy(fq::EnergyLedger& ledger) const override { ledger.elastic_J += elastic_J_; }

 private:
  fq::BodyId body_;
  double anchor_x_m_;
  double k_;
  double elastic_J_ = 0.0;
};

SimulationSettings no_gravity(double dt_s, double duration_s) {
  SimulationSettings s;
  s.dt_s = dt_s;
  s.duration_s = duration_s;
  s.gravity_mps2 = Vec3::Zero();
  return s;
}

constexpr double kX0_m = 1e-3;         // initial stretch of the spring
constexpr double kOmega_radps = 100.0;  // sqrt(|k| / m)
constexpr double kDt_s = 1e-4;          // w dt = 0.01: leapfrog follows the exponential closely

TEST(EnergyGuard, NegativeStiffnessSpringStopsTheRunAtThePredictedTime) {
  BodyStore store = two_boxes();
  const double m_kg = store.mass_kg[1];
  const double total_kg = store.mass_kg[0] + store.mass_kg[1];
  const double k_Npm = -kOmega_radps * kOmega_radps * m_kg;
  const double anchor_x_m = store.position_m[1].x() - kX0_m;
  Simulation sim(std::move(store), no_gravity(kDt_s, 1.0));
  sim.add_force_provider(std::make_unique<AxialSpring>(1, anchor_x_m, k_Npm));
  const RunResult res = sim.run();

  ASSERT_EQ(res.status, RunStatus::Unstable) << res.message;
  ASSERT_EQ(sim.events().count(fq::EventKind::Instability), 1u);
  const fq::Event& e = sim.events().all().back();
  EXPECT_STREQ(e.mode, "energy_blow_up");
  EXPECT_EQ(e.body_a, 1) << "the body with the largest kinetic energy is named";
  // Closed form (header comment): v(t*) = 100 m/s * sqrt(M / m).
  const double v_star_mps = 100.0 * std::sqrt(total_kg / m_kg);
  const double t_star_s = std::asinh(v_star_mps / (kX0_m * kOmega_radps)) / kOmega_radps;
  // The guard checks every step, so it fires within a step of t*; the
  // ledger's KE at t_n is the mean of the half-step values, whose spread is
  // a factor exp(w dt) = 1.01, far less than a step's growth of 2 w dt.
  EXPECT_NEAR(e.time_s, t_star_s, 1.5 * kDt_s);
  // The guard looks after each completed step (in run()): the step that
  // crossed the bound is counted, and its state is not sampled.
  EXPECT_EQ(res.steps, e.step + 1);
  // The guard stops the run long before anything overflows.
  EXPECT_TRUE(sim.bodies().velocity_mps[1].allFinite());
  EXPECT_NE(res.message.find("runaway"), std::string::npos) << res.message;
  EXPECT_NE(res.message.find("step " + std::to_string(e.step)), std::string::npos) << res.message;
  EXPECT_NE(res.message.find("t = "), std::string::npos) << res.message;
  EXPECT_EQ(res.message.find("calm"), std::string::npos) << res.message;
}

TEST(EnergyGuard, PositiveStiffnessSpringRunsToTheEnd) {
  // The harmonic oscillator conserves energy: the guard must stay silent
  // over many periods (1 s = 16 periods at w = 100 rad/s).
  BodyStore store = two_boxes();
  const double m_kg = store.mass_kg[1];
  const double anchor_x_m = store.position_m[1].x() - kX0_m;
  Simulation sim(std::move(store), no_gravity(kDt_s, 1.0));
  sim.add_force_provider(std::make_unique<AxialSpring>(1, anchor_x_m, kOmega_radps * kOmega_radps * m_kg));
  const RunResult res = sim.run();
  EXPECT_EQ(res.status, RunStatus::Completed) << res.message;
  EXPECT_EQ(sim.events().count(fq::EventKind::Instability), 0u);
}

TEST(EnergyGuard, FreeFallWithGravityDoesNotTrigger) {
  // Free fall turns gravity work into kinetic energy one for one (exact for
  // the scheme, energy_ledger.h): KE never exceeds what gravity put in.
  SimulationSettings s;
  s.dt_s = 1e-3;
  s.duration_s = 5.0;  // 120 m of fall: speeds of 49 m/s
  Simulation sim(two_boxes(), s);
  const RunResult res = sim.run();
  EXPECT_EQ(res.status, RunStatus::Completed) << res.message;
}

}  // namespace
