#include "progress_display.h"

#include <algorithm>
#include <cmath>

namespace fq {

namespace {
std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}
}  // namespace

ProgressDisplay::ProgressDisplay(std::string label, std::FILE* stream, bool in_place, double log_interval_s)
    : label_(std::move(label)), stream_(stream), in_place_(in_place), log_interval_s_(log_interval_s) {}

void ProgressDisplay::on_start(const Simulation& sim) {
  start_ = std::chrono::steady_clock::now();
  last_draw_ = start_;
  start_step_ = sim.steps_done();
}

void ProgressDisplay::on_sample(const Simulation& sim) {
  // Asked after every step: the clock is read every kClockEvery calls only,
  // a negligible cost even at a few microseconds a step.
  if (++calls_ % kClockEvery != 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_draw_).count() < (in_place_ ? 0.25 : log_interval_s_)) return;
  last_draw_ = now;
  draw(sim, false);
}

void ProgressDisplay::on_finish(const Simulation& sim) {
  if (in_place_) draw(sim, true);  // a log gets the run's own closing line instead
}

void ProgressDisplay::draw(const Simulation& sim, bool final_line) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::int64_t total = std::max<std::int64_t>(1, sim.total_steps());
  const std::int64_t done = sim.steps_done();
  const double rate = elapsed > 0 ? double(done - start_step_) / elapsed : 0.0;
  const double left = rate > 0 ? double(total - done) / rate : -1.0;
  std::fprintf(stream_, in_place_ ? "\r%s  t = %.4f / %.4f s  %5.1f%%  %.3g steps/s  %s left   "
                                  : "%s  t = %.4f / %.4f s  %5.1f%%  %.3g steps/s  %s left\n",
               label_.c_str(), sim.time_s(), sim.settings().duration_s, 100.0 * double(done) / double(total), rate,
               final_line ? "0:00" : format_duration(left).c_str());
  if (final_line && in_place_) std::fputc('\n', stream_);
  std::fflush(stream_);
}

}  // namespace fq
