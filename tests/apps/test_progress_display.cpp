// The progress display of `run` (apps/progress_display.h): on a terminal a
// line redrawn in place ('\r', a final newline at the end); into a file or
// pipe, whole lines at the log interval and no redraws, so that a batch
// job's log shows a long run advancing (it showed nothing; CLI probe).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "dem_core/simulation.h"
#include "progress_display.h"

namespace fq {
namespace {

std::unique_ptr<Simulation> one_box(double duration_s) {
  BodyStore store;
  BoxBodyDef d;
  d.name = "box";
  d.size_m = Vec3(0.1, 0.1, 0.1);
  store.add_box(d);
  SimulationSettings settings;
  settings.dt_s = 1e-3;
  settings.duration_s = duration_s;
  return std::make_unique<Simulation>(std::move(store), settings, GroundMotion{});
}

std::string run_with(bool in_place, double log_interval_s) {
  std::FILE* f = std::tmpfile();
  auto sim = one_box(0.2);
  ProgressDisplay progress("box", f, in_place, log_interval_s);
  sim->add_step_monitor(&progress);  // asked after every step, as run_case asks it
  sim->run();
  std::fflush(f);
  std::rewind(f);
  std::string text;
  for (int c = std::fgetc(f); c != EOF; c = std::fgetc(f)) text.push_back(char(c));
  std::fclose(f);
  return text;
}

TEST(ProgressDisplay, LogLinesIntoAFileAndRedrawsOnATerminal) {
  const std::string log = run_with(false, 0.0);  // every sample, as lines
  EXPECT_EQ(log.find('\r'), std::string::npos) << log;
  std::size_t lines = 0;
  for (const char c : log) lines += c == '\n';
  EXPECT_GE(lines, 10u) << log;  // 200 steps, the clock read at every 8th (progress_display.cpp)
  EXPECT_EQ(log.rfind("box  t = ", 0), 0u) << log;
  EXPECT_EQ(run_with(false, 1e9), "");  // nothing before the interval, no closing redraw

  const std::string terminal = run_with(true, 0.0);
  EXPECT_NE(terminal.find('\r'), std::string::npos);
  EXPECT_EQ(terminal.back(), '\n');  // the final line ends the redraws
}

}  // namespace
}  // namespace fq
