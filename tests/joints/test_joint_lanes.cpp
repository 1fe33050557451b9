// The lane kernel (joint_lane_kernels.h) against the general joint code: the
// same chain run twice, once with JointSystemSettings::lane_kernel on and
// once off, must give the same events (every field), the same final state
// of every body, the same per-spring deformations, forces and states and
// the same energy books, bit for bit. The kernel runs in each SIMD form
// this build and processor have (dem_core/lane_isa.h: SSE2, AVX2), against
// one general run in the SSE2 form (whose four-body rotation drift is the
// SSE2 one too). The lane kernel claims exactly that
// (it evaluates the general code's expressions in the general code's
// order), and the general code is itself checked against closed forms by
// the other joint tests.
//
// The chain mixes every shape the kernel must take or hand back: four
// corners with trilinear normal and shear springs (yield, unloading with a
// plastic offset, deletion, breaking under each criterion), linear springs,
// a trilinear normal with a linear shear law, points in a partial group of
// lanes (2 and 6 points), and joints the kernel must leave to the general
// code (a link system, a CUREE shear law).
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>

#include "dem_core/lane_isa.h"
#include "dem_core/simulation.h"
#include "joint_test_util.h"

namespace fq {
namespace {

TrilinearParams brittle(double k_Npm, double yield_m, double reference_m) {
  TrilinearParams t;
  t.yield_strain_tension = t.yield_strain_compression = yield_m / reference_m;
  t.yield_force_tension_N = t.yield_force_compression_N = k_Npm * yield_m;
  t.ultimate_strain_tension = t.ultimate_strain_compression = 5.0 * yield_m / reference_m;
  t.ultimate_force_tension_N = t.ultimate_force_compression_N = 1.2 * k_Npm * yield_m;
  return t;
}

JointLayout points_layout(const std::vector<Vec3>& offsets, const SpringDef& normal, const SpringDef& shear) {
  JointLayout lay;
  for (const Vec3& o : offsets) {
    SpringPointDef p;
    p.offset_m = o;
    p.normal = normal;
    p.shear = shear;
    lay.points.push_back(p);
  }
  return lay;
}

struct Outcome {
  test::JointRunOutcome run;
  std::size_t lane_joints = 0;
};

constexpr int kJoints = 8;
const int kLaneJoints[] = {0, 1, 2, 3, 4, 6};  // the joints the kernel takes

// The lane form for one scope (lane_isa.h), the previous one restored after.
class ScopedLaneIsa {
 public:
  explicit ScopedLaneIsa(LaneIsa isa) : previous_(active_lane_isa()) { ok_ = set_lane_isa(isa); }
  ~ScopedLaneIsa() { set_lane_isa(previous_); }
  bool ok() const { return ok_; }

 private:
  LaneIsa previous_;
  bool ok_ = false;
};

Outcome run(bool lane_kernel, int steps, LaneIsa isa) {
  const ScopedLaneIsa form(isa);
  EXPECT_TRUE(form.ok());
  test::ChainSpec spec;
  spec.n = kJoints;
  spec.length_m = 0.8;
  spec.width_m = spec.depth_m = 0.03;
  const double c = 0.012;  // corner offset (m)
  const double ref = 0.01;
  const SpringDef tri_n = trilinear_spring(brittle(2e4, 2e-4, ref), ref, 0.02);
  const SpringDef tri_s = trilinear_spring(brittle(1e4, 3e-4, ref), ref, 0.05);
  const SpringDef lin_n = linear_spring(2e4, 0.05), lin_s = linear_spring(1e4, 0.05);
  // A timber connection softer than the trilinear shear springs.
  const CureeParams cu = test::timber_curee(1e4, 3.0, 0.5, 1e-3);
  auto layout_of = [&](int i) -> JointLayout {
    switch (i) {
      case 0:
        return four_corner_layout(c, c, 1.0, tri_n, tri_s);
      case 1:
        return four_corner_layout(c, c, 1.0, lin_n, lin_s);
      case 2:
        return points_layout({Vec3(-c, 0, 0), Vec3(c, 0, 0)}, tri_n, tri_s);
      case 3:
        return points_layout({Vec3(-c, -c, 0), Vec3(0, -c, 0), Vec3(c, -c, 0), Vec3(-c, c, 0), Vec3(0, c, 0),
                              Vec3(c, c, 0)},
                             tri_n, tri_s);
      case 4:
        return four_corner_layout(c, c, 1.0, tri_n, tri_s);
      case 5: {
        LinkSystemDef l;
        l.side_m = 2 * c;
        l.gap_m = 0.005;
        l.axial = l.diagonal = l.shear = lin_n;
        return link_system_layout(l);
      }
      case 6:
        return four_corner_layout(c, c, 1.0, tri_n, lin_s);
      default:
        return four_corner_layout(c, c, 1.0, tri_n, curee_spring(cu, 0.02));
    }
  };
  auto fracture_of = [](int i) {
    JointBreakDef f;
    f.criterion = i == 2 ? BreakCriterion::AnySpringDeleted
                  : i == 4 ? BreakCriterion::StrainLimit
                  : i == 1 ? BreakCriterion::Never
                           : BreakCriterion::AllNormalSpringsDeleted;
    if (i == 4) f.strain_limit = 0.06;
    return f;
  };
  BodyStore bodies = test::chain_bodies(spec);
  auto add_joints = [&](JointSystem& js, const BodyStore& store) {
    const double l = spec.length_m / spec.n;
    for (int i = 0; i < spec.n; ++i) {
      JointDef d;
      d.body_a = i;
      d.body_b = i + 1;
      d.origin_m = Vec3(0, 0, i * l);
      d.layout = layout_of(i);
      d.fracture = fracture_of(i);
      js.add_joint(store, d);
    }
  };
  double omega_max = 0.0;
  {
    JointSystem probe(nullptr);
    add_joints(probe, bodies);
    omega_max = probe.stiffest_mode(bodies).omega_radps;
  }
  // Alternating kick: neighbours pull apart, shear and twist past each other.
  for (int i = 1; i <= spec.n; ++i) {
    const double sgn = (i % 2) ? 1.0 : -1.0;
    bodies.velocity_mps[std::size_t(i)] = Vec3(0.5 * sgn, 0.3 * sgn, 0.6 * sgn);
    const Vec3 w(20.0 * sgn, -15.0 * sgn, 30.0);
    const Mat3& r = bodies.rotation[std::size_t(i)];
    bodies.angular_velocity_radps[std::size_t(i)] = w;
    bodies.angular_momentum_Nms[std::size_t(i)] =
        r * bodies.principal_inertia_kgm2[std::size_t(i)].asDiagonal() * (r.transpose() * w);
  }
  SimulationSettings settings;
  settings.dt_s = 0.9 / omega_max;
  settings.duration_s = steps * settings.dt_s;
  Simulation sim(std::move(bodies), settings);
  JointSystemSettings js_settings;
  js_settings.lane_kernel = lane_kernel;
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs(), js_settings);
  add_joints(*js, sim.bodies());
  const JointSystem* joints = js.get();
  sim.add_force_provider(std::move(js));
  const RunResult rr = sim.run();
  EXPECT_EQ(rr.status, RunStatus::Completed);
  Outcome o;
  o.run = test::capture_outcome(sim, *joints);
  o.lane_joints = joints->lane_joint_count();
  return o;
}

void expect_same_bits_as_the_general_code(LaneIsa isa) {
  const int steps = 600;
  const Outcome lanes = run(true, steps, isa), general = run(false, steps, LaneIsa::Sse2);
  // The kernel took the joints it should and no other; the general run none.
  EXPECT_EQ(lanes.lane_joints, std::size(kLaneJoints));
  EXPECT_EQ(general.lane_joints, 0u);

  // The scenario covers what the kernel must hand to the general code:
  // springs of lane joints yield, are deleted, and lane joints break.
  int yielded = 0, deleted = 0, broken = 0;
  for (const Event& e : lanes.run.events) {
    const bool lane_joint = std::find(std::begin(kLaneJoints), std::end(kLaneJoints), e.joint_id) != std::end(kLaneJoints);
    if (!lane_joint) continue;
    yielded += e.kind == EventKind::SpringYielded;
    deleted += e.kind == EventKind::SpringDeleted;
    broken += e.kind == EventKind::JointBroken;
  }
  EXPECT_GT(yielded, 0);
  EXPECT_GT(deleted, 0);
  EXPECT_GT(broken, 0);
  EXPECT_LT(lanes.run.counts.broken, kJoints);  // and joints stay to carry load to the end

  test::expect_identical(lanes.run, general.run);
  std::printf("lanes (%s): %zu events (lane joints: %d yields, %d deletions, %d breaks), %d joints broken, %d yielded\n",
              lane_isa_name(isa), lanes.run.events.size(), yielded, deleted, broken, lanes.run.counts.broken,
              lanes.run.counts.yielded);
}

TEST(JointLanes, SameBitsAsTheGeneralCodeThroughYieldDeletionAndBreaking) {
  expect_same_bits_as_the_general_code(LaneIsa::Sse2);
}

TEST(JointLanes, Avx2FormSameBitsAsTheGeneralCode) {
  if (!lane_isa_available(LaneIsa::Avx2))
    GTEST_SKIP() << "no AVX2 kernels in this build or no AVX2 on this processor";
  expect_same_bits_as_the_general_code(LaneIsa::Avx2);
}

TEST(JointLanes, Avx512vlFormSameBitsAsTheGeneralCode) {
  if (!lane_isa_available(LaneIsa::Avx512vl))
    GTEST_SKIP() << "no AVX-512VL kernels in this build or no AVX-512VL on this processor";
  expect_same_bits_as_the_general_code(LaneIsa::Avx512vl);
}

}  // namespace
}  // namespace fq
