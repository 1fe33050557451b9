#include "io/batch_runner.h"

#include <algorithm>
#include <mutex>
#include <thread>

#include "io/input_error.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace fq {

std::vector<BatchOutcome> run_batch(const std::vector<BatchJob>& jobs, const BatchOptions& options) {
  std::vector<BatchOutcome> outcomes(jobs.size());
  if (jobs.empty()) return outcomes;
  int workers = options.parallel_runs > 0 ? options.parallel_runs : int(std::thread::hardware_concurrency());
  workers = std::clamp(workers, 1, int(jobs.size()));

  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex report_mutex;
  auto worker = [&]() {
#if defined(_OPENMP)
    omp_set_num_threads(1);  // one core per run; the runs themselves are the parallelism
#endif
    for (std::size_t i = next++; i < jobs.size(); i = next++) {
      BatchOutcome& out = outcomes[i];
      if (options.stop_requested && options.stop_requested->load()) {
        out.error = "not run: stopped on request (Ctrl-C or SIGTERM)";
        out.exit_code = 130;
      } else {
        CaseRunOptions run;
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
      if (options.on_done) {
        std::lock_guard<std::mutex> lock(report_mutex);
        ++done;
        options.on_done(i, jobs[i], out, done, jobs.size());
      }
    }
  };
  std::vector<std::thread> threads;
  for (int w = 1; w < workers; ++w) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  return outcomes;
}

}  // namespace fq
