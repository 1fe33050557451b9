#include "io/batch_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

#include "io/input_error.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace fq {

namespace {
// A run's share of its simulated time, for the batch's progress lines
// (asked after every step, as the terminal display of `run` is: a relaxed
// store is all it costs).
class FractionObserver : public StepObserver {
 public:
  explicit FractionObserver(std::atomic<double>* fraction) : fraction_(fraction) {}
  void on_sample(const Simulation& sim) override {
    const double total = double(std::max<std::int64_t>(1, sim.total_steps()));
    fraction_->store(double(sim.steps_done()) / total, std::memory_order_relaxed);
  }

 private:
  std::atomic<double>* fraction_;
};
}  // namespace

std::vector<BatchOutcome> run_batch(const std::vector<BatchJob>& jobs, const BatchOptions& options) {
  std::vector<BatchOutcome> outcomes(jobs.size());
  if (jobs.empty()) return outcomes;
  int workers = options.parallel_runs > 0 ? options.parallel_runs : int(std::thread::hardware_concurrency());
  workers = std::clamp(workers, 1, int(jobs.size()));

  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex report_mutex;
  // Per job: -1 not started, else its fraction of simulated time; 2 ended.
  std::unique_ptr<std::atomic<double>[]> fraction(new std::atomic<double>[jobs.size()]);
  for (std::size_t i = 0; i < jobs.size(); ++i) fraction[i].store(-1.0);
  auto worker = [&]() {
#if defined(_OPENMP)
    omp_set_num_threads(1);  // one core per run; the runs themselves are the parallelism
#endif
    for (std::size_t i = next++; i < jobs.size(); i = next++) {
      BatchOutcome& out = outcomes[i];
      if (options.stop_requested && options.stop_requested->load()) {
        out.error = "not run: stopped on request (Ctrl-C, SIGTERM or SIGHUP)";
        out.exit_code = 130;
      } else {
        CaseRunOptions run;
        FractionObserver progress(&fraction[i]);
        fraction[i].store(0.0);
        if (options.on_progress) run.progress = &progress;
        run.output_folder = jobs[i].output_folder;
        run.allow_unstable_time_step = options.allow_unstable_time_step;
        run.stop_requested = options.stop_requested;
        try {
          out.report = run_case(jobs[i].def, run);
          out.ok = true;
          switch (out.report.result.status) {
            case RunStatus::Completed: out.exit_code = 0; break;
            case RunStatus::Unstable: out.exit_code = 1; break;
            case RunStatus::Stopped: out.exit_code = 130; break;
          }
        } catch (const InputError& e) {
          out.error = e.what();
          out.exit_code = 2;
        } catch (const OutputError& e) {
          out.error = e.what();
          out.exit_code = 3;
        } catch (const std::exception& e) {
          out.error = std::string("internal error: ") + e.what();
          out.exit_code = 4;
        }
      }
      fraction[i].store(2.0);
      {
        std::lock_guard<std::mutex> lock(report_mutex);
        ++done;
        if (options.on_done) options.on_done(i, jobs[i], out, done, jobs.size());
      }
    }
  };
  // The progress lines, from a thread of their own that the end wakes.
  std::mutex progress_mutex;
  std::condition_variable progress_wake;
  bool finished = false;
  std::thread reporter;
  if (options.on_progress && options.progress_interval_s > 0.0 && std::isfinite(options.progress_interval_s)) {
    reporter = std::thread([&]() {
      const auto interval = std::chrono::duration<double>(options.progress_interval_s);
      std::unique_lock<std::mutex> lock(progress_mutex);
      while (!progress_wake.wait_for(lock, interval, [&] { return finished; })) {
        std::ostringstream line;
        std::size_t running = 0, ended = 0;
        for (std::size_t i = 0; i < jobs.size(); ++i) {
          const double f = fraction[i].load();
          if (f > 1.5) {
            ++ended;
          } else if (f >= 0.0) {
            line << (running++ ? ", " : "") << jobs[i].label << " " << int(std::floor(100.0 * f)) << " %";
          }
        }
        if (running == 0) continue;
        line << "; " << ended << " of " << jobs.size() << " done";
        options.on_progress(line.str());
      }
    });
  }
  std::vector<std::thread> threads;
  for (int w = 1; w < workers; ++w) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  if (reporter.joinable()) {
    {
      std::lock_guard<std::mutex> lock(progress_mutex);
      finished = true;
    }
    progress_wake.notify_all();
    reporter.join();
  }
  return outcomes;
}

}  // namespace fq
