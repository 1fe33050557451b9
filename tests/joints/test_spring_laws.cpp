// Spring laws driven through a real joint: a fixed body and a free body
// joined by one spring point; the free body's position is prescribed each
// step and the force on it read back. Expected values are the laws' closed
// forms (seed 000 Fig. 3 for the trilinear law, Folz & Filiatrault 2001 for
// the CUREE envelope and cyclic rules), never program output.
#include <gtest/gtest.h>

#include <cmath>

#include "joint_test_util.h"

namespace fq {
namespace {

// Trilinear test values (reference length 0.1 m): tension yields at 1 mm /
// 1000 N, ultimate 5 mm / 1500 N; compression yields at 2 mm / 3000 N,
// ultimate 8 mm / 4000 N.
TrilinearParams asymmetric_trilinear() {
  TrilinearParams p;
  p.yield_strain_tension = 0.01;
  p.yield_force_tension_N = 1000.0;
  p.ultimate_strain_tension = 0.05;
  p.ultimate_force_tension_N = 1500.0;
  p.yield_strain_compression = 0.02;
  p.yield_force_compression_N = 3000.0;
  p.ultimate_strain_compression = 0.08;
  p.ultimate_force_compression_N = 4000.0;
  return p;
}
TrilinearParams symmetric_trilinear() {
  TrilinearParams p = asymmetric_trilinear();
  p.yield_strain_compression = p.yield_strain_tension;
  p.yield_force_compression_N = p.yield_force_tension_N;
  p.ultimate_strain_compression = p.ultimate_strain_tension;
  p.ultimate_force_compression_N = p.ultimate_force_tension_N;
  return p;
}
constexpr double kRefLen = 0.1;

// Closed form of seed 000 Fig. 3 on a monotonic path (signed).
double trilinear_backbone(const TrilinearParams& p, double delta) {
  const bool t = delta >= 0.0;
  const double x = std::abs(delta);
  const double ey = (t ? p.yield_strain_tension : p.yield_strain_compression) * kRefLen;
  const double fy = t ? p.yield_force_tension_N : p.yield_force_compression_N;
  const double eu = (t ? p.ultimate_strain_tension : p.ultimate_strain_compression) * kRefLen;
  const double fu = t ? p.ultimate_force_tension_N : p.ultimate_force_compression_N;
  double f = 0.0;
  if (x <= ey)
    f = fy / ey * x;
  else if (x <= eu)
    f = fy + (fu - fy) / (eu - ey) * (x - ey);
  return t ? f : -f;
}

CureeParams timber_curee() { return test::timber_curee(1e6, 1000.0, 150.0, 0.01); }
// Folz & Filiatrault envelope, written out independently of the library.
double curee_env(const CureeParams& c, double x) {
  const double fu = (c.F0_N + c.r1 * c.K0_Npm * c.delta_u_m) * (1.0 - std::exp(-c.K0_Npm * c.delta_u_m / c.F0_N));
  if (x <= c.delta_u_m) return (c.F0_N + c.r1 * c.K0_Npm * x) * (1.0 - std::exp(-c.K0_Npm * x / c.F0_N));
  const double f = fu + c.r2 * c.K0_Npm * (x - c.delta_u_m);
  return f > 0.0 ? f : 0.0;
}

struct Rig {
  BondedPairs bonded;
  BodyStore store = test::two_boxes();
  JointSystem js{&bonded};
  Vec3 rest;
  Quat rest_q;
  Rig(const SpringDef& normal, const SpringDef& shear, BreakCriterion crit = BreakCriterion::AllNormalSpringsDeleted) {
    JointDef d;
    d.body_a = 0;
    d.body_b = 1;
    d.layout = single_point_layout(normal, shear);
    d.fracture.criterion = crit;
    js.add_joint(store, d);
    js.prepare(store);
    rest = store.position_m[1];
    rest_q = store.orientation[1];
  }
  // Spring force (+ tension) of the spring along `axis` for displacement u.
  double force(const Vec3& u, int axis, std::int64_t step = 0) {
    const test::Wrench w = test::drive(js, store, 1, rest, rest_q, u, Vec3::Zero(), Vec3::Zero(), step);
    return -w.force_N[axis];
  }
};

TEST(TrilinearLaw, MonotonicTensionCompressionAndShearTraceFig3) {
  const TrilinearParams p = asymmetric_trilinear();
  const SpringDef tri = trilinear_spring(p, kRefLen);
  for (int axis : {2, 0}) {  // normal, then shear (t1)
    for (double sign : {1.0, -1.0}) {
      Rig rig(tri, tri, BreakCriterion::Never);
      const double end = sign > 0 ? 0.0049 : -0.0079;  // just inside the ultimate strain
      for (int k = 0; k <= 490; ++k) {
        const double d = end * k / 490.0;
        Vec3 u = Vec3::Zero();
        u[axis] = d;
        const double expected = trilinear_backbone(p, d);
        EXPECT_NEAR(rig.force(u, axis, k), expected, 1e-9 * 4000.0) << "axis " << axis << " delta " << d;
      }
    }
  }
}

TEST(TrilinearLaw, DeletedPastUltimateStrainAndCarriesNothingAfter) {
  const TrilinearParams p = asymmetric_trilinear();
  Rig rig(trilinear_spring(p, kRefLen), linear_spring(1e6));
  EventLog log;
  const double du = p.ultimate_strain_tension * kRefLen;  // 5 mm
  const int n = 100;
  std::int64_t step = 0;
  // Up to the ultimate strain (the last sample a hair inside, so that
  // rounding of du does not decide): still carries ~F_U (seed: deleted only
  // when exceeded).
  for (int k = 0; k <= n; ++k, ++step) {
    const double f = rig.force(Vec3(0, 0, k == n ? du * (1.0 - 1e-9) : du * k / n), 2, step);
    rig.js.finish_step(rig.store, StepInfo{step, 0.0, 1e-3}, log);
    if (k == n) {
      EXPECT_NEAR(f, p.ultimate_force_tension_N, 1e-9 * p.ultimate_force_tension_N);
    }
  }
  EXPECT_TRUE(rig.bonded.bonded(0, 1));
  // One step beyond: deleted, zero force.
  EXPECT_EQ(rig.force(Vec3(0, 0, du * 1.001), 2, step), 0.0);
  rig.js.finish_step(rig.store, StepInfo{step, 0.0, 1e-3}, log);
  ++step;
  EXPECT_EQ(rig.js.spring_status(0), SpringStatus::Deleted);
  // Back through zero into compression: nothing, ever (the joint is broken too).
  for (double d : {0.004, 0.0, -0.001, -0.003}) {
    EXPECT_EQ(rig.force(Vec3(0, 0, d), 2, step), 0.0);
    rig.js.finish_step(rig.store, StepInfo{step, 0.0, 1e-3}, log);
    ++step;
  }
  // Events: yield (tension), deletion (tension, force = F_U carried just before), joint broken.
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log.all()[0].kind, EventKind::SpringYielded);
  EXPECT_STREQ(log.all()[0].mode, "tension");
  EXPECT_EQ(log.all()[1].kind, EventKind::SpringDeleted);
  EXPECT_STREQ(log.all()[1].mode, "tension");
  EXPECT_EQ(log.all()[1].spring_index, 0);
  EXPECT_NEAR(log.all()[1].force_N, p.ultimate_force_tension_N, 1e-9 * p.ultimate_force_tension_N);
  EXPECT_EQ(log.all()[2].kind, EventKind::JointBroken);
  EXPECT_EQ(log.all()[2].joint_id, 0);
  EXPECT_FALSE(rig.bonded.bonded(0, 1));
  EXPECT_EQ(rig.js.joint_status(0), JointStatus::Broken);
  EXPECT_EQ(rig.js.counts().broken, 1);
}

TEST(TrilinearLaw, CompressionAndShearDeletionModes) {
  const TrilinearParams p = asymmetric_trilinear();
  {
    Rig rig(trilinear_spring(p, kRefLen), linear_spring(1e6));
    EventLog log;
    rig.force(Vec3(0, 0, -0.0081), 2);
    rig.js.finish_step(rig.store, StepInfo{0, 0.0, 1e-3}, log);
    ASSERT_GE(log.size(), 2u);
    EXPECT_EQ(log.all()[1].kind, EventKind::SpringDeleted);
    EXPECT_STREQ(log.all()[1].mode, "compression");
  }
  {
    Rig rig(linear_spring(1e6), trilinear_spring(p, kRefLen), BreakCriterion::AnySpringDeleted);
    EventLog log;
    rig.force(Vec3(0.0051, 0, 0), 0);
    rig.js.finish_step(rig.store, StepInfo{0, 0.0, 1e-3}, log);
    ASSERT_EQ(log.size(), 3u);  // yield + deletion of shear spring 1 (t1), joint broken
    EXPECT_EQ(log.all()[1].spring_index, 1);
    EXPECT_STREQ(log.all()[1].mode, "shear");
    EXPECT_EQ(log.all()[2].kind, EventKind::JointBroken);
  }
}

TEST(TrilinearLaw, ElasticUnloadingAndKinematicReyield) {
  // Rule documented in trilinear_law.h: elastic unloading at k0 from the
  // plastic state, bounded by the two hardening lines.
  const TrilinearParams p = symmetric_trilinear();
  const TrilinearLaw law = compile_trilinear(p, kRefLen);
  TrilinearState st;
  const double k0 = 1e6, k1 = 1.25e5;  // 1000 N / 1 mm; 500 N / 4 mm
  EXPECT_DOUBLE_EQ(law.k0_t_Npm, k0);
  EXPECT_DOUBLE_EQ(law.k1_t_Npm, k1);
  double f = 0;
  for (int k = 0; k <= 30; ++k) f = evaluate_trilinear(law, st, 1e-4 * k).force_N;
  EXPECT_NEAR(f, 1000.0 + k1 * 2e-3, 1e-9);  // on the hardening line at 3 mm
  // Unload to 1.5 mm: F = 1250 - k0 * 1.5 mm, inside the band.
  for (int k = 29; k >= 15; --k) f = evaluate_trilinear(law, st, 1e-4 * k).force_N;
  EXPECT_NEAR(f, 1250.0 - k0 * 1.5e-3, 1e-9);
  // Reload to 3 mm: back to 1250 N on the same elastic line, then hardening.
  for (int k = 16; k <= 30; ++k) f = evaluate_trilinear(law, st, 1e-4 * k).force_N;
  EXPECT_NEAR(f, 1250.0, 1e-9);
  f = evaluate_trilinear(law, st, 4e-3).force_N;
  EXPECT_NEAR(f, 1000.0 + k1 * 3e-3, 1e-9);
  // Reverse far: the compression hardening line caps the force (Bauschinger):
  // F_lo(-2 mm) = -1000 + k1 (-2 mm + 1 mm).
  for (int k = 39; k >= -20; --k) f = evaluate_trilinear(law, st, 1e-4 * k).force_N;
  EXPECT_NEAR(f, -1000.0 + k1 * (-1e-3), 1e-9);
}

TEST(TrilinearLaw, JointForceIsTheLawsAtEveryStepAcrossYieldUnloadingAndDeletion) {
  // The joint system evaluates a trilinear spring that has never left its
  // initial linear branch by a shortcut (joint_system.cpp,
  // evaluate_spring_). Reference for the force: the law itself
  // (evaluate_trilinear, whose closed forms the tests above check) on its
  // own state, fed the joint's deformation at every step. The path loads
  // past yield (1 mm), unloads back inside the initial elastic range with a
  // plastic offset, reverses past compression yield, and ends past the
  // ultimate deformation (5 mm). While the spring is on its initial branch
  // its books must hold what an elastic spring stores, k0 delta^2 / 2, and
  // no plastic work (CyclicDissipationEqualsLoopArea checks them after).
  const TrilinearParams p = symmetric_trilinear();
  Rig rig(trilinear_spring(p, kRefLen), linear_spring(1e6), BreakCriterion::Never);
  const TrilinearLaw law = compile_trilinear(p, kRefLen);
  TrilinearState reference;
  bool reference_deleted = false;
  std::vector<double> path;
  for (int k = 0; k <= 30; ++k) path.push_back(1e-4 * k);     // 0 -> 3 mm
  for (int k = 29; k >= -30; --k) path.push_back(1e-4 * k);   // -> -3 mm
  for (int k = -29; k <= 60; ++k) path.push_back(1e-4 * k);   // -> 6 mm
  std::int64_t step = 0;
  int deleted_at = -1;
  for (std::size_t i = 0; i < path.size(); ++i) {
    rig.force(Vec3(0, 0, path[i]), 2, step++);
    const double delta = rig.js.spring_deformation_m()[0];
    double expected = 0.0;
    if (!reference_deleted) {
      const LawOutput out = evaluate_trilinear(law, reference, delta);
      reference_deleted = out.failed;
      expected = out.failed ? 0.0 : out.force_N;
      if (out.failed) deleted_at = int(i);
    }
    // Bit for bit: the same expressions on the same inputs.
    ASSERT_EQ(rig.js.spring_force_N()[0], expected) << "step " << i << ", delta " << delta;
    if (i > 0 && i < 10) {  // 0.1-0.9 mm, below yield
      EXPECT_NEAR(rig.js.spring_elastic_J(0), 0.5 * law.k0_t_Npm * delta * delta, 1e-12) << "step " << i;
      EXPECT_EQ(rig.js.spring_plastic_J(0), 0.0) << "step " << i;
    }
  }
  // The path did reach every branch: yield, and deletion past 5 mm.
  EXPECT_NE(reference.plastic_offset_m, 0.0);
  ASSERT_GE(deleted_at, 0);
  EXPECT_GT(path[std::size_t(deleted_at)], 5e-3);
}

TEST(TrilinearLaw, CyclicDissipationEqualsLoopArea) {
  // Symmetric law cycled between +-dm after a first loading to dm. The
  // steady loop is the parallelogram bounded by the hardening lines (slope
  // k1, vertical gap 2 (F_Y - k1 d_Y)) and the elastic lines through
  // (+-dm, +-F_m) (slope k0, intercept gap 2 (k0 dm - F_m)); its area is
  // 4 (F_Y - k1 d_Y)(k0 dm - F_m) / (k0 - k1).
  Rig rig(trilinear_spring(symmetric_trilinear(), kRefLen), linear_spring(1e6), BreakCriterion::Never);
  const double k0 = 1e6, k1 = 1.25e5, fy = 1000.0, dy = 1e-3, dm = 3e-3;
  const double fm = fy + k1 * (dm - dy);
  const double area_closed = 4.0 * (fy - k1 * dy) * (k0 * dm - fm) / (k0 - k1);
  const int n = 3000;  // samples per dm: kinks fall on samples (dm, dy multiples of dm/n)
  std::int64_t step = 0;
  for (int k = 0; k <= n; ++k) rig.force(Vec3(0, 0, dm * k / n), 2, step++);
  const double plastic_start = rig.js.spring_plastic_J(0);
  std::vector<double> xs, fs;
  for (int k = n; k > -n; --k) {
    const double d = dm * k / n;
    xs.push_back(d);
    fs.push_back(rig.force(Vec3(0, 0, d), 2, step++));
  }
  for (int k = -n; k < n; ++k) {
    const double d = dm * k / n;
    xs.push_back(d);
    fs.push_back(rig.force(Vec3(0, 0, d), 2, step++));
  }
  const double f_end = rig.force(Vec3(0, 0, dm), 2, step++);
  EXPECT_NEAR(f_end, fm, 1e-9 * fm);  // the loop closes
  const double area = test::shoelace_area(xs, fs);
  const double dissipated = rig.js.spring_plastic_J(0) - plastic_start;
  EXPECT_NEAR(area, area_closed, 1e-6 * area_closed);
  EXPECT_NEAR(dissipated, area, 1e-9 * area);
}

TEST(CureeLaw, MonotonicEnvelopeAndFailure) {
  const CureeParams c = timber_curee();
  for (int axis : {2, 0}) {
    for (double sign : {1.0, -1.0}) {
      Rig rig(curee_spring(c), curee_spring(c), BreakCriterion::Never);
      // delta_f = delta_u + E(delta_u) / (|r2| K0) ~ 0.025 m; go to 0.024.
      for (int k = 0; k <= 480; ++k) {
        const double d = 0.024 * k / 480.0;
        Vec3 u = Vec3::Zero();
        u[axis] = sign * d;
        EXPECT_NEAR(rig.force(u, axis, k), sign * curee_env(c, d), 1e-9 * 1500.0) << d;
      }
      Vec3 u = Vec3::Zero();
      u[axis] = sign * 0.0251;
      EXPECT_EQ(rig.force(u, axis, 481), 0.0);
      EXPECT_EQ(rig.js.spring_status(axis == 2 ? 0 : 1), SpringStatus::Deleted);
    }
  }
}

TEST(CureeLaw, PinchingDegradationAndLoopArea) {
  const CureeParams c = timber_curee();
  Rig rig(curee_spring(c), linear_spring(1e6), BreakCriterion::Never);
  const double dm = 0.006;
  const int n = 600;
  std::int64_t step = 0;
  for (int k = 0; k <= n; ++k) rig.force(Vec3(0, 0, dm * k / n), 2, step++);
  // First unloading: the unloading line (slope r3 K0) meets the pinching line
  // -F1 + r4 K0 d at d_x = (r3 K0 dm - E(dm) - F1) / ((r3 - r4) K0) > 0, so at
  // d = 0 the force is -F1; the reloading line towards -beta dm lies above it
  // there (its value at 0 is -E(beta dm) + Kp beta dm > -F1).
  double f0 = 0.0;
  for (int k = n - 1; k >= 0; --k) f0 = rig.force(Vec3(0, 0, dm * k / n), 2, step++);
  EXPECT_NEAR(f0, -c.F1_N, 1e-9 * c.F0_N);
  for (int k = -1; k >= -n; --k) rig.force(Vec3(0, 0, dm * k / n), 2, step++);
  // Reloading to +dm ends on the degraded line towards E(beta dm):
  // F(dm) = E(beta dm) - Kp (beta - 1) dm, Kp = K0 (delta0 / dm)^alpha.
  double f_dm = 0.0;
  for (int k = -n + 1; k <= n; ++k) f_dm = rig.force(Vec3(0, 0, dm * k / n), 2, step++);
  const double kp = c.K0_Npm * std::pow((c.F0_N / c.K0_Npm) / dm, c.alpha);
  const double f_expected = curee_env(c, c.beta * dm) - kp * (c.beta - 1.0) * dm;
  EXPECT_NEAR(f_dm, f_expected, 1e-9 * c.F0_N);
  EXPECT_LT(f_dm, curee_env(c, dm));  // strength degradation
  // Steady cycle dm -> -dm -> dm: a closed loop; dissipation = loop area.
  const double plastic_start = rig.js.spring_plastic_J(0);
  std::vector<double> xs, fs;
  for (int k = n; k > -n; --k) {
    xs.push_back(dm * k / n);
    fs.push_back(rig.force(Vec3(0, 0, xs.back()), 2, step++));
  }
  for (int k = -n; k < n; ++k) {
    xs.push_back(dm * k / n);
    fs.push_back(rig.force(Vec3(0, 0, xs.back()), 2, step++));
  }
  EXPECT_NEAR(rig.force(Vec3(0, 0, dm), 2, step++), f_expected, 1e-9 * c.F0_N);  // closed
  const double area = test::shoelace_area(xs, fs);
  EXPECT_GT(area, 0.0);
  EXPECT_NEAR(rig.js.spring_plastic_J(0) - plastic_start, area, 1e-9 * area);
}

// delta_p of the test's own envelope: where E(x) meets the pinching line
// F1 + r4 K0 x (bisection on the closed form above, not the library's).
double curee_pinch_point(const CureeParams& c) {
  double lo = 0.0, hi = c.delta_u_m;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (curee_env(c, mid) >= c.F1_N + c.r4 * c.K0_Npm * mid ? hi : lo) = mid;
  }
  return hi;
}

// Folz & Filiatrault's loops cross zero deformation at -F1 on the pinching
// line F = -F1 + r4 K0 delta and follow it until it meets the envelope at
// -delta_p; the force never jumps between reversals (no branch is steeper
// than the unloading slope r3 K0). Capping the pinching line by the
// envelope near zero, where E is 0, made the force jump by about F1.
TEST(CureeLaw, LoopCrossesZeroOnThePinchingLineWithoutAJump) {
  const CureeParams c = timber_curee();
  const double dp = curee_pinch_point(c);
  ASSERT_GT(dp, 0.0);
  ASSERT_LT(dp, c.delta_u_m);
  Rig rig(curee_spring(c), linear_spring(1e6), BreakCriterion::Never);
  const double dm = 0.006;
  const int n = 6000;  // steps of 1 um
  std::int64_t step = 0;
  double f_prev = 0.0;
  for (int k = 0; k <= n; ++k) f_prev = rig.force(Vec3(0, 0, dm * k / n), 2, step++);
  int on_pinch = 0, on_envelope = 0;
  double largest_jump = 0.0;
  for (int k = n - 1; k >= -n; --k) {
    const double d = dm * k / n;
    const double f = rig.force(Vec3(0, 0, d), 2, step++);
    largest_jump = std::max(largest_jump, std::abs(f - f_prev) / (c.r3 * c.K0_Npm * (dm / n)));
    f_prev = f;
    if (d < 0.0 && -d < dp * (1.0 - 1e-9)) {
      EXPECT_NEAR(f, -c.F1_N + c.r4 * c.K0_Npm * d, 1e-9 * c.F0_N) << d;
      ++on_pinch;
    } else if (-d > dp * (1.0 + 1e-9)) {
      // First excursion to -delta: beyond delta_p the envelope.
      EXPECT_NEAR(f, -curee_env(c, -d), 1e-9 * c.F0_N) << d;
      ++on_envelope;
    }
  }
  EXPECT_GT(on_pinch, 10);
  EXPECT_GT(on_envelope, 10);
  EXPECT_LE(largest_jump, 1.0 + 1e-9);
}

// A spring never deformed beyond delta_p is nonlinear elastic on the
// envelope (as SAWS, the model's own program, does): small cycles retrace
// sign(delta) E(|delta|), dissipate nothing, and cross zero continuously.
TEST(CureeLaw, SmallCyclesStayElasticOnTheEnvelope) {
  const CureeParams c = timber_curee();
  const double dp = curee_pinch_point(c);
  Rig rig(curee_spring(c), linear_spring(1e6), BreakCriterion::Never);
  const double a = 0.9 * dp;
  const int n = 400;
  std::int64_t step = 0;
  double work = 0.0, f_prev = 0.0, d_prev = 0.0;
  for (int cycle = 0; cycle < 3; ++cycle) {
    for (int k = 0; k < 4 * n; ++k) {
      // 0 -> a -> -a -> 0 as a triangle wave
      const int m = k % (4 * n);
      const double d = m < n ? a * m / n : (m < 3 * n ? a * (2.0 * n - m) / n : a * (m - 4.0 * n) / n);
      const double f = rig.force(Vec3(0, 0, d), 2, step++);
      EXPECT_NEAR(f, d >= 0.0 ? curee_env(c, d) : -curee_env(c, -d), 1e-9 * c.F0_N) << d;
      work += 0.5 * (f + f_prev) * (d - d_prev);
      f_prev = f;
      d_prev = d;
    }
  }
  const double f_end = rig.force(Vec3(0, 0, 0.0), 2, step++);
  EXPECT_EQ(f_end, 0.0);
  work += 0.5 * (f_end + f_prev) * (0.0 - d_prev);
  // Back at zero after whole cycles: what was stored is given back, up to
  // the trapezoid rule's error on the curved envelope (dx^2 / 12 of E'').
  EXPECT_LT(std::abs(rig.js.spring_plastic_J(0)), 1e-6 * 0.5 * c.K0_Npm * a * a);
  EXPECT_LT(std::abs(work), 1e-6 * 0.5 * c.K0_Npm * a * a);
}

// Parameters whose pinching line F1 + r4 K0 x lies above the envelope all
// the way to delta_u have no delta_p and are refused naming F1_N: with
// F1 = 0.99 F0 and r4 = 0.06 the line is 1470 N at x = 8 mm where E is
// 1400 N, and 1590 N against 1500 N at delta_u = 10 mm (test's own closed
// form above); r4 = 0.02 meets the envelope and is accepted.
TEST(CureeLaw, APinchingLineAboveTheWholeEnvelopeIsRefused) {
  CureeParams c = timber_curee();
  c.F1_N = 0.99 * c.F0_N;
  c.r4 = 0.06;
  for (double x = c.delta_u_m / 64; x <= c.delta_u_m; x += c.delta_u_m / 64)
    ASSERT_LT(curee_env(c, x), c.F1_N + c.r4 * c.K0_Npm * x) << x;
  try {
    compile_curee(c);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("F1_N must be small enough that the pinching line"), std::string::npos)
        << e.what();
  }
  c.r4 = 0.02;
  EXPECT_NO_THROW(compile_curee(c));
}

TEST(LinearLaw, ForceAndEnergy) {
  Rig rig(linear_spring(2e5), linear_spring(1e5));
  EXPECT_NEAR(rig.force(Vec3(0, 0, 1e-3), 2), 200.0, 1e-9);
  EXPECT_NEAR(rig.force(Vec3(2e-3, 0, 0), 0), 200.0, 1e-9);
  EXPECT_NEAR(rig.js.spring_elastic_J(1), 0.5 * 1e5 * 4e-6, 1e-15);
  EXPECT_EQ(rig.js.spring_plastic_J(1), 0.0);
}

}  // namespace
}  // namespace fq
