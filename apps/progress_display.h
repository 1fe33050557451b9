// Terminal progress for long runs: simulated time, percent, steps per second
// and time left, redrawn in place on stderr at most a few times a second.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include "dem_core/simulation.h"

namespace fq {

class ProgressDisplay : public StepObserver {
 public:
  // `label` prefixes the line (the case name); output goes to `stream`.
  ProgressDisplay(std::string label, std::FILE* stream);
  void on_start(const Simulation& sim) override;
  void on_sample(const Simulation& sim) override;
  void on_finish(const Simulation& sim) override;

 private:
  void draw(const Simulation& sim, bool final_line);
  std::string label_;
  std::FILE* stream_;
  std::chrono::steady_clock::time_point start_{};
  std::chrono::steady_clock::time_point last_draw_{};
  std::int64_t start_step_ = 0;
};

}  // namespace fq
