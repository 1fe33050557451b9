// Ground-motion time function: record interpolation, scaling in amplitude and
// time, windows, sums of components, refusal of unusable components, peaks.
// Expected values are hand-computed from the definitions in ground_motion.h
// (linear interpolation between samples; t_sim = time_scale * t_record).
// Sample times and values are binary fractions, so most checks are exact.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dem_core/ground_motion.h"

namespace {

using fq::AccelerationRecord;
using fq::GroundMotion;
using fq::GroundMotionComponent;
using fq::Vec3;

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// Samples at 0, 0.25, 0.5, 0.75, 1.0 s.
AccelerationRecord record_r() {
  AccelerationRecord r;
  r.source = "R.AT2";
  r.dt_s = 0.25;
  r.acceleration_mps2 = {0.0, 1.0, -2.0, 4.0, 0.5};
  return r;
}

GroundMotionComponent component(const AccelerationRecord& r, const Vec3& direction) {
  GroundMotionComponent c;
  c.record = r;
  c.direction = direction;
  return c;
}

TEST(AccelerationRecord, InterpolatesLinearlyAndIsZeroOutside) {
  const AccelerationRecord r = record_r();
  EXPECT_EQ(r.duration_s(), 1.0);
  // On samples: the samples.
  for (int k = 0; k < 5; ++k) EXPECT_EQ(r.at(0.25 * k), r.acceleration_mps2[std::size_t(k)]) << k;
  // Half-way: the mean of the neighbours.
  EXPECT_EQ(r.at(0.125), 0.5);
  EXPECT_EQ(r.at(0.375), -0.5);
  EXPECT_EQ(r.at(0.625), 1.0);
  EXPECT_EQ(r.at(0.875), 2.25);
  // Anywhere: (1 - f) a_k + f a_k+1 with f = 0.2 at t = 0.3 s.
  EXPECT_NEAR(r.at(0.3), 0.8 * 1.0 + 0.2 * -2.0, 1e-15);
  // Outside [0, duration]: no motion.
  EXPECT_EQ(r.at(-1e-9), 0.0);
  EXPECT_EQ(r.at(-5.0), 0.0);
  EXPECT_EQ(r.at(1.0 + 1e-6), 0.0);
  EXPECT_EQ(r.at(100.0), 0.0);
  EXPECT_EQ(r.at(kNaN), 0.0);
  // An empty record is no motion.
  EXPECT_EQ(AccelerationRecord{}.at(0.0), 0.0);
  EXPECT_EQ(AccelerationRecord{}.duration_s(), 0.0);
}

TEST(AccelerationRecord, PeakIsTheSignedSampleOfLargestMagnitude) {
  double t = -1.0;
  EXPECT_EQ(record_r().peak_mps2(&t), 4.0);
  EXPECT_EQ(t, 0.75);
  AccelerationRecord r;
  r.dt_s = 0.25;
  r.acceleration_mps2 = {1.0, -3.0, 2.0};
  EXPECT_EQ(r.peak_mps2(&t), -3.0);
  EXPECT_EQ(t, 0.25);
  EXPECT_EQ(r.peak_mps2(), -3.0);
}

TEST(GroundMotion, EmptyMotionIsZero) {
  const GroundMotion gm;
  EXPECT_TRUE(gm.empty());
  EXPECT_TRUE(gm.acceleration(0.3).isZero(0.0));
  EXPECT_TRUE(gm.peak_abs_mps2().isZero(0.0));
  EXPECT_EQ(gm.end_time_s(), 0.0);
}

TEST(GroundMotion, SingleComponentFollowsTheRecordAlongItsDirection) {
  GroundMotion gm;
  gm.add_component(component(record_r(), Vec3::UnitY()));
  EXPECT_FALSE(gm.empty());
  for (double t : {0.0, 0.125, 0.3, 0.75, 1.0})
    EXPECT_TRUE(gm.acceleration(t).isApprox(Vec3(0.0, record_r().at(t), 0.0), 1e-15)) << t;
  EXPECT_TRUE(gm.acceleration(-0.1).isZero(0.0));
  EXPECT_TRUE(gm.acceleration(1.5).isZero(0.0));  // beyond the record
  EXPECT_EQ(gm.end_time_s(), 1.0);
}

TEST(GroundMotion, AmplitudeScaleMultiplies) {
  GroundMotionComponent c = component(record_r(), Vec3::UnitX());
  c.amplitude_scale = 2.5;
  GroundMotion gm;
  gm.add_component(c);
  EXPECT_EQ(gm.acceleration(0.75).x(), 10.0);
  EXPECT_EQ(gm.acceleration(0.125).x(), 1.25);
  c.amplitude_scale = -1.0;  // a reversed polarity is a legitimate choice
  GroundMotion reversed;
  reversed.add_component(c);
  EXPECT_EQ(reversed.acceleration(0.75).x(), -4.0);
}

TEST(GroundMotion, TimeScaleCompressesTheRecord) {
  // time_scale 0.5: t_sim = 0.5 t_record, so a_g(t) = a_rec(2 t) (a model at
  // length scale 1/4 under similitude, t_model = sqrt(1/4) t_proto).
  GroundMotionComponent c = component(record_r(), Vec3::UnitX());
  c.time_scale = 0.5;
  GroundMotion gm;
  gm.add_component(c);
  EXPECT_EQ(gm.acceleration(0.0625).x(), 0.5);   // record 0.125 s
  EXPECT_EQ(gm.acceleration(0.375).x(), 4.0);    // record 0.75 s
  EXPECT_EQ(gm.acceleration(0.5).x(), 0.5);      // record 1.0 s, the last sample
  EXPECT_TRUE(gm.acceleration(0.51).isZero(0.0));  // record 1.02 s: over
  EXPECT_EQ(gm.end_time_s(), 0.5);
  // Stretching works the same way.
  c.time_scale = 2.0;
  GroundMotion slow;
  slow.add_component(c);
  EXPECT_EQ(slow.acceleration(1.5).x(), 4.0);  // record 0.75 s
  EXPECT_EQ(slow.end_time_s(), 2.0);
}

TEST(GroundMotion, WindowSelectsPartOfTheRecordAndIsZeroOutside) {
  GroundMotionComponent c = component(record_r(), Vec3::UnitX());
  c.window_start_s = 0.25;
  c.window_length_s = 0.5;
  GroundMotion gm;
  gm.add_component(c);
  // a_g(t) = a_rec(0.25 + t) for 0 <= t <= 0.5.
  EXPECT_EQ(gm.acceleration(0.0).x(), 1.0);
  EXPECT_EQ(gm.acceleration(0.125).x(), -0.5);
  EXPECT_EQ(gm.acceleration(0.25).x(), -2.0);
  EXPECT_EQ(gm.acceleration(0.5).x(), 4.0);  // window end, included
  // Outside the window: zero, although the record goes on.
  EXPECT_TRUE(gm.acceleration(0.5 + 1e-9).isZero(0.0));
  EXPECT_TRUE(gm.acceleration(0.625).isZero(0.0));
  EXPECT_TRUE(gm.acceleration(-1e-9).isZero(0.0));
  EXPECT_EQ(gm.end_time_s(), 0.5);

  // Window and time scale together: the window length is in record seconds.
  c.time_scale = 2.0;
  GroundMotion slow;
  slow.add_component(c);
  EXPECT_EQ(slow.acceleration(0.5).x(), -2.0);  // record 0.25 + 0.25
  EXPECT_EQ(slow.acceleration(1.0).x(), 4.0);   // record 0.25 + 0.5, window end
  EXPECT_TRUE(slow.acceleration(1.0 + 1e-9).isZero(0.0));
  EXPECT_EQ(slow.end_time_s(), 1.0);

  // A window longer than what is left of the record ends with the record.
  c.time_scale = 1.0;
  c.window_start_s = 0.5;
  c.window_length_s = 10.0;
  GroundMotion tail;
  tail.add_component(c);
  EXPECT_EQ(tail.acceleration(0.25).x(), 4.0);
  EXPECT_EQ(tail.acceleration(0.5).x(), 0.5);
  EXPECT_TRUE(tail.acceleration(0.75).isZero(0.0));
  EXPECT_EQ(tail.end_time_s(), 0.5);
}

TEST(GroundMotion, WindowEndIsReachedAtTheStepLoopsLastTime) {
  // The step loop's last time is n dt with n = round(duration / dt), and
  // (n dt) / time_scale can land an ulp past the window length: 20 record
  // seconds at time scale 0.3162 (the frames) and dt = 1e-5 s end at
  // t = 632400e-5 s, 20.000000000000004 record seconds. The last step must
  // still feel the window's last sample.
  AccelerationRecord r;
  r.source = "ramp";
  r.dt_s = 0.01;
  for (int k = 0; k <= 3000; ++k) r.acceleration_mps2.push_back(1.0 + 0.001 * k);  // 1 + 0.1 t (m/s^2)
  for (const auto& [time_scale, length_s] : {std::pair{0.3162, 20.0}, std::pair{0.2108, 3.0}, std::pair{0.5, 3.0}}) {
    GroundMotionComponent c = component(r, Vec3::UnitX());
    c.time_scale = time_scale;
    c.window_length_s = length_s;
    GroundMotion gm;
    gm.add_component(c);
    const double dt = 1e-5;
    const auto n = std::llround(gm.end_time_s() / dt);
    ASSERT_GT(double(n) * dt / time_scale, length_s) << "the case this test is about";
    EXPECT_NEAR(gm.acceleration(double(n) * dt).x(), 1.0 + 0.1 * length_s, 1e-9) << time_scale << " " << length_s;
    // A step later is outside.
    EXPECT_TRUE(gm.acceleration(double(n + 1) * dt).isZero(0.0));
  }
}

TEST(GroundMotion, ComponentsAlongDifferentDirectionsSum) {
  AccelerationRecord s;
  s.source = "S.AT2";
  s.dt_s = 0.5;
  s.acceleration_mps2 = {2.0, 2.0, -1.0};
  AccelerationRecord u;
  u.source = "U.AT2";
  u.dt_s = 0.125;
  u.acceleration_mps2 = {0.0, 1.0, 1.0, 1.0, 0.0};  // 0.5 s long
  GroundMotion gm;
  gm.add_component(component(record_r(), Vec3::UnitX()));
  gm.add_component(component(s, Vec3(0.0, 3.0, 4.0)));  // normalised to (0, 0.6, 0.8)
  GroundMotionComponent cu = component(u, Vec3(1.0, 1.0, 0.0));
  cu.amplitude_scale = 2.0;
  gm.add_component(cu);
  ASSERT_EQ(gm.components().size(), 3u);
  EXPECT_TRUE(gm.components()[1].direction.isApprox(Vec3(0.0, 0.6, 0.8), 1e-15));
  EXPECT_NEAR(gm.components()[2].direction.norm(), 1.0, 1e-15);
  const double h = std::sqrt(0.5);
  for (double t : {0.0, 0.125, 0.3, 0.5, 0.75, 1.0}) {
    const Vec3 expected = record_r().at(t) * Vec3::UnitX() + s.at(t) * Vec3(0.0, 0.6, 0.8) +
                          2.0 * u.at(t) * Vec3(h, h, 0.0);
    EXPECT_TRUE((gm.acceleration(t) - expected).isZero(1e-15)) << "t = " << t << ": " << gm.acceleration(t).transpose()
                                                               << " vs " << expected.transpose();
  }
  // Hand values at t = 0.25: R 1, S 2, U 1 (x 2 scale).
  EXPECT_TRUE(gm.acceleration(0.25).isApprox(Vec3(1.0 + 2.0 * h, 1.2 + 2.0 * h, 1.6), 1e-15));
  EXPECT_EQ(gm.end_time_s(), 1.0);  // the longest component
}

TEST(GroundMotion, UnusableComponentsThrowAndNameTheRecord) {
  struct Case {
    const char* what;
    GroundMotionComponent c;
  };
  auto base = [] { return component(record_r(), Vec3::UnitX()); };
  std::vector<Case> cases;
  {
    Case k{"one sample", base()};
    k.c.record.acceleration_mps2 = {1.0};
    cases.push_back(k);
  }
  {
    Case k{"no sample", base()};
    k.c.record.acceleration_mps2.clear();
    cases.push_back(k);
  }
  for (double dt : {0.0, -0.01, kNaN, kInf}) {
    Case k{"bad dt", base()};
    k.c.record.dt_s = dt;
    cases.push_back(k);
  }
  for (const Vec3& d : {Vec3(0.0, 0.0, 0.0), Vec3(kNaN, 0.0, 0.0), Vec3(kInf, 1.0, 0.0)}) {
    Case k{"bad direction", base()};
    k.c.direction = d;
    cases.push_back(k);
  }
  for (double ts : {0.0, -1.0, kNaN, kInf}) {
    Case k{"bad time scale", base()};
    k.c.time_scale = ts;
    cases.push_back(k);
  }
  for (double as : {kNaN, kInf}) {
    Case k{"bad amplitude scale", base()};
    k.c.amplitude_scale = as;
    cases.push_back(k);
  }
  for (double ws : {-0.1, kNaN}) {
    Case k{"bad window start", base()};
    k.c.window_start_s = ws;
    cases.push_back(k);
  }
  for (double wl : {0.0, -1.0, kNaN}) {
    Case k{"bad window length", base()};
    k.c.window_length_s = wl;
    cases.push_back(k);
  }
  for (const Case& k : cases) {
    GroundMotion gm;
    try {
      gm.add_component(k.c);
      ADD_FAILURE() << k.what << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("R.AT2"), std::string::npos) << k.what << ": " << e.what();
    }
    EXPECT_TRUE(gm.empty()) << k.what;
  }
}

TEST(GroundMotion, PeakAbsIsPerWorldAxisOverTheWindows) {
  // Component 1 along x, window [0, 0.6] s of R: samples 0, 1, -2 count, the
  // 4 at 0.75 s does not: peak x = 2. Component 2: S scaled by 2 along
  // (0, 0.6, 0.8): |4| -> y 2.4, z 3.2.
  AccelerationRecord s;
  s.dt_s = 0.5;
  s.acceleration_mps2 = {2.0, 2.0, -1.0};
  GroundMotionComponent c1 = component(record_r(), Vec3::UnitX());
  c1.window_length_s = 0.6;
  GroundMotionComponent c2 = component(s, Vec3(0.0, 3.0, 4.0));
  c2.amplitude_scale = 2.0;
  GroundMotion gm;
  gm.add_component(c1);
  gm.add_component(c2);
  EXPECT_TRUE(gm.peak_abs_mps2().isApprox(Vec3(2.0, 2.4, 3.2), 1e-15)) << gm.peak_abs_mps2().transpose();

  // A window that starts later: samples at record 0.5, 0.75, 1.0 -> peak 4,
  // wherever the time scale puts them.
  GroundMotionComponent late = component(record_r(), Vec3::UnitZ());
  late.window_start_s = 0.5;
  late.time_scale = 0.25;
  GroundMotion gm_late;
  gm_late.add_component(late);
  EXPECT_TRUE(gm_late.peak_abs_mps2().isApprox(Vec3(0.0, 0.0, 4.0), 1e-15));
}

// A run shorter than its window feels the motion only up to its end: the
// peaks up to until_s (the run's duration) are those of the part applied.
// A ramp a(t) = t m/s^2 sampled every 1 s over 10 s, along x, time scale 2
// (record second r is applied at 2 r): up to 5 s of the run the record
// has reached r = 2.5 s, between its samples 2 and 3, where it is linear:
// peak 2.5 m/s^2, not the 10 of the whole window (nor the 2 of the last
// sample before the end). A window starting at record 3.5 s (between two
// samples, time scale 1) is felt from a(3.5) = 3.5 on: its peak up to
// 0.25 s of the run, record 3.5 to 3.75 s, is 3.75.
TEST(GroundMotion, PeaksUpToTheRunsEndAreThoseOfThePartApplied) {
  AccelerationRecord ramp;
  ramp.dt_s = 1.0;
  for (int k = 0; k <= 10; ++k) ramp.acceleration_mps2.push_back(double(k));
  GroundMotionComponent c = component(ramp, Vec3::UnitX());
  c.time_scale = 2.0;
  GroundMotion gm;
  gm.add_component(c);
  EXPECT_NEAR(gm.peak_abs_mps2().x(), 10.0, 1e-15);
  EXPECT_NEAR(gm.peak_abs_mps2(5.0).x(), 2.5, 1e-15);
  EXPECT_NEAR(gm.peak_horizontal_mps2(5.0), 2.5, 1e-15);
  EXPECT_NEAR(gm.peak_horizontal_mps2(100.0), 10.0, 1e-15);

  GroundMotionComponent late = component(ramp, Vec3::UnitY());
  late.window_start_s = 3.5;
  GroundMotion gm_late;
  gm_late.add_component(late);
  EXPECT_NEAR(gm_late.peak_horizontal_mps2(0.25), 3.75, 1e-15);
  EXPECT_NEAR(gm_late.peak_abs_mps2(0.25).y(), 3.75, 1e-15);
}

TEST(GroundMotion, HorizontalPeakIsTheSameWhateverTheHorizontalDirection) {
  // Record R (peak |4| at 0.75 s) along x, along y, and along directions
  // turned 30 and 45 degrees about z: the horizontal PGA is 4 every time
  // (|(a_x, a_y)| is unchanged by a turn about z), where the larger of the
  // x and y peaks gives 4 cos 45 = 2.83 on the diagonal. A vertical part
  // does not count: along (3, 0, 4) / 5 it is 4 x 3/5 = 2.4.
  for (const double turn_deg : {0.0, 90.0, 30.0, 45.0, -135.0}) {
    const double turn = turn_deg * std::numbers::pi / 180.0;
    GroundMotion gm;
    gm.add_component(component(record_r(), Vec3(std::cos(turn), std::sin(turn), 0.0)));
    EXPECT_NEAR(gm.peak_horizontal_mps2(), 4.0, 1e-14) << turn_deg;
  }
  GroundMotion inclined;
  inclined.add_component(component(record_r(), Vec3(3.0, 0.0, 4.0)));
  EXPECT_NEAR(inclined.peak_horizontal_mps2(), 2.4, 1e-14);
  // Two horizontal components at once: the peak of the vector sum, not of
  // either part. S {3} along x and {4} along y at t = 0 give |(3, 4)| = 5.
  AccelerationRecord sx, sy;
  sx.dt_s = sy.dt_s = 0.5;
  sx.acceleration_mps2 = {3.0, 0.0};
  sy.acceleration_mps2 = {4.0, 0.0};
  GroundMotion both;
  both.add_component(component(sx, Vec3::UnitX()));
  both.add_component(component(sy, Vec3::UnitY()));
  EXPECT_NEAR(both.peak_horizontal_mps2(), 5.0, 1e-14);
  EXPECT_EQ(GroundMotion{}.peak_horizontal_mps2(), 0.0);
}

TEST(GroundMotion, PeakAbsOfComponentsSharingAnAxisIsThePeakOfTheirSum) {
  // Two records along x: {1, 0, -1} and {1, 1, 1}; their sum {2, 1, 0} peaks
  // at 2 (each alone would say 1). An oblique third along (1, 1, 0)/sqrt 2
  // with {2 sqrt 2, 0, 0} adds (2, 2, 0) at t = 0: x = 1 + 1 + 2 = 4, y = 2.
  AccelerationRecord a, b, o;
  a.dt_s = b.dt_s = o.dt_s = 0.5;
  a.acceleration_mps2 = {1.0, 0.0, -1.0};
  b.acceleration_mps2 = {1.0, 1.0, 1.0};
  o.acceleration_mps2 = {2.0 * std::sqrt(2.0), 0.0, 0.0};
  GroundMotion gm;
  gm.add_component(component(a, Vec3::UnitX()));
  gm.add_component(component(b, Vec3::UnitX()));
  EXPECT_TRUE(gm.peak_abs_mps2().isApprox(Vec3(2.0, 0.0, 0.0), 1e-15)) << gm.peak_abs_mps2().transpose();
  gm.add_component(component(o, Vec3(1.0, 1.0, 0.0)));
  EXPECT_TRUE(gm.peak_abs_mps2().isApprox(Vec3(4.0, 2.0, 0.0), 1e-14)) << gm.peak_abs_mps2().transpose();
}

}  // namespace
