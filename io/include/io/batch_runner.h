// Runs several independent cases at once (the comparison and sweep
// commands): each run is single-threaded and up to `parallel_runs` of them
// run side by side, one per core, which is how a handful of 16-body frames
// uses a multi-core machine best (a frame is too small to share among
// threads). Runs are deterministic and independent, so the results do not
// depend on the order in which they finish.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "io/case_def.h"
#include "io/case_runner.h"

namespace fq {

struct BatchJob {
  CaseDef def;                          // as loaded (and possibly adjusted: scale, window, record)
  std::filesystem::path output_folder;  // where this run writes
  std::string label;                    // for progress lines and tables
};

struct BatchOutcome {
  bool ok = false;          // the run finished (completed, stopped or unstable) and its output was written
  std::string error;        // why not, when !ok (bad input or output failure)
  int exit_code = 0;        // as `framequake run` would exit: 0, 1 unstable, 2 input, 3 output, 130 stopped
  CaseRunReport report;     // valid when ok
};

struct BatchOptions {
  int parallel_runs = 0;    // 0: one per hardware thread
  bool allow_unstable_time_step = false;
  const std::atomic<bool>* stop_requested = nullptr;
  // Called (from the worker thread, serialised by a mutex) when a job ends.
  std::function<void(std::size_t job, const BatchJob&, const BatchOutcome&, std::size_t done, std::size_t total)>
      on_done;
  // While runs go, every `progress_interval_s` of wall time (0: never):
  // one line naming the runs in progress with their percent of simulated
  // time, and how many are done ("frame_A 45 %, frame_B 40 %; 1 of 3
  // done"). Called from a thread of its own, never after run_batch returns.
  double progress_interval_s = 0.0;
  std::function<void(const std::string& line)> on_progress;
};

// Runs every job; outcomes in job order. Never throws for a job's own
// failure (it is reported in its outcome).
std::vector<BatchOutcome> run_batch(const std::vector<BatchJob>& jobs, const BatchOptions& options);

}  // namespace fq
