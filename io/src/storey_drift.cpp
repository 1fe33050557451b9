#include "io/storey_drift.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace fq {

const char* storey_verdict_name(StoreyVerdict v) {
  switch (v) {
    case StoreyVerdict::Standing: return "standing";
    case StoreyVerdict::Damaged: return "damaged";
    case StoreyVerdict::Collapsed: return "collapsed";
  }
  return "unknown";
}

std::vector<Storey> find_storeys(const Model& model) {
  const CaseDef& def = model.def;
  struct ColumnSpan {
    std::size_t member;
    Vec3 low_m, high_m;  // node positions, low end first
  };
  std::vector<ColumnSpan> columns;
  std::vector<double> levels;
  for (std::size_t i = 0; i < def.members.size(); ++i) {
    const MemberDef& m = def.members[i];
    if (m.kind != MemberKind::Column) continue;
    Vec3 a = def.nodes[std::size_t(def.node_index(m.node_a))].xyz_m;
    Vec3 b = def.nodes[std::size_t(def.node_index(m.node_b))].xyz_m;
    if (std::abs(a.z() - b.z()) < kStoreyLevelTolerance_m) continue;  // a horizontal "column" spans no storey
    if (a.z() > b.z()) std::swap(a, b);
    columns.push_back({i, a, b});
    levels.push_back(b.z());
  }
  // Levels are the column tops and the lowest column foot. A foot higher
  // up (a column on a hillside step, a post standing on a beam) is no
  // level of its own: it made a storey between the two feet, of the longer
  // column alone.
  if (!columns.empty())
    levels.push_back(std::min_element(columns.begin(), columns.end(), [](const ColumnSpan& p, const ColumnSpan& q) {
                       return p.low_m.z() < q.low_m.z();
                     })->low_m.z());
  std::sort(levels.begin(), levels.end());
  std::vector<double> merged;
  for (double z : levels)
    if (merged.empty() || z - merged.back() > kStoreyLevelTolerance_m) merged.push_back(z);

  std::vector<Storey> storeys;
  for (std::size_t k = 1; k < merged.size(); ++k) {
    Storey s;
    s.number = int(k);
    s.bottom_z_m = merged[k - 1];
    s.top_z_m = merged[k];
    for (const ColumnSpan& c : columns) {
      // A column of the band reaches its top level and starts at or below
      // it; one whose foot lies inside the band counts from its foot.
      if (c.low_m.z() > s.top_z_m - kStoreyLevelTolerance_m || c.high_m.z() < s.top_z_m - kStoreyLevelTolerance_m) continue;
      const double foot_z = c.low_m.z() > s.bottom_z_m + kStoreyLevelTolerance_m ? c.low_m.z() : s.bottom_z_m;
      const BodyId body = model.member_body[c.member];
      auto point_at = [&](double z) {  // on the column axis at height z
        const double f = (z - c.low_m.z()) / (c.high_m.z() - c.low_m.z());
        return Vec3(c.low_m + f * (c.high_m - c.low_m));
      };
      StoreyColumn sc;
      sc.body = body;
      sc.bottom_start_m = point_at(foot_z);
      sc.top_start_m = point_at(s.top_z_m);
      const Mat3& r = model.bodies.rotation[body];
      const Vec3& x = model.bodies.position_m[body];
      sc.bottom_local_m = r.transpose() * (sc.bottom_start_m - x);
      sc.top_local_m = r.transpose() * (sc.top_start_m - x);
      s.columns.push_back(sc);
      s.column_names.push_back(def.members[c.member].id);
    }
    if (!s.columns.empty()) storeys.push_back(std::move(s));
  }
  for (std::size_t k = 0; k < storeys.size(); ++k) storeys[k].number = int(k) + 1;
  return storeys;
}

Eigen::Vector2d storey_drift_m(const Storey& storey, const BodyStore& bodies, std::vector<Eigen::Vector2d>* per_column) {
  Vec3 sum = Vec3::Zero();
  if (per_column) per_column->clear();
  for (const StoreyColumn& c : storey.columns) {
    const Vec3 top = bodies.to_world(c.body, c.top_local_m) - c.top_start_m;
    const Vec3 bottom = bodies.to_world(c.body, c.bottom_local_m) - c.bottom_start_m;
    const Vec3 drift = top - bottom;
    if (per_column) per_column->emplace_back(drift.x(), drift.y());
    sum += drift;
  }
  sum /= double(storey.columns.size());
  return {sum.x(), sum.y()};
}

StoreyDriftMonitor::StoreyDriftMonitor(std::vector<Storey> storeys, AssessmentDef limits, double dt_s)
    : storeys_(std::move(storeys)),
      limits_(limits),
      records_(storeys_.size()),
      drift_m_(storeys_.size(), Eigen::Vector2d::Zero()),
      residual_(storeys_.size()),
      dt_s_(dt_s) {
  if (!(dt_s > 0.0)) throw std::invalid_argument("StoreyDriftMonitor: the time step must be positive");
  const double window_steps = std::max(1.0, std::round(kResidualDriftWindow_s / dt_s));
  block_steps_ = std::max<std::int64_t>(1, std::int64_t(window_steps / 1000.0));
  window_blocks_ = std::size_t(std::ceil(window_steps / double(block_steps_)));
}

void StoreyDriftMonitor::sample(const BodyStore& bodies, std::int64_t step, double time_s) {
  if (step == last_step_) return;
  last_step_ = step;
  for (std::size_t i = 0; i < storeys_.size(); ++i) record(i, storey_drift_m(storeys_[i], bodies), time_s);
}

void StoreyDriftMonitor::track(const BodyStore& bodies, double time_s) {
  for (std::size_t i = 0; i < storeys_.size(); ++i) {
    const double height_m = storeys_[i].height_m();
    const Eigen::Vector2d ratio = storey_drift_m(storeys_[i], bodies, &column_drift_m_) / height_m;
    record_peaks(i, ratio, time_s);
    record_residual(i, ratio);
    StoreyDriftRecord& r = records_[i];
    for (std::size_t c = 0; c < column_drift_m_.size(); ++c) {
      const double column_ratio = column_drift_m_[c].norm() / height_m;
      if (column_ratio > r.peak_column_ratio_rad) {
        r.peak_column_ratio_rad = column_ratio;
        r.peak_column = int(c);
      }
    }
  }
}

void StoreyDriftMonitor::save_state(StateWriter& out) const {
  out.section("storeys");
  out.u64(records_.size());
  out.i64(block_steps_);
  for (std::size_t i = 0; i < records_.size(); ++i) {
    const StoreyDriftRecord& r = records_[i];
    for (const double v : {r.peak_ratio_x_rad, r.peak_ratio_y_rad, r.peak_ratio_rad, r.peak_time_s, r.collapse_time_s,
                           r.final_ratio_x_rad, r.final_ratio_y_rad, r.residual_ratio_x_rad, r.residual_ratio_y_rad,
                           r.residual_window_s, r.peak_column_ratio_rad})
      out.f64(v);
    out.i64(r.peak_column);
    out.f64(drift_m_[i].x());
    out.f64(drift_m_[i].y());
    const ResidualBlocks& b = residual_[i];
    out.u64(b.sums.size());
    for (const Eigen::Vector2d& v : b.sums) {
      out.f64(v.x());
      out.f64(v.y());
    }
    out.f64(b.total.x());
    out.f64(b.total.y());
    out.f64(b.open_sum.x());
    out.f64(b.open_sum.y());
    out.i64(b.open_steps);
  }
}

void StoreyDriftMonitor::load_state(StateReader& in) {
  in.section("storeys");
  const std::uint64_t n = in.u64("storey count");
  if (n != records_.size())
    in.fail("the checkpoint has " + std::to_string(n) + " storeys, the case " + std::to_string(records_.size()));
  if (in.i64("residual block") != block_steps_) in.fail("the residual's blocks are of another size");
  for (std::size_t i = 0; i < records_.size(); ++i) {
    StoreyDriftRecord& r = records_[i];
    for (double* v : {&r.peak_ratio_x_rad, &r.peak_ratio_y_rad, &r.peak_ratio_rad, &r.peak_time_s, &r.collapse_time_s,
                      &r.final_ratio_x_rad, &r.final_ratio_y_rad, &r.residual_ratio_x_rad, &r.residual_ratio_y_rad,
                      &r.residual_window_s, &r.peak_column_ratio_rad})
      *v = in.f64("storey record");
    r.peak_column = int(in.i64("peak column"));
    if (r.peak_column < -1 || r.peak_column >= int(storeys_[i].columns.size())) in.fail("peak column out of range");
    drift_m_[i].x() = in.f64("drift x");
    drift_m_[i].y() = in.f64("drift y");
    ResidualBlocks& b = residual_[i];
    const std::uint64_t blocks = in.u64("residual blocks");
    if (blocks > window_blocks_) in.fail("more residual blocks than the window holds");
    b.sums.clear();
    for (std::uint64_t k = 0; k < blocks; ++k) {
      const double x = in.f64("block sum x");
      b.sums.emplace_back(x, in.f64("block sum y"));
    }
    b.total.x() = in.f64("residual total x");
    b.total.y() = in.f64("residual total y");
    b.open_sum.x() = in.f64("open block x");
    b.open_sum.y() = in.f64("open block y");
    b.open_steps = in.i64("open block steps");
    if (b.open_steps < 0 || b.open_steps >= block_steps_) in.fail("the open residual block is out of range");
  }
}

void StoreyDriftMonitor::record_peaks(std::size_t i, const Eigen::Vector2d& ratio, double time_s) {
  StoreyDriftRecord& r = records_[i];
  r.peak_ratio_x_rad = std::max(r.peak_ratio_x_rad, std::abs(ratio.x()));
  r.peak_ratio_y_rad = std::max(r.peak_ratio_y_rad, std::abs(ratio.y()));
  const double magnitude = ratio.norm();
  if (magnitude > r.peak_ratio_rad) {
    r.peak_ratio_rad = magnitude;
    r.peak_time_s = time_s;
  }
  if (r.collapse_time_s < 0.0 && magnitude >= limits_.collapse_drift_ratio_rad) r.collapse_time_s = time_s;
}

void StoreyDriftMonitor::record_residual(std::size_t i, const Eigen::Vector2d& ratio) {
  // A running total of the complete blocks (one add and one subtract per
  // block): its round-off stays below 1e-16 of the largest block sum times
  // the blocks of a run, far below any drift worth reading.
  ResidualBlocks& b = residual_[i];
  b.open_sum += ratio;
  if (++b.open_steps == block_steps_) {
    b.sums.push_back(b.open_sum);
    b.total += b.open_sum;
    b.open_sum.setZero();
    b.open_steps = 0;
    if (b.sums.size() > window_blocks_) {
      b.total -= b.sums.front();
      b.sums.pop_front();
    }
  }
  const std::int64_t steps = std::int64_t(b.sums.size()) * block_steps_ + b.open_steps;
  StoreyDriftRecord& r = records_[i];
  r.residual_ratio_x_rad = (b.total.x() + b.open_sum.x()) / double(steps);
  r.residual_ratio_y_rad = (b.total.y() + b.open_sum.y()) / double(steps);
  r.residual_window_s = double(steps - 1) * dt_s_;
}

void StoreyDriftMonitor::record(std::size_t i, const Eigen::Vector2d& drift_m, double time_s) {
  drift_m_[i] = drift_m;
  const Eigen::Vector2d ratio = drift_ratio_rad(i);
  record_peaks(i, ratio, time_s);
  StoreyDriftRecord& r = records_[i];
  r.final_ratio_x_rad = ratio.x();
  r.final_ratio_y_rad = ratio.y();
}

StoreyVerdict verdict_for_peak(double peak, const AssessmentDef& limits) {
  if (peak >= limits.collapse_drift_ratio_rad) return StoreyVerdict::Collapsed;
  if (peak > limits.safety_drift_ratio_rad) return StoreyVerdict::Damaged;
  return StoreyVerdict::Standing;
}

StoreyVerdict StoreyDriftMonitor::verdict(std::size_t i) const {
  return verdict_for_peak(records_[i].peak_ratio_rad, limits_);
}

std::string StoreyDriftMonitor::twist_warning(std::size_t i) const {
  const StoreyDriftRecord& r = records_[i];
  const StoreyVerdict storey = verdict(i), column = verdict_for_peak(r.peak_column_ratio_rad, limits_);
  if (r.peak_column < 0 || int(column) <= int(storey)) return "";
  const Storey& s = storeys_[i];
  std::ostringstream w;
  w << std::setprecision(3) << "storey " << s.number << " twists: its drift, the mean of its " << s.columns.size()
    << " columns, peaked at " << r.peak_ratio_rad << " rad (" << storey_verdict_name(storey) << "), but column '"
    << s.column_names[std::size_t(r.peak_column)] << "' alone drifted " << r.peak_column_ratio_rad << " rad, which would "
    << "make it " << storey_verdict_name(column) << "; the verdict uses the mean (cases/README.md, assessment)";
  return w.str();
}

}  // namespace fq
