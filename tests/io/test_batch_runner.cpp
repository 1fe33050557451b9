// run_batch's progress lines (io/batch_runner.h): while runs go, a line at
// every interval naming each running case with its percent of simulated
// time and the count done; none after the batch ends. A study of long runs
// said nothing until its first run ended (CLI probe: 13.8 s of silence).
#include <gtest/gtest.h>

#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "io/batch_runner.h"
#include "io/case_file.h"
#include "io_test_util.h"

namespace fq {
namespace {

namespace fs = std::filesystem;

TEST(BatchRunner, ProgressLinesNameTheRunningCasesWhileTheyGo) {
  test::TempDir dir;
  // The falling-block demo run for 0.5 s of simulated time: about 0.05 s
  // of wall time in the plain build (three under the sanitizers), so a
  // 0.005 s interval gives several lines. (At 10 s it took 52 s of the
  // sanitizer stage of CI, at 2 s 12 s.)
  CaseDef def = load_case_file(fs::path(FQ_SOURCE_DIR) / "cases" / "demo_falling_block.yaml");
  def.time.duration_s = 0.5;
  def.output.frame_interval_s = 1.0;
  BatchJob job;
  job.def = def;
  job.output_folder = dir.path() / "block";
  job.label = "block";
  BatchOptions options;
  options.parallel_runs = 1;
  options.progress_interval_s = 0.005;
  std::mutex mutex;
  std::vector<std::string> lines;
  options.on_progress = [&](const std::string& line) {
    std::lock_guard<std::mutex> lock(mutex);
    lines.push_back(line);
  };
  const std::vector<BatchOutcome> out = run_batch({job}, options);
  const std::size_t after_return = lines.size();
  ASSERT_EQ(out.size(), 1u);
  ASSERT_TRUE(out[0].ok) << out[0].error;
  ASSERT_GE(lines.size(), 2u) << "the run took " << out[0].report.wall_s << " s";
  int previous = -1;
  for (const std::string& line : lines) {
    SCOPED_TRACE(line);
    ASSERT_EQ(line.rfind("block ", 0), 0u);
    EXPECT_NE(line.find(" %; 0 of 1 done"), std::string::npos);
    const int percent = std::stoi(line.substr(6));
    EXPECT_GE(percent, previous);  // simulated time only goes forward
    EXPECT_LE(percent, 100);
    previous = percent;
  }
  EXPECT_EQ(lines.size(), after_return);  // nothing after run_batch returned
}

}  // namespace
}  // namespace fq
