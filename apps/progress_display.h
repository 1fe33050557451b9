// Progress for long runs: simulated time, percent, steps per second and time
// left. On a terminal redrawn in place at most a few times a second; into a
// file or pipe (a batch job's log) one whole line every kLogInterval_s, so
// that a log shows a long run advancing (it showed nothing until the end;
// CLI probe).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include "dem_core/simulation.h"

namespace fq {

class ProgressDisplay : public StepObserver {
 public:
  static constexpr double kLogInterval_s = 30.0;
  // `label` prefixes the line (the case name); output goes to `stream`,
  // redrawn in place when `in_place` (a terminal), else as log lines at
  // most every `log_interval_s`.
  ProgressDisplay(std::string label, std::FILE* stream, bool in_place = true, double log_interval_s = kLogInterval_s);
  void on_start(const Simulation& sim) override;
  void on_sample(const Simulation& sim) override;
  void on_finish(const Simulation& sim) override;

 private:
  void draw(const Simulation& sim, bool final_line);
  std::string label_;
  std::FILE* stream_;
  bool in_place_ = true;
  double log_interval_s_ = kLogInterval_s;
  std::chrono::steady_clock::time_point start_{};
  std::chrono::steady_clock::time_point last_draw_{};
  std::int64_t start_step_ = 0;
  static constexpr std::int64_t kClockEvery = 8;
  std::int64_t calls_ = 0;
};

}  // namespace fq
