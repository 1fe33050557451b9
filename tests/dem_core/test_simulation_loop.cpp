// The step loop's bookkeeping: when observers run, how a run stops, how a
// non-finite state is caught and reported, the stage profile, and refusal of
// unusable settings. Expected sample steps follow the contract in
// simulation.h: every k steps, once at the start, and the final state once.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem_core/simulation.h"

namespace {

using fq::BodyStore;
using fq::RunResult;
using fq::RunStatus;
using fq::Simulation;
using fq::SimulationSettings;
using fq::Vec3;

BodyStore two_boxes() {
  BodyStore store;
  fq::BoxBodyDef def;
  def.size_m = Vec3(0.01, 0.02, 0.29);  // a column of the seed 001 frames (m)
  def.density_kg_per_m3 = 450.0;
  def.name = "column_1";
  def.position_m = Vec3(0.0, 0.0, 0.145);
  def.angular_velocity_radps = Vec3(0.1, 0.2, 0.3);
  store.add_box(def);
  def.name = "column_2";
  def.position_m = Vec3(0.49, 0.0, 0.145);
  store.add_box(def);
  return store;
}

SimulationSettings settings(double dt_s, double duration_s) {
  SimulationSettings s;
  s.dt_s = dt_s;
  s.duration_s = duration_s;
  s.profile_every_steps = 4;
  return s;
}

// Records which steps it was sampled at, and its start / finish calls.
struct Recorder : fq::StepObserver {
  std::vector<std::int64_t> steps;
  int starts = 0, finishes = 0;
  double max_time_mismatch = 0.0;
  std::atomic<bool>* stop = nullptr;  // set when sampled at stop_at
  std::int64_t stop_at = -1;
  void on_start(const Simulation&) override { ++starts; }
  void on_sample(const Simulation& sim) override {
    steps.push_back(sim.steps_done());
    max_time_mismatch =
        std::max(max_time_mismatch, std::abs(sim.time_s() - double(sim.steps_done()) * sim.settings().dt_s));
    if (stop && sim.steps_done() == stop_at) stop->store(true);
  }
  void on_finish(const Simulation&) override { ++finishes; }
};

std::vector<std::int64_t> expected_steps(std::int64_t every, std::int64_t total) {
  std::vector<std::int64_t> out;
  for (std::int64_t n = 0; n <= total; n += every) out.push_back(n);
  if (out.back() != total) out.push_back(total);
  return out;
}

TEST(SimulationLoop, ObserversRunEveryKStepsOnceAtStartAndFinalStateOnce) {
  // 23 steps: k = 5 is due at 0, 5, ..., 20 and gets the final 23 once;
  // k = 1 sees every step; k = 23 and k = 30 see start and end only.
  Simulation sim(two_boxes(), settings(1e-3, 0.023));
  ASSERT_EQ(sim.total_steps(), 23);
  Recorder r1, r5, r23, r30;
  sim.add_observer(&r1, 1);
  sim.add_observer(&r5, 5);
  sim.add_observer(&r23, 23);
  sim.add_observer(&r30, 30);
  const RunResult res = sim.run();
  EXPECT_EQ(res.status, RunStatus::Completed);
  EXPECT_EQ(res.steps, 23);
  EXPECT_NEAR(res.simulated_s, 0.023, 1e-15);
  EXPECT_TRUE(res.message.empty());
  EXPECT_EQ(r1.steps, expected_steps(1, 23));
  EXPECT_EQ(r5.steps, (std::vector<std::int64_t>{0, 5, 10, 15, 20, 23}));
  EXPECT_EQ(r23.steps, (std::vector<std::int64_t>{0, 23}));
  EXPECT_EQ(r30.steps, (std::vector<std::int64_t>{0, 23}));
  for (const Recorder* r : {&r1, &r5, &r23, &r30}) {
    EXPECT_EQ(r->starts, 1);
    EXPECT_EQ(r->finishes, 1);
    EXPECT_EQ(r->max_time_mismatch, 0.0);  // time reported is t = steps * dt
  }
}

TEST(SimulationLoop, FinalStateIsNotSampledTwiceWhenItIsDue) {
  // 24 steps: k = 4 is due at 24 and must get it once; k = 5 is not and gets
  // the extra final sample once.
  Simulation sim(two_boxes(), settings(1e-3, 0.024));
  ASSERT_EQ(sim.total_steps(), 24);
  Recorder r4, r5;
  sim.add_observer(&r4, 4);
  sim.add_observer(&r5, 5);
  ASSERT_EQ(sim.run().status, RunStatus::Completed);
  EXPECT_EQ(r4.steps, expected_steps(4, 24));
  EXPECT_EQ(r5.steps, expected_steps(5, 24));
  EXPECT_EQ(r5.steps.back(), 24);
}

TEST(SimulationLoop, ZeroDurationSamplesTheInitialStateOnce) {
  Simulation sim(two_boxes(), settings(1e-3, 0.0));
  Recorder r;
  sim.add_observer(&r, 7);
  const RunResult res = sim.run();
  EXPECT_EQ(res.status, RunStatus::Completed);
  EXPECT_EQ(res.steps, 0);
  EXPECT_EQ(r.steps, (std::vector<std::int64_t>{0}));
}

TEST(SimulationLoop, StopFlagStopsTheRunAndTheLastStateIsSampled) {
  Simulation sim(two_boxes(), settings(1e-3, 0.1));
  std::atomic<bool> stop{false};
  Recorder r1, r5;
  r1.stop = &stop;
  r1.stop_at = 7;  // as a signal handler would, between two steps
  sim.add_observer(&r1, 1);
  sim.add_observer(&r5, 5);
  const RunResult res = sim.run(&stop);
  EXPECT_EQ(res.status, RunStatus::Stopped);
  EXPECT_EQ(res.steps, 7);
  EXPECT_EQ(sim.steps_done(), 7);
  EXPECT_NEAR(res.simulated_s, 0.007, 1e-15);
  EXPECT_EQ(r1.steps, expected_steps(1, 7));
  EXPECT_EQ(r5.steps, (std::vector<std::int64_t>{0, 5, 7}));
  EXPECT_EQ(r1.finishes, 1);
  EXPECT_STREQ(fq::run_status_name(res.status), "stopped");
}

TEST(SimulationLoop, StopFlagSetBeforeTheRunStopsAtOnce) {
  Simulation sim(two_boxes(), settings(1e-3, 0.1));
  std::atomic<bool> stop{true};
  Recorder r;
  sim.add_observer(&r, 3);
  const RunResult res = sim.run(&stop);
  EXPECT_EQ(res.status, RunStatus::Stopped);
  EXPECT_EQ(res.steps, 0);
  EXPECT_EQ(r.steps, (std::vector<std::int64_t>{0}));
}

// Adds a non-finite force or torque to one body from a given step on.
class PoisonProvider : public fq::ForceProvider {
 public:
  PoisonProvider(fq::BodyId body, std::int64_t from_step, bool torque)
      : body_(body), from_step_(from_step), torque_(torque) {}
  const char* name() const override { return "poison"; }
  void accumulate_forces(BodyStore& bodies, const fq::StepInfo& step) override {
    ++calls;
    if (step.step < from_step_) return;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (torque_)
      bodies.torque_Nm[std::size_t(body_)].x() += nan;
    else
      bodies.force_N[std::size_t(body_)].y() += nan;
  }
  int calls = 0;

 private:
  fq::BodyId body_;
  std::int64_t from_step_;
  bool torque_;
};

TEST(SimulationLoop, NonFiniteForceMakesTheRunUnstableAndNamesTheBody) {
  for (bool torque : {false, true}) {
    SCOPED_TRACE(torque ? "NaN torque" : "NaN force");
    Simulation sim(two_boxes(), settings(1e-3, 0.1));
    sim.add_force_provider(std::make_unique<PoisonProvider>(1, 5, torque));
    Recorder r;
    sim.add_observer(&r, 1);
    const RunResult res = sim.run();
    EXPECT_EQ(res.status, RunStatus::Unstable);
    EXPECT_STREQ(fq::run_status_name(res.status), "unstable");
    // Step 5 failed and is not counted; the last good state (t = 5 dt) was
    // sampled before it, and nothing after.
    EXPECT_EQ(res.steps, 5);
    EXPECT_EQ(r.steps, expected_steps(1, 5));
    EXPECT_NE(res.message.find("column_2"), std::string::npos) << res.message;
    EXPECT_NE(res.message.find("body 1"), std::string::npos) << res.message;
    EXPECT_NE(res.message.find("step 5"), std::string::npos) << res.message;
    ASSERT_EQ(sim.events().count(fq::EventKind::Instability), 1u);
    const fq::Event& e = sim.events().all().back();
    EXPECT_EQ(e.kind, fq::EventKind::Instability);
    EXPECT_EQ(e.body_a, 1);
    EXPECT_EQ(e.step, 5);
    EXPECT_NEAR(e.time_s, 0.005, 1e-15);
    // The healthy body was not named.
    EXPECT_EQ(res.message.find("column_1"), std::string::npos) << res.message;
  }
}

TEST(SimulationLoop, StepReturnsFalseOnNonFiniteState) {
  Simulation sim(two_boxes(), settings(1e-3, 0.1));
  sim.add_force_provider(std::make_unique<PoisonProvider>(0, 2, false));
  EXPECT_TRUE(sim.step());
  EXPECT_TRUE(sim.step());
  EXPECT_FALSE(sim.step());
  EXPECT_EQ(sim.steps_done(), 2);
  ASSERT_EQ(sim.events().size(), 1u);
  EXPECT_EQ(sim.events().all()[0].body_a, 0);
}

TEST(SimulationLoop, ProvidersAreCalledOncePerStep) {
  // Forces at step n are computed once: at initialisation for n = 0, then at
  // the start of each later step.
  Simulation sim(two_boxes(), settings(1e-3, 0.017));
  auto p = std::make_unique<PoisonProvider>(0, 1000000, false);  // never poisons
  PoisonProvider* raw = p.get();
  sim.add_force_provider(std::move(p));
  Recorder r;
  sim.add_observer(&r, 1);
  ASSERT_EQ(sim.run().status, RunStatus::Completed);
  EXPECT_EQ(raw->calls, 17);
}

TEST(SimulationLoop, ProfileHasNonNegativeStageTimes) {
  Simulation sim(two_boxes(), settings(1e-3, 0.05));
  sim.add_force_provider(std::make_unique<PoisonProvider>(0, 1000000, false));
  Recorder r;
  sim.add_observer(&r, 10);
  const RunResult res = sim.run();
  ASSERT_EQ(res.status, RunStatus::Completed);
  const fq::StageProfile& prof = sim.profile();
  for (int s = 0; s < int(fq::Stage::Count); ++s) {
    EXPECT_GE(prof.seconds[std::size_t(s)], 0.0) << fq::stage_name(fq::Stage(s));
    EXPECT_TRUE(std::isfinite(prof.seconds[std::size_t(s)])) << fq::stage_name(fq::Stage(s));
    EXPECT_STRNE(fq::stage_name(fq::Stage(s)), "unknown");
  }
  ASSERT_EQ(prof.provider_seconds.size(), 1u);
  EXPECT_GE(prof.provider_seconds[0], 0.0);
  // With one provider the per-provider figure is the Providers stage.
  EXPECT_EQ(prof.provider_seconds[0], prof.seconds[std::size_t(fq::Stage::Providers)]);
  EXPECT_GE(res.wall_s, 0.0);
}

TEST(SimulationLoop, ManualStepsThenRunContinueToTheEnd) {
  Simulation sim(two_boxes(), settings(1e-3, 0.01));
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(sim.step());
  Recorder r;
  sim.add_observer(&r, 3);
  const RunResult res = sim.run();
  EXPECT_EQ(res.status, RunStatus::Completed);
  EXPECT_EQ(res.steps, 10);
  // Not at step 0 any more: no initial sample; due at 6 and 9, final 10.
  EXPECT_EQ(r.steps, (std::vector<std::int64_t>{6, 9, 10}));
}

TEST(SimulationLoop, RefusesUnusableSettingsAndLateProviders) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (double dt : {0.0, -1e-5, nan, std::numeric_limits<double>::infinity()})
    EXPECT_THROW(Simulation(two_boxes(), settings(dt, 1.0)), std::invalid_argument) << dt;
  for (double d : {-1.0, nan, std::numeric_limits<double>::infinity()})
    EXPECT_THROW(Simulation(two_boxes(), settings(1e-3, d)), std::invalid_argument) << d;
  // More steps than kMaxSimulationSteps: a unit mistake, and past 2^63 the
  // step count would overflow (a run of "0 steps" reported as completed).
  // 1e12 steps exactly are accepted.
  for (const auto& [dt, d] : {std::pair{1e-300, 0.2}, std::pair{1e-4, 1e16}, std::pair{1e-5, 1.0000001e7}})
    EXPECT_THROW(Simulation(two_boxes(), settings(dt, d)), std::invalid_argument) << dt << " " << d;
  EXPECT_EQ(Simulation(two_boxes(), settings(1e-5, 1e7)).total_steps(), std::int64_t(1e12));
  Simulation sim(two_boxes(), settings(1e-3, 0.01));
  ASSERT_TRUE(sim.step());
  EXPECT_THROW(sim.add_force_provider(std::make_unique<PoisonProvider>(0, 0, false)), std::logic_error);
}

}  // namespace
