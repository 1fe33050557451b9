// Storeys sliding on joints soft in shear (io/storey_drift.h): a floor
// sliding on its column tops and columns sliding on their feet, run from a
// case file against the oscillator's closed form. Each run is 240 000
// steps, 0.7 s in the plain build and 15-16 s under the sanitizers, so
// this program is labelled `slow` and runs in the plain suite only
// (scripts/sanitize.sh); the slip bookkeeping it exercises runs under the
// sanitizers in test_storey_drift's unit tests of the monitor.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io/storey_drift.h"
#include "io_test_util.h"

namespace fq {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

// A square storey like the top-slip probe's (p4_top_slip): four columns
// 0.3 m tall at (0 | 0.5, 0 | 0.5), 20 x 20 mm, of wood (450 kg/m^3), and
// a floor of four beams 0.5 m long, 20 x 20 mm, of 1250 kg/m^3 joining
// their tops (joints.hub_kind: beam, so each column tenons into a floor
// beam). Each column end carries a four-corner joint of the type `top`
// (column to floor) or `foot` (column to ground): "soft" (normal springs
// 1e7 N/m, shear springs k_s = 10 N/m) or "rigid" (1e8 N/m both); the
// beams are joined rigidly to each other. No gravity. The ground
// accelerates along x by a(t) = a_f min(t / ramp_s, 1), a_f = 2 m/s^2,
// sampled every millisecond (linear between samples), for `duration_s`.
std::string square_storey_case(const fs::path& dir, const char* top, const char* foot, double ramp_s,
                               double duration_s) {
  {
    std::ofstream record(dir / "ramp.txt");
    record.precision(17);
    const int samples = int(std::ceil(duration_s / 1e-3));
    for (int k = 0; k <= samples; ++k) record << 1e-3 * k << " " << 2.0 * std::min(1e-3 * k / ramp_s, 1.0) << "\n";
  }
  std::ostringstream t;
  t << "framequake_case: 1\n"
       "time: {dt_s: 5.0e-6, duration_s: "
    << duration_s
    << ", gravity_mps2: [0, 0, 0]}\n"
       "materials: [{name: wood, density_kg_per_m3: 450}, {name: floor, density_kg_per_m3: 1250}]\n"
       "sections: [{name: sq, width_m: 0.02, depth_m: 0.02}]\n"
       "nodes:\n"
       "  - {id: b00, xyz_m: [0, 0, 0]}\n  - {id: t00, xyz_m: [0, 0, 0.3]}\n"
       "  - {id: b01, xyz_m: [0, 0.5, 0]}\n  - {id: t01, xyz_m: [0, 0.5, 0.3]}\n"
       "  - {id: b10, xyz_m: [0.5, 0, 0]}\n  - {id: t10, xyz_m: [0.5, 0, 0.3]}\n"
       "  - {id: b11, xyz_m: [0.5, 0.5, 0]}\n  - {id: t11, xyz_m: [0.5, 0.5, 0.3]}\n"
       "members:\n"
       "  - {id: c00, kind: column, nodes: [b00, t00], section: sq, material: wood}\n"
       "  - {id: c01, kind: column, nodes: [b01, t01], section: sq, material: wood}\n"
       "  - {id: c10, kind: column, nodes: [b10, t10], section: sq, material: wood}\n"
       "  - {id: c11, kind: column, nodes: [b11, t11], section: sq, material: wood}\n"
       "  - {id: bx0, kind: beam, nodes: [t00, t10], section: sq, material: floor}\n"
       "  - {id: by1, kind: beam, nodes: [t10, t11], section: sq, material: floor}\n"
       "  - {id: bx1, kind: beam, nodes: [t11, t01], section: sq, material: floor}\n"
       "  - {id: by0, kind: beam, nodes: [t01, t00], section: sq, material: floor}\n"
       "joint_types:\n"
       "  - {name: rigid, layout: four_corner, normal: {law: linear, stiffness_N_per_m: 1.0e8},\n"
       "     shear: {law: linear, stiffness_N_per_m: 1.0e8}, fracture: {criterion: never}}\n"
       "  - {name: soft, layout: four_corner, corner_fraction: 1, normal: {law: linear, stiffness_N_per_m: 1.0e7},\n"
       "     shear: {law: linear, stiffness_N_per_m: 10}, fracture: {criterion: never}}\n"
       "joints:\n"
       "  hub_kind: beam\n"
       "  support_type: "
    << foot
    << "\n"
       "  rules: [{kinds: [beam, beam], type: rigid}, {kinds: [column, beam], type: "
    << top
    << "}]\n"
       "supports: [{node: b00}, {node: b01}, {node: b10}, {node: b11}]\n"
       "ground_motion:\n"
       "  components: [{file: ramp.txt, format: two_column, axis: x}]\n"
       "output: {folder: "
    << (dir / "out").string() << ", frame_interval_s: 10.0, history_interval_s: 0.01}\n";
  return t.str();
}

// Runs the square storey with its soft joints at the column tops ("soft",
// "rigid") or at the feet ("rigid", "soft"), where m_kg slides on
// K = 4 joints x 4 corners x 10 N/m = 160 N/m, under a ramp of two of that
// oscillator's periods, to 0.2 s past it. Checks what both cases share:
// the run completes, the slip that gives (`slip`) peaks at u_f = m a_f / K
// (a_f = 2 m/s^2) within 0.1 %, the floor drift at u_f / h, while the other
// slip and the columns' drift stay near nothing (standing); and the slip
// warning gives the floor drift as `floor_ratio` (damaged by it), says
// `said` and not `unsaid`, and does not claim that joints broke.
void expect_sliding_square_storey(const TempDir& dir, const char* top, const char* foot, double m_kg,
                                  double StoreyDriftRecord::*slip, double StoreyDriftRecord::*other,
                                  const std::string& floor_ratio, const char* said, const char* unsaid) {
  const double K = 4.0 * 4.0 * 10.0, a_f = 2.0, h = 0.3, u_f = m_kg * a_f / K;
  const double ramp_s = 2.0 * 2.0 * M_PI * std::sqrt(m_kg / K);
  const CaseRunReport report = run_case(
      load_case_file(dir.write("storey.yaml", square_storey_case(dir.path(), top, foot, ramp_s, ramp_s + 0.2))), {});
  EXPECT_EQ(report.result.status, RunStatus::Completed);
  ASSERT_EQ(report.storeys.size(), 1u);
  const StoreyDriftRecord& r = report.storeys[0].drift;
  EXPECT_NEAR(r.*slip, u_f, 1e-3 * u_f);
  EXPECT_NEAR(r.peak_floor_ratio_rad, u_f / h, 1e-3 * u_f / h);
  EXPECT_LT(r.*other, 1e-6);
  EXPECT_LT(r.peak_ratio_rad, 1e-4);
  EXPECT_EQ(report.storeys[0].verdict, StoreyVerdict::Standing);
  std::string warning;
  for (const std::string& w : report.warnings)
    if (w.find("storey 1's floor moved") != std::string::npos) warning = w;
  EXPECT_NE(warning.find("storey 1's floor moved " + floor_ratio +
                         " rad of its height relative to the foundation, which would make it damaged"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find(said), std::string::npos) << warning;
  EXPECT_EQ(warning.find(unsaid), std::string::npos) << warning;
  EXPECT_EQ(warning.find("joints break"), std::string::npos) << warning;
}

// The top-slip probe's storey (square_storey_case): its column feet rigid,
// its column tops joined to the floor by joints stiff in bending and soft
// in shear. The floor slides on its column tops while the columns, on
// rigid feet, stand (their tops move about 1e-6 m).
//   The floor's mass: four beams of 0.5 x 0.02 x 0.02 m at 1250 kg/m^3,
// m = 4 x 0.25 = 1.0 kg. Each column top's joint has its normal along the
// column (the joined member's axis) and four corner points with two shear
// springs of k_s each in the horizontal plane: the floor rests on
// K = 4 joints x 4 corners x k_s = 160 N/m along x (the normal springs,
// 1e7 N/m, keep it from rocking). Relative to the ground the floor feels
// -m a(t): m u'' + K u = m a(t) for its slip u on the column tops. Under
// the ramp a_f t / T_r, from rest, u(t) = (m a_f / K) (t - sin(w t) / w) / T_r,
// w = sqrt(K / m); u' = (m a_f / K)(1 - cos(w t)) / T_r >= 0, so u grows
// without overshoot, and a ramp of two whole periods (T_r = 4 pi / w)
// leaves the floor at rest at u_f = m a_f / K when the acceleration turns
// constant: there it stays. Peak top slip u_f = 1.0 x 2 / 160 = 12.5 mm;
// peak floor drift u_f / h = 0.0125 / 0.3 = 0.0417 rad, past the 1/30
// safety limit, while the columns' drift stays a few 1e-6 rad: standing by
// the verdict, with a warning that the floor slid on its column tops.
// (The floor was taken at the column top points until the top-slip probe:
// the floor drift read 4e-6 rad, the same as the columns'.) The 0.1 %
// allowed is far above what the millisecond samples of the record and the
// columns' 1e-6 m leave, and far below the 16 % overshoot of a ramp that
// does not end on a whole period.
TEST(StoreyDrift, AFloorSlidingOnItsColumnTopsIsItsTopSlipAndFloorDrift) {
  TempDir dir;
  const double m = 4.0 * 0.5 * 0.02 * 0.02 * 1250.0;
  ASSERT_NEAR(m * 2.0 / 160.0, 0.0125, 1e-15);
  expect_sliding_square_storey(dir, "soft", "rigid", m, &StoreyDriftRecord::peak_top_slip_m,
                               &StoreyDriftRecord::peak_base_slip_m, "0.0417",
                               "the floor slid up to 12.5 mm on its column tops (", "feet");
  // summary.json gives the top slip next to the base slip.
  std::ifstream in(dir.path() / "out/summary.json");
  std::stringstream summary;
  summary << in.rdbuf();
  EXPECT_NE(summary.str().find("\"peak_top_slip_m\":0.0125"), std::string::npos) << summary.str();
}

// The mirror of the top-slip storey: column tops rigid, column feet soft
// in shear (square_storey_case). Floor and columns slide on the feet as
// one: m = 1.0 kg of floor + 4 columns of 0.3 x 0.02 x 0.02 m at
// 450 kg/m^3 (0.054 kg each) = 1.216 kg on K = 160 N/m, the same
// oscillator as there, so under a ramp of two of its periods the feet
// slide u_f = m a_f / K = 1.216 x 2 / 160 = 15.2 mm, without overshoot.
// The base slip (the column bottom points off the foundation) is u_f, the
// floor drift u_f / h = 0.0507 rad (damaged by it), the top slip nothing,
// and the columns, held square by the rigid floor, barely tilt
// (standing). The warning says the columns' feet slid on the foundation,
// and not that the joints broke: they hold (the probe's p4_base_slip read
// "as where their joints break").
TEST(StoreyDrift, ColumnFeetSlidingOnTheFoundationAreItsBaseSlip) {
  TempDir dir;
  const double m = 4.0 * 0.5 * 0.02 * 0.02 * 1250.0 + 4.0 * 0.3 * 0.02 * 0.02 * 450.0;
  ASSERT_NEAR(m * 2.0 / 160.0, 0.0152, 1e-15);
  expect_sliding_square_storey(dir, "rigid", "soft", m, &StoreyDriftRecord::peak_base_slip_m,
                               &StoreyDriftRecord::peak_top_slip_m, "0.0507",
                               "the columns' feet slid up to 15.2 mm on the foundation (", "column tops");
}

}  // namespace
}  // namespace fq
