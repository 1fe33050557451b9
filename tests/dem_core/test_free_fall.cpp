// Constant-acceleration motion: free fall, a projectile, a constant ground
// acceleration, a fixed body, and the energy ledger of these runs.
//
// Why these are exact: central difference started with
// v(-1/2) = v0 - (dt/2) a gives v(n+1/2) = v0 + (n + 1/2) dt a and
// x(n) = x0 + dt sum_{k<n} v(k+1/2) = x0 + v0 t_n + a t_n^2 / 2 (the sum of
// (k + 1/2) over k < n is n^2 / 2), i.e. the closed form with no truncation
// error. What remains is round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dem_core/simulation.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace {

using fq::BodyStore;
using fq::BoxBodyDef;
using fq::EnergyLedger;
using fq::Simulation;
using fq::SimulationSettings;
using fq::Vec3;

constexpr double kDensity = 450.0;            // softwood (kg/m^3)
const Vec3 kSize(0.1, 0.2, 0.35);             // edges (m)
const double kMass = kDensity * 0.1 * 0.2 * 0.35;  // (kg)

// Round-off bound for positions: each step adds dt v to x with one rounding
// of relative size eps = 1.1e-16 of |x|; after N = 1000 steps the worst case
// is N eps ~ 1.1e-13 of the displacement scale. 1e-12 leaves a factor 10.
constexpr double kPositionRoundOff = 1e-12;
// The ledger sums N work increments, each a few flops: N * 10 flops * eps
// ~ 1.1e-12 of the energy scale; 1e-11 leaves a factor 10.
constexpr double kLedgerRoundOff = 1e-11;

BoxBodyDef box(const Vec3& x0, const Vec3& v0) {
  BoxBodyDef def;
  def.size_m = kSize;
  def.density_kg_per_m3 = kDensity;
  def.position_m = x0;
  def.velocity_mps = v0;
  return def;
}

fq::GroundMotion constant_ground_motion(const Vec3& direction, double a_mps2) {
  // Two equal samples 100 s apart: a_g(t) = a for the whole run (runs last 1 s).
  fq::GroundMotionComponent c;
  c.record.source = "constant";
  c.record.dt_s = 100.0;
  c.record.acceleration_mps2 = {a_mps2, a_mps2};
  c.direction = direction;
  fq::GroundMotion gm;
  gm.add_component(c);
  return gm;
}

// Records the ledger and the step count each time it is called.
struct LedgerRecorder : fq::StepObserver {
  struct Sample {
    std::int64_t steps_done;
    EnergyLedger ledger;
  };
  std::vector<Sample> samples;
  void on_sample(const Simulation& sim) override { samples.push_back({sim.steps_done(), sim.ledger()}); }
};

struct Motion {
  Vec3 x0, v0, a;
  Vec3 x(double t) const { return x0 + v0 * t + 0.5 * a * t * t; }
  Vec3 v(double t) const { return v0 + a * t; }
  double scale(double t) const { return x0.norm() + v0.norm() * t + 0.5 * a.norm() * t * t; }
};

TEST(FreeFall, FreeFallAndProjectileMatchClosedFormToRoundOff) {
  SimulationSettings s;
  s.dt_s = 1e-3;
  s.duration_s = 1.0;
  const Vec3 g = s.gravity_mps2;
  const Motion fall{Vec3(0.0, 0.0, 10.0), Vec3::Zero(), g};
  const Motion projectile{Vec3(1.0, 2.0, 10.0), Vec3(3.0, -1.0, 6.0), g};
  BodyStore store;
  store.add_box(box(fall.x0, fall.v0));
  store.add_box(box(projectile.x0, projectile.v0));
  Simulation sim(std::move(store), s);
  const std::int64_t n_steps = sim.total_steps();
  ASSERT_EQ(n_steps, 1000);
  for (std::int64_t n = 1; n <= n_steps; ++n) {
    ASSERT_TRUE(sim.step());
    const double t = double(n) * s.dt_s;
    int body = 0;
    for (const Motion* m : {&fall, &projectile}) {
      const Vec3 err = sim.bodies().position_m[body] - m->x(t);
      ASSERT_LE(err.cwiseAbs().maxCoeff(), kPositionRoundOff * m->scale(t)) << "body " << body << " step " << n;
      // Stored velocity is v(n - 1/2) at t - dt/2, the exact mean velocity
      // over the last step.
      const Vec3 verr = sim.bodies().velocity_mps[body] - m->v(t - 0.5 * s.dt_s);
      ASSERT_LE(verr.cwiseAbs().maxCoeff(), kPositionRoundOff * (m->v0.norm() + g.norm() * t)) << "step " << n;
      ++body;
    }
  }
  EXPECT_DOUBLE_EQ(sim.time_s(), 1.0);
}

TEST(FreeFall, ConstantGroundAccelerationActsAsMinusAgInRelativeFrame) {
  // Relative frame (DESIGN.md step 1): every free body feels m (g - a_g), so
  // relative to the ground it moves with constant acceleration g - a_g.
  SimulationSettings s;
  s.dt_s = 1e-3;
  s.duration_s = 1.0;
  const Vec3 ag(2.5, 0.0, 0.0);  // (m/s^2), a strong but ordinary earthquake peak
  const Motion m{Vec3(0.0, 0.0, 3.0), Vec3(0.2, 0.1, 0.0), s.gravity_mps2 - ag};
  BodyStore store;
  store.add_box(box(m.x0, m.v0));
  Simulation sim(std::move(store), s, constant_ground_motion(Vec3::UnitX(), ag.x()));
  for (std::int64_t n = 1; n <= sim.total_steps(); ++n) {
    ASSERT_TRUE(sim.step());
    // (1 - f) a + f a rounds to a within one ulp.
    EXPECT_TRUE(sim.ground_acceleration_mps2().isApprox(ag, 1e-15));
    const double t = double(n) * s.dt_s;
    const Vec3 err = sim.bodies().position_m[0] - m.x(t);
    ASSERT_LE(err.cwiseAbs().maxCoeff(), kPositionRoundOff * m.scale(t)) << "step " << n;
  }
  // Sanity of the sign: the body lags behind the accelerating ground.
  EXPECT_LT(sim.bodies().position_m[0].x(), m.x0.x() + m.v0.x() * 1.0);
}

TEST(FreeFall, FixedBodyNeverMoves) {
  // Expected: a fixed body keeps its pose bitwise under gravity, ground
  // motion and an initial velocity in its definition.
  SimulationSettings s;
  s.dt_s = 1e-3;
  s.duration_s = 0.5;
  BoxBodyDef def = box(Vec3(0.3, -0.2, 0.05), Vec3(1.0, 1.0, 1.0));
  def.fixed = true;
  def.angular_velocity_radps = Vec3(3.0, 0.0, 1.0);
  def.orientation = fq::Quat(Eigen::AngleAxisd(0.4, Vec3(1.0, 1.0, 0.0).normalized()));
  BodyStore store;
  store.add_box(def);
  store.add_box(box(Vec3(0.0, 0.0, 1.0), Vec3::Zero()));  // a free neighbour
  const Vec3 x_fixed = store.position_m[0];
  const fq::Quat q_fixed = store.orientation[0];
  Simulation sim(std::move(store), s, constant_ground_motion(Vec3(1.0, 1.0, 0.0), 3.0));
  const fq::RunResult r = sim.run();
  ASSERT_EQ(r.status, fq::RunStatus::Completed);
  EXPECT_TRUE(sim.bodies().position_m[0] == x_fixed);
  EXPECT_TRUE(sim.bodies().orientation[0].coeffs() == q_fixed.coeffs());
  EXPECT_TRUE(sim.bodies().velocity_mps[0].isZero(0.0));
  EXPECT_TRUE(sim.bodies().angular_velocity_radps[0].isZero(0.0));
  // The free neighbour did move (the run was not a no-op).
  EXPECT_LT(sim.bodies().position_m[1].z(), 0.0);
}

// Energy ledger of constant-force motion, checked against closed forms.
//
// Why the bookkeeping of energy_ledger.h is exact here. With v(n+-1/2) =
// v_n +- (dt/2) a (constant a) the ledger's kinetic energy at step n is
//   K_n = (KE(n-1/2) + KE(n+1/2)) / 2 = m |v_n|^2 / 2 + m dt^2 |a|^2 / 8,
// the closed-form kinetic energy plus a constant. The work of a constant
// force F from t = 0 to t_n, trapezoidal on the step means
// v_k = (v(k-1/2) + v(k+1/2)) / 2, is
//   W_n = sum_{k<n} dt F . (v_k + v_{k+1}) / 2 = F . sum_{k<n} dt v(k+1/2) = F . (x_n - x_0)
// because (v_k + v_{k+1}) / 2 = v(k+1/2) when a is constant. So the gravity
// potential is exactly -m g . (x_n - x_0), the ground-motion work exactly
// -m a_g . (x_n - x_0), and K_n - K_0 = m a . (x_n - x_0) (closed form:
// |v_n|^2 - |v_0|^2 = 2 a . (x_n - x_0)) equals the total work: the balance
// error is zero up to round-off.
TEST(FreeFall, LedgerBalancesToRoundOffForGravityAndGroundMotion) {
  SimulationSettings s;
  s.dt_s = 1e-3;
  s.duration_s = 1.0;
  const Vec3 g = s.gravity_mps2;
  const Vec3 ag(1.5, -0.8, 0.0);  // (m/s^2)
  const Vec3 a = g - ag;
  const Motion m1{Vec3(0.0, 0.0, 10.0), Vec3(3.0, -1.0, 6.0), a};
  const Motion m2{Vec3(2.0, 0.0, 1.0), Vec3(-0.5, 0.0, 0.0), a};
  BodyStore store;
  store.add_box(box(m1.x0, m1.v0));
  BoxBodyDef spinning = box(m2.x0, m2.v0);
  // Spin about a principal axis: a steady torque-free motion that the
  // rotation scheme reproduces exactly (only the z sub-rotation is non-zero),
  // so the rotational energy stays constant and cannot hide a translation error.
  spinning.angular_velocity_radps = Vec3(0.0, 0.0, 4.0);
  store.add_box(spinning);
  BoxBodyDef ground = box(Vec3(0.0, 0.0, -0.1), Vec3::Zero());
  ground.fixed = true;  // contributes nothing to any energy
  store.add_box(ground);
  const double i_z = kMass * (0.01 + 0.04) / 12.0;
  const double rotational = 0.5 * i_z * 16.0;

  fq::GroundMotion gm;
  gm.add_component([&] {
    fq::GroundMotionComponent c;
    c.record.dt_s = 100.0;
    c.record.acceleration_mps2 = {ag.norm(), ag.norm()};
    c.direction = ag;
    return c;
  }());
  Simulation sim(std::move(store), s, std::move(gm));
  LedgerRecorder rec;
  sim.add_observer(&rec, 1);
  ASSERT_EQ(sim.run().status, fq::RunStatus::Completed);
  ASSERT_EQ(rec.samples.size(), 1001u);

  double max_err = 0.0;
  for (const LedgerRecorder::Sample& smp : rec.samples) {
    // The ledger seen after step n describes step n (simulation.h): at the
    // first sample (before any step) and after step 0 that is t = 0.
    const std::int64_t n = smp.steps_done == 0 ? 0 : smp.steps_done - 1;
    const double t = double(n) * s.dt_s;
    const EnergyLedger& l = smp.ledger;
    double kinetic = rotational, gravity_potential = 0.0, work_ground = 0.0;
    for (const Motion* m : {&m1, &m2}) {
      const Vec3 dx = m->x(t) - m->x0;
      kinetic += 0.5 * kMass * m->v(t).squaredNorm() + kMass * s.dt_s * s.dt_s * a.squaredNorm() / 8.0;
      gravity_potential += -kMass * g.dot(dx);
      work_ground += -kMass * ag.dot(dx);
    }
    const double scale = l.scale_J;
    ASSERT_GT(scale, 0.0);
    EXPECT_NEAR(l.kinetic_J, kinetic, kLedgerRoundOff * scale) << "step " << n;
    EXPECT_NEAR(l.kinetic_rotational_J, rotational, kLedgerRoundOff * scale) << "step " << n;
    EXPECT_NEAR(l.gravity_potential_J, gravity_potential, kLedgerRoundOff * scale) << "step " << n;
    EXPECT_NEAR(l.work_ground_motion_J, work_ground, kLedgerRoundOff * scale) << "step " << n;
    EXPECT_EQ(l.elastic_J, 0.0);
    EXPECT_EQ(l.dissipated_J(), 0.0);
    // kinetic + gravity potential - initial = work of the ground motion.
    max_err = std::max(max_err, l.balance_error_relative());
  }
  EXPECT_LE(max_err, kLedgerRoundOff);
  std::cout << "[ledger] max relative balance error over 1000 steps: " << max_err << "\n";
  // The run was not trivial: the ground did work and gravity released energy.
  EXPECT_GT(std::abs(rec.samples.back().ledger.work_ground_motion_J), 1.0);
  EXPECT_GT(std::abs(rec.samples.back().ledger.gravity_potential_J), 10.0);
}

// The ledger of a scene large enough for the threaded body update (11 000
// bodies, of which every eleventh is fixed, like the 1e4-body lattice of
// bench_joints): the kinetic energy and the gravity potential are the closed
// forms above, summed over the free bodies, and every ledger field is the
// same bits on one and on two threads. The bodies are summed per chunk and
// the chunk sums added in order (simulation.cpp, parallel_for.h
// EqualChunks); a chunking that depended on the thread count would change
// the order of the sums and, at this size, their last bits.
struct LedgerRun {
  std::vector<EnergyLedger> ledgers;
  std::uint64_t state_hash = 0;
};

LedgerRun run_many_bodies(int threads, std::vector<Motion>& motions, double& rotational, SimulationSettings& s) {
#if defined(_OPENMP)
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  s.dt_s = 1e-3;
  s.duration_s = 0.05;
  BodyStore store;
  motions.clear();
  rotational = 0.0;
  const double i_z = kMass * (0.01 + 0.04) / 12.0;
  for (int i = 0; i < 11000; ++i) {
    // Positions on a 100 x 110 grid 1 m apart; velocities of varied size
    // (the sums then round at every addition).
    const Vec3 x0(double(i % 100), double(i / 100), 5.0);
    const Vec3 v0(0.1 * std::sin(0.7 * i), 0.2 * std::cos(1.3 * i), 1.0 + 0.05 * (i % 17));
    BoxBodyDef def = box(x0, v0);
    if (i % 11 == 0) {
      def.fixed = true;
      store.add_box(def);
      continue;
    }
    const double spin = 1.0 + 0.01 * (i % 23);  // about a principal axis: steady (see above)
    def.angular_velocity_radps = Vec3(0.0, 0.0, spin);
    store.add_box(def);
    motions.push_back({x0, v0, s.gravity_mps2});
    rotational += 0.5 * i_z * spin * spin;
  }
  Simulation sim(std::move(store), s);
  LedgerRecorder rec;
  sim.add_observer(&rec, 1);
  EXPECT_EQ(sim.run().status, fq::RunStatus::Completed);
  LedgerRun out;
  for (const LedgerRecorder::Sample& smp : rec.samples) out.ledgers.push_back(smp.ledger);
  out.state_hash = sim.state_hash();
  return out;
}

TEST(FreeFall, LedgerOfElevenThousandBodiesIsClosedFormAndTheSameOnOneAndTwoThreads) {
#if defined(_OPENMP)
  const int threads_before = omp_get_max_threads();
#endif
  std::vector<Motion> motions;
  double rotational = 0.0;
  SimulationSettings s;
  const LedgerRun one = run_many_bodies(1, motions, rotational, s);
  ASSERT_EQ(motions.size(), 10000u);
  ASSERT_EQ(one.ledgers.size(), 51u);
  for (std::size_t k = 0; k < one.ledgers.size(); ++k) {
    const std::int64_t n = k == 0 ? 0 : std::int64_t(k) - 1;  // as in the test above
    const double t = double(n) * s.dt_s;
    double kinetic = rotational, gravity_potential = 0.0;
    for (const Motion& m : motions) {
      kinetic += 0.5 * kMass * m.v(t).squaredNorm() + kMass * s.dt_s * s.dt_s * m.a.squaredNorm() / 8.0;
      gravity_potential += -kMass * s.gravity_mps2.dot(m.x(t) - m.x0);
    }
    const EnergyLedger& l = one.ledgers[k];
    EXPECT_NEAR(l.kinetic_J, kinetic, kLedgerRoundOff * l.scale_J) << "step " << n;
    EXPECT_NEAR(l.kinetic_rotational_J, rotational, kLedgerRoundOff * l.scale_J) << "step " << n;
    EXPECT_NEAR(l.gravity_potential_J, gravity_potential, kLedgerRoundOff * l.scale_J) << "step " << n;
  }
#if defined(_OPENMP)
  const LedgerRun two = run_many_bodies(2, motions, rotational, s);
  omp_set_num_threads(threads_before);
  ASSERT_EQ(two.ledgers.size(), one.ledgers.size());
  EXPECT_EQ(two.state_hash, one.state_hash);
  for (std::size_t k = 0; k < one.ledgers.size(); ++k) {
    // Bitwise: EXPECT_EQ on doubles compares exactly.
    EXPECT_EQ(two.ledgers[k].kinetic_J, one.ledgers[k].kinetic_J) << "sample " << k;
    EXPECT_EQ(two.ledgers[k].kinetic_rotational_J, one.ledgers[k].kinetic_rotational_J) << "sample " << k;
    EXPECT_EQ(two.ledgers[k].gravity_potential_J, one.ledgers[k].gravity_potential_J) << "sample " << k;
  }
#endif
}

}  // namespace
