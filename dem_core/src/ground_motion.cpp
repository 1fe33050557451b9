#include "dem_core/ground_motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fq {

double AccelerationRecord::at(double t_s) const {
  const std::size_t n = acceleration_mps2.size();
  if (n == 0 || !(t_s >= 0.0)) return 0.0;
  if (!sample_time_s.empty()) {
    // Non-uniform: the segment [k, k + 1] holding t_s by bisection.
    const double end_s = sample_time_s.back();
    if (t_s >= end_s) return t_s <= end_s + 1e-9 * dt_s ? acceleration_mps2[n - 1] : 0.0;
    const std::size_t k =
        std::size_t(std::upper_bound(sample_time_s.begin(), sample_time_s.end(), t_s) - sample_time_s.begin()) - 1;
    const double f = (t_s - sample_time_s[k]) / (sample_time_s[k + 1] - sample_time_s[k]);
    return (1.0 - f) * acceleration_mps2[k] + f * acceleration_mps2[k + 1];
  }
  const double x = t_s / dt_s;
  const double k_floor = std::floor(x);
  if (k_floor >= double(n - 1)) {
    // Exactly on the last sample: its value; beyond it: no motion.
    return (x <= double(n - 1) + 1e-9) ? acceleration_mps2[n - 1] : 0.0;
  }
  const std::size_t k = static_cast<std::size_t>(k_floor);
  const double f = x - k_floor;
  return (1.0 - f) * acceleration_mps2[k] + f * acceleration_mps2[k + 1];
}

double AccelerationRecord::peak_mps2(double* out_time_s) const {
  double peak = 0.0;
  std::size_t at_k = 0;
  for (std::size_t k = 0; k < acceleration_mps2.size(); ++k) {
    if (std::abs(acceleration_mps2[k]) > std::abs(peak)) {
      peak = acceleration_mps2[k];
      at_k = k;
    }
  }
  if (out_time_s) *out_time_s = time_of(at_k);
  return peak;
}

void GroundMotion::add_component(GroundMotionComponent c) {
  const std::string who = c.record.source.empty() ? std::string("ground motion record") : c.record.source;
  if (c.record.acceleration_mps2.size() < 2)
    throw std::invalid_argument(who + ": a record needs at least 2 samples");
  if (!(c.record.dt_s > 0.0) || !std::isfinite(c.record.dt_s))
    throw std::invalid_argument(who + ": sampling interval DT must be a positive number of seconds");
  if (!c.record.sample_time_s.empty()) {
    const std::vector<double>& t = c.record.sample_time_s;
    if (t.size() != c.record.acceleration_mps2.size() || t.front() != 0.0)
      throw std::invalid_argument(who + ": sample times must start at 0 s, one per sample");
    for (std::size_t k = 1; k < t.size(); ++k)
      if (!(t[k] > t[k - 1]) || !std::isfinite(t[k]))
        throw std::invalid_argument(who + ": sample times must increase strictly");
  }
  if (!(c.direction.norm() > 0.0) || !c.direction.allFinite())
    throw std::invalid_argument(who + ": direction must be a non-zero vector");
  if (!(c.time_scale > 0.0) || !std::isfinite(c.time_scale))
    throw std::invalid_argument(who + ": time_scale must be a positive number");
  if (!std::isfinite(c.amplitude_scale))
    throw std::invalid_argument(who + ": amplitude_scale must be a finite number");
  if (!(c.window_start_s >= 0.0))
    throw std::invalid_argument(who + ": window start must be >= 0 s");
  if (!(c.window_length_s > 0.0))
    throw std::invalid_argument(who + ": window length must be > 0 s");
  c.direction.normalize();
  components_.push_back(std::move(c));
}

Vec3 GroundMotion::acceleration(double t_s) const {
  Vec3 a = Vec3::Zero();
  for (const GroundMotionComponent& c : components_) {
    const double t_window = t_s / c.time_scale;
    // The window's last instant counts. The step loop reaches it as n dt,
    // and (n dt) / time_scale lands an ulp past the length (0.3162 and 20 s:
    // 20.000000000000004 s), which dropped the last step's motion; the
    // record's own end has the same tolerance (AccelerationRecord::at).
    if (t_window < 0.0 || t_window > c.window_length_s + 1e-9 * c.record.dt_s) continue;
    a += (c.amplitude_scale * c.record.at(c.window_start_s + t_window)) * c.direction;
  }
  return a;
}

double GroundMotion::end_time_s() const {
  double end = 0.0;
  for (const GroundMotionComponent& c : components_) {
    const double length = std::min(c.window_length_s, c.record.duration_s() - c.window_start_s);
    end = std::max(end, std::max(0.0, length) * c.time_scale);
  }
  return end;
}

template <class Visit>
void GroundMotion::for_each_sample_(double until_s, Visit&& visit) const {
  // Components may share a world axis (oblique directions), so peaks are
  // those of the summed a_g(t), evaluated at every component's sample times
  // and at the ends of the span (a window may start or a run end between
  // two samples).
  visit(acceleration(0.0));
  if (std::isfinite(until_s)) visit(acceleration(until_s));
  for (const GroundMotionComponent& c : components_) {
    const std::size_t n = c.record.acceleration_mps2.size();
    for (std::size_t k = 0; k < n; ++k) {
      const double t_rec = c.record.time_of(k);
      if (t_rec < c.window_start_s || t_rec > c.window_start_s + c.window_length_s) continue;
      const double t_s = (t_rec - c.window_start_s) * c.time_scale;
      if (t_s > until_s) break;  // sample times increase
      visit(acceleration(t_s));
    }
  }
}

Vec3 GroundMotion::peak_abs_mps2(double until_s) const {
  Vec3 peak = Vec3::Zero();
  for_each_sample_(until_s, [&](const Vec3& a) { peak = peak.cwiseMax(a.cwiseAbs()); });
  return peak;
}

double GroundMotion::peak_horizontal_mps2(double until_s) const {
  double peak = 0.0;
  for_each_sample_(until_s, [&](const Vec3& a) { peak = std::max(peak, std::hypot(a.x(), a.y())); });
  return peak;
}

}  // namespace fq
