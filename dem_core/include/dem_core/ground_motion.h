// Ground-motion time function a_g(t) (m/s^2, world frame) in the relative
// frame of DESIGN.md: the ground is fixed and every free body feels the
// inertia force -m a_g(t). No integration of the record to displacement is
// needed.
//
// A ground motion is a sum of components, each a uniformly sampled record
// acting along one world direction, with
//   a_g(t) += amplitude_scale * a_rec(window_start_s + t / time_scale) * direction
// for 0 <= t / time_scale <= window_length_s, and zero outside the window or
// beyond the record. time_scale < 1 compresses the record in time, as
// similitude asks of a reduced-scale model (t_model = sqrt(lambda) t_proto).
// Between samples the record is interpolated linearly.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "dem_core/types.h"

namespace fq {

// A recorded accelerogram: sample k at record time k * dt_s.
struct AccelerationRecord {
  std::string source;       // file it came from (for messages and the summary)
  std::string description;  // header text (event, station, component)
  double dt_s = 0.0;        // sampling interval (s); of a non-uniform record, its smallest interval
  std::vector<double> acceleration_mps2;  // (m/s^2)
  // Empty for a uniform record (sample k at k dt_s). Otherwise the time of
  // each sample (s): from 0, strictly increasing, one per acceleration (a
  // digitised record whose samples are where the trace bends; resampling
  // it onto a grid would cut the peaks that fall between grid points).
  std::vector<double> sample_time_s;
  // Time of the first sample in the file (s): record time 0 is that sample,
  // so window_start_s counts from it (a two-column file whose times start
  // at 5 s is shifted by -5 s; io/accelerogram.h). 0 for the other formats.
  double file_start_time_s = 0.0;
  double time_of(std::size_t k) const { return sample_time_s.empty() ? double(k) * dt_s : sample_time_s[k]; }
  double duration_s() const { return acceleration_mps2.empty() ? 0.0 : time_of(acceleration_mps2.size() - 1); }
  // Value at record time t_s (linear interpolation between samples); 0
  // outside [0, duration].
  double at(double t_s) const;
  // Signed sample of largest magnitude (m/s^2) and its time (s).
  double peak_mps2(double* out_time_s = nullptr) const;
};

struct GroundMotionComponent {
  AccelerationRecord record;
  Vec3 direction = Vec3::UnitX();  // unit vector, world frame
  double amplitude_scale = 1.0;    // (-)
  double time_scale = 1.0;         // simulation seconds per record second (-)
  double window_start_s = 0.0;     // record time at simulation t = 0 (s)
  double window_length_s = std::numeric_limits<double>::infinity();  // record seconds (s)
};

class GroundMotion {
 public:
  GroundMotion() = default;
  // Throws std::invalid_argument with a message naming the problem when a
  // component is unusable (no samples, dt <= 0, zero direction, scale <= 0).
  void add_component(GroundMotionComponent component);
  bool empty() const { return components_.empty(); }
  const std::vector<GroundMotionComponent>& components() const { return components_; }

  // Ground acceleration at simulation time t_s (m/s^2, world frame).
  Vec3 acceleration(double t_s) const;
  // Simulation time (s) at which the last component's window ends.
  double end_time_s() const;
  // Peak magnitude of each world component of the summed a_g(t) over the
  // windows up to simulation time until_s (m/s^2): a run of duration_s
  // feels the motion only up to its end (a window longer than the run used
  // to report a peak the run never felt). a_g is linear between a record's
  // samples, so its peaks lie at every record's own sample times within
  // [0, until_s] or at the two ends of that span, where it is evaluated too.
  Vec3 peak_abs_mps2(double until_s = std::numeric_limits<double>::infinity()) const;
  // Peak of the horizontal ground acceleration's magnitude |(a_x, a_y)|
  // over the same span (m/s^2), sampled as peak_abs_mps2: the horizontal PGA
  // whatever the record's direction (RotD100), unchanged when the scene and
  // its ground motion are turned about the vertical together.
  double peak_horizontal_mps2(double until_s = std::numeric_limits<double>::infinity()) const;

 private:
  template <class Visit>
  void for_each_sample_(double until_s, Visit&& visit) const;
  std::vector<GroundMotionComponent> components_;
};

}  // namespace fq
