// A run whose joints end near a whole turn warns of them, even when it goes
// unstable (io/case_runner.h, whole_turn_joints_warning; joints/README.md,
// "Large rotations"). The frame probe of stop 41: a portal with a heavy
// beam (W/h above its out-of-plane sway stiffness) on linear joints that
// never break buckles out of plane and, with no ground contact to stop it,
// swings about its base line like an undamped pendulum released from its
// upright equilibrium, which energy conservation brings back to upright
// after one revolution: the four joints then stand near a whole turn,
// where their half-way frames are undefined, and the run blew up soon
// after. About 460 000 steps, 0.6 s in the plain build; labelled `slow`
// (plain suite only), the warning's own test (test_run_warnings) runs
// under the sanitizers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io_test_util.h"

namespace fq {
namespace {

TEST(WholeTurnRun, AnUnstableRunWhoseJointsTurnedAWholeTurnSaysSo) {
  const test::TempDir dir;
  {
    // 0.2 m/s^2 along x for 0.02 s, then still, to 0.2 s.
    std::ofstream pulse(dir.path() / "pulse.txt");
    for (int k = 0; k <= 2000; ++k) pulse << 1e-4 * k << " " << (k < 200 ? 0.2 : 0.0) << "\n";
  }
  const std::string text =
      "framequake_case: 1\n"
      "time: {dt_s: 2.0e-5, duration_s: 12.0}\n"
      "materials: [{name: wood, density_kg_per_m3: 450.0}, {name: heavy, density_kg_per_m3: 450000.0}]\n"
      "sections: [{name: col, width_m: 0.02, depth_m: 0.01}, {name: bm, width_m: 0.01, depth_m: 0.03}]\n"
      "nodes:\n"
      "  - {id: b_w, xyz_m: [0.0, 0.0, 0.0]}\n"
      "  - {id: t_w, xyz_m: [0.0, 0.0, 0.3]}\n"
      "  - {id: t_e, xyz_m: [0.5, 0.0, 0.3]}\n"
      "  - {id: b_e, xyz_m: [0.5, 0.0, 0.0]}\n"
      "members:\n"
      "  - {id: col_w, kind: column, nodes: [b_w, t_w], section: col, material: wood}\n"
      "  - {id: col_e, kind: column, nodes: [b_e, t_e], section: col, material: wood}\n"
      "  - {id: beam, kind: beam, nodes: [t_w, t_e], section: bm, material: heavy}\n"
      "joint_types:\n"
      "  - name: lin\n"
      "    layout: four_corner\n"
      "    normal: {law: linear, stiffness_N_per_m: 100000.0, damping_ratio: 0.0}\n"
      "    shear: {law: linear, stiffness_N_per_m: 1000000.0, damping_ratio: 0.0}\n"
      "    fracture: {criterion: never}\n"
      "joints: {default_type: lin, support_type: lin}\n"
      "supports: [{node: b_w}, {node: b_e}]\n"
      "ground_motion:\n"
      "  components: [{file: pulse.txt, format: two_column, unit: m/s2, axis: x}]\n"
      "output: {frame_interval_s: 1.0, history_interval_s: 0.01}\n";
  const CaseDef def = load_case_file(dir.write("portal.yaml", text));
  CaseRunOptions options;
  options.output_folder = dir.path() / "out";
  const CaseRunReport r = run_case(def, options);
  EXPECT_EQ(r.result.status, RunStatus::Unstable) << r.result.message;
  bool warned = false;
  for (const std::string& w : r.warnings)
    warned = warned || w.find("more than three quarters of a whole turn against each other") != std::string::npos;
  EXPECT_TRUE(warned) << testing::PrintToString(r.warnings);
}

}  // namespace
}  // namespace fq
