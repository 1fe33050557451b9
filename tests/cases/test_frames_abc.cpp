// Regression of seed 001's frames A, B and C (cases/frame_*.yaml) under the
// JMA Kobe NS record. Expected behaviour is the seed's report (seed 001,
// "Modeling and Results"): frame A's first-storey joints fail and the frame
// collapses completely; frame B is damaged in its first storey while its
// second storey stays together; frame C, braced, withstands the motion with
// its first-storey drift reduced by the braces. cases/README.md states
// which parts of that picture this model reproduces at amplitude 1 (B's
// first storey is damaged but does not fall at amplitude 1; it falls from
// the amplitude the sweep reports).
//
// Only the window is shortened (record seconds 5-13, which hold the peak at
// 8.52 s and the whole failure sequence of the full run); the case files,
// and so the physics, are used as shipped.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "io/batch_runner.h"
#include "io/case_file.h"
#include "io_test_util.h"

namespace fq {
namespace {

namespace fs = std::filesystem;

constexpr double kWindowStart_s = 5.0;   // record seconds
constexpr double kWindowLength_s = 8.0;  // record seconds

void expect_sound_run(const CaseRunReport& r) {
  EXPECT_EQ(r.result.status, RunStatus::Completed) << r.result.message;
  ASSERT_EQ(r.storeys.size(), 2u);
  // Energy conservation of the whole run, collapse and impacts included:
  // the ledger balances to 0.1 % of the largest energy of the run.
  EXPECT_LT(r.energy_balance_error_relative, 1e-3);
}

// One test for the three runs: they run side by side, as `framequake
// compare` runs them, once (ctest runs every TEST of a program as its own
// process, so separate TESTs would repeat the runs).
TEST(FramesABC, SeedOutcomesUnderKobe) {
  test::TempDir dir;
  std::vector<BatchJob> jobs;
  for (const char* name : {"frame_A", "frame_B", "frame_C"}) {
    BatchJob job;
    job.def = load_case_file(fs::path(FQ_SOURCE_DIR) / "cases" / (std::string(name) + ".yaml"));
    job.def.ground_motion->window_start_s = kWindowStart_s;
    job.def.ground_motion->window_length_s = kWindowLength_s;
    job.output_folder = dir.path() / name;
    job.label = name;
    jobs.push_back(std::move(job));
  }
  const std::vector<BatchOutcome> out = run_batch(jobs, {});
  for (const BatchOutcome& o : out) ASSERT_TRUE(o.ok) << o.error;
  const CaseRunReport& a = out[0].report;
  const CaseRunReport& b = out[1].report;
  const CaseRunReport& c = out[2].report;
  {
    SCOPED_TRACE("frame A: its joints fail and the whole frame collapses");
    expect_sound_run(a);
    EXPECT_EQ(a.storeys[0].verdict, StoreyVerdict::Collapsed);
    EXPECT_EQ(a.storeys[1].verdict, StoreyVerdict::Collapsed);
    EXPECT_TRUE(std::isfinite(a.first_joint_failure_time_s));
    // It leans: the first storey collapses first, the second follows.
    EXPECT_GE(a.storeys[0].drift.collapse_time_s, 0.0);
    EXPECT_GE(a.storeys[1].drift.collapse_time_s, a.storeys[0].drift.collapse_time_s);
    EXPECT_GE(a.joints.broken, a.joint_count / 2);
  }
  {
    SCOPED_TRACE("frame B: the first storey is the damaged one, the second stays together");
    expect_sound_run(b);
    EXPECT_NE(b.storeys[0].verdict, StoreyVerdict::Standing);
    EXPECT_NE(b.storeys[1].verdict, StoreyVerdict::Collapsed);
    EXPECT_GT(b.storeys[0].drift.peak_ratio_rad, b.storeys[1].drift.peak_ratio_rad);
    EXPECT_TRUE(std::isfinite(b.first_joint_failure_time_s));
  }
  {
    SCOPED_TRACE("frame C withstands the motion");
    expect_sound_run(c);
    EXPECT_EQ(c.storeys[0].verdict, StoreyVerdict::Standing);
    EXPECT_NE(c.storeys[1].verdict, StoreyVerdict::Collapsed);
    EXPECT_EQ(c.joints.broken, 0u);
  }
  {
    SCOPED_TRACE("the braces reduce first-storey drift: A and B far above C");
    const double pa = a.storeys[0].drift.peak_ratio_rad;
    const double pb = b.storeys[0].drift.peak_ratio_rad;
    const double pc = c.storeys[0].drift.peak_ratio_rad;
    EXPECT_GT(pa, 3.0 * pc);
    EXPECT_GT(pb, 3.0 * pc);
    EXPECT_GE(pa, pb);
  }
}

}  // namespace
}  // namespace fq
