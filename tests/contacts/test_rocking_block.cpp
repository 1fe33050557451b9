// A slender block rocking on the ground under a horizontal ground
// acceleration, against Housner's closed forms (Bull. Seismol. Soc. Am. 53,
// 403-417, 1963):
//   uplift needs a_g > g b / h (half-width b, half-height h), and
//   a rectangular pulse of amplitude a_p and duration t_p overturns the
//   block when a_p >= g alpha / (1 - exp(-p t_p)), alpha = atan(b / h),
//   p^2 = 3 g / (4 R), R = sqrt(b^2 + h^2) (slender-block linearisation).
// Derivation of the pulse criterion (energy): during the pulse the
// linearised rocking equation theta'' = p^2 (theta - alpha + a_p / g) gives
// theta1 = (beta - 1) alpha (cosh(p t_p) - 1), theta1' = (beta - 1) alpha p
// sinh(p t_p) with beta = a_p / (g alpha); afterwards free rocking conserves
// theta'^2 - p^2 (theta - alpha)^2, and the block passes theta = alpha (tips
// over) iff theta1' >= p (alpha - theta1), i.e. (beta - 1)(e^{p t_p} - 1) >= 1.
// Margins: the tests sit 10 % below and above each threshold. The
// linearisation (sin x ~ x, cos x ~ 1 for x <= alpha = 0.0997 rad) is good to
// alpha^2 / 2 = 0.5 %, the contact compliance tilts the block by ~5e-4 rad
// (0.5 % of alpha) before uplift: 10 % leaves a wide gap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scene_helpers.h"

namespace {

using fq::Vec3;

constexpr double kB = 0.025, kH = 0.25;  // half-width and half-height (m)
constexpr double kDensity = 500.0, kK = 1e5;

fq::GroundMotion ramp_then_hold(double level_mps2, double ramp_s, double total_s) {
  fq::GroundMotionComponent c;
  c.record.dt_s = 1e-3;
  const int n = int(total_s / c.record.dt_s) + 1;
  for (int k = 0; k < n; ++k) {
    const double t = k * c.record.dt_s;
    c.record.acceleration_mps2.push_back(level_mps2 * std::min(1.0, t / ramp_s));
  }
  c.direction = Vec3::UnitX();
  fq::GroundMotion gm;
  gm.add_component(c);
  return gm;
}

fq::GroundMotion rectangular_pulse(double level_mps2, double duration_s, double total_s) {
  fq::GroundMotionComponent c;
  c.record.dt_s = 1e-4;
  const int n = int(total_s / c.record.dt_s) + 1;
  for (int k = 0; k < n; ++k) c.record.acceleration_mps2.push_back(k * c.record.dt_s <= duration_s ? level_mps2 : 0.0);
  c.direction = Vec3::UnitX();
  fq::GroundMotion gm;
  gm.add_component(c);
  return gm;
}

struct Outcome {
  double max_tilt_rad = 0.0;
  double final_tilt_rad = 0.0;
  std::size_t min_contacts = 8;
};

Outcome run_block(fq::GroundMotion gm, double duration_s) {
  fq::BodyStore store;
  const double m = 8.0 * kB * kB * kH * kDensity;
  const double d = m * fq::kStandardGravity_mps2 / (4.0 * kK);  // start at the static overlap
  fq::test::add_box(store, Vec3(2 * kB, 2 * kB, 2 * kH), kDensity, Vec3(0.0, 0.0, kH - d));
  fq::SimulationSettings s;
  s.dt_s = 1e-4;
  s.duration_s = duration_s;
  // mu = 1 > a_g / g everywhere here: the block rocks, it does not slide.
  auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
    c.set_ground(0.0, fq::test::params(kK, 0.5, 1.0));
  }, std::move(gm));
  Outcome out;
  const auto steps = scene.sim->total_steps();
  for (std::int64_t k = 0; k < steps; ++k) {
    scene.sim->step();
    const double tilt = std::acos(std::clamp(scene.sim->bodies().rotation[0](2, 2), -1.0, 1.0));
    out.max_tilt_rad = std::max(out.max_tilt_rad, tilt);
    out.final_tilt_rad = tilt;
    if (scene.sim->bodies().position_m[0].z() < 2 * kH) out.min_contacts = std::min(out.min_contacts, scene.contacts->contact_count());
  }
  return out;
}

const double kAlpha = std::atan(kB / kH);

TEST(RockingBlock, UpliftThresholdIsGTimesBOverH) {
  // Quasi-static ramp (0.5 s, against an elastic rocking period of 0.09 s)
  // to a held level, so the spring foundation does not overshoot.
  const double a_uplift = fq::kStandardGravity_mps2 * kB / kH;
  const Outcome below = run_block(ramp_then_hold(0.9 * a_uplift, 0.5, 2.0), 1.5);
  EXPECT_EQ(below.min_contacts, 4u);              // no corner ever lifted
  EXPECT_LT(below.max_tilt_rad, 0.05 * kAlpha);   // only elastic tilt
  const Outcome above = run_block(ramp_then_hold(1.1 * a_uplift, 0.5, 2.0), 1.5);
  EXPECT_EQ(above.min_contacts, 2u);              // rocks on one edge
  // A held acceleration above the threshold tips the block over.
  EXPECT_GT(above.final_tilt_rad, 0.5 * std::numbers::pi / 2);
}

TEST(RockingBlock, RectangularPulseOverturnsAccordingToHousner) {
  const double g = fq::kStandardGravity_mps2;
  const double p = std::sqrt(3.0 * g / (4.0 * std::hypot(kB, kH)));
  const double t_p = 1.0 / p;  // p t_p = 1
  const double a_crit = g * kAlpha / (1.0 - std::exp(-p * t_p));
  const Outcome below = run_block(rectangular_pulse(0.9 * a_crit, t_p, 3.0), 2.5);
  EXPECT_GT(below.max_tilt_rad, 0.2 * kAlpha);  // it did rock
  EXPECT_LT(below.max_tilt_rad, kAlpha);        // but never passed the tipping angle
  EXPECT_LT(below.final_tilt_rad, kAlpha);
  const Outcome above = run_block(rectangular_pulse(1.1 * a_crit, t_p, 3.0), 2.5);
  EXPECT_GT(above.final_tilt_rad, 0.5 * std::numbers::pi / 2);  // lies on its side
}

}  // namespace
