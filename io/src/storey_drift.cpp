#include "io/storey_drift.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace fq {

namespace {
constexpr double kLevelTolerance_m = kStoreyLevelTolerance_m;
}

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
    if (std::abs(a.z() - b.z()) < kLevelTolerance_m) continue;  // a horizontal "column" spans no storey
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
    if (merged.empty() || z - merged.back() > kLevelTolerance_m) merged.push_back(z);

  std::vector<Storey> storeys;
  for (std::size_t k = 1; k < merged.size(); ++k) {
    Storey s;
    s.number = int(k);
    s.bottom_z_m = merged[k - 1];
    s.top_z_m = merged[k];
    for (const ColumnSpan& c : columns) {
      // A column of the band reaches its top level and starts at or below
      // it; one whose foot lies inside the band counts from its foot.
      if (c.low_m.z() > s.top_z_m - kLevelTolerance_m || c.high_m.z() < s.top_z_m - kLevelTolerance_m) continue;
      const double foot_z = c.low_m.z() > s.bottom_z_m + kLevelTolerance_m ? c.low_m.z() : s.bottom_z_m;
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

Eigen::Vector2d storey_drift_m(const Storey& storey, const BodyStore& bodies) {
  Vec3 sum = Vec3::Zero();
  for (const StoreyColumn& c : storey.columns) {
    const Vec3 top = bodies.to_world(c.body, c.top_local_m) - c.top_start_m;
    const Vec3 bottom = bodies.to_world(c.body, c.bottom_local_m) - c.bottom_start_m;
    sum += top - bottom;
  }
  sum /= double(storey.columns.size());
  return {sum.x(), sum.y()};
}

StoreyDriftMonitor::StoreyDriftMonitor(std::vector<Storey> storeys, AssessmentDef limits)
    : storeys_(std::move(storeys)),
      limits_(limits),
      records_(storeys_.size()),
      drift_m_(storeys_.size(), Eigen::Vector2d::Zero()),
      window_(storeys_.size()),
      window_sum_(storeys_.size(), Eigen::Vector2d::Zero()) {}

void StoreyDriftMonitor::sample(const BodyStore& bodies, std::int64_t step, double time_s) {
  if (step == last_step_) return;
  last_step_ = step;
  for (std::size_t i = 0; i < storeys_.size(); ++i) record(i, storey_drift_m(storeys_[i], bodies), time_s);
}

void StoreyDriftMonitor::track(const BodyStore& bodies, double time_s) {
  for (std::size_t i = 0; i < storeys_.size(); ++i)
    record_peaks(i, storey_drift_m(storeys_[i], bodies) / storeys_[i].height_m(), time_s);
}

void StoreyDriftMonitor::save_peaks(StateWriter& out) const {
  out.section("storeys");
  out.u64(records_.size());
  for (const StoreyDriftRecord& r : records_) {
    out.f64(r.peak_ratio_x_rad);
    out.f64(r.peak_ratio_y_rad);
    out.f64(r.peak_ratio_rad);
    out.f64(r.peak_time_s);
    out.f64(r.collapse_time_s);
  }
}

void StoreyDriftMonitor::load_peaks(StateReader& in) {
  in.section("storeys");
  const std::uint64_t n = in.u64("storey count");
  if (n != records_.size())
    in.fail("the checkpoint has " + std::to_string(n) + " storeys, the case " + std::to_string(records_.size()));
  for (StoreyDriftRecord& r : records_) {
    r.peak_ratio_x_rad = in.f64("peak drift ratio x");
    r.peak_ratio_y_rad = in.f64("peak drift ratio y");
    r.peak_ratio_rad = in.f64("peak drift ratio");
    r.peak_time_s = in.f64("peak time");
    r.collapse_time_s = in.f64("collapse time");
  }
}

void StoreyDriftMonitor::replay_history(const std::filesystem::path& history_csv) {
  std::ifstream in(history_csv, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + history_csv.string());
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::size_t from = 0;
    for (std::size_t comma; (comma = line.find(',', from)) != std::string::npos; from = comma + 1)
      cells.push_back(line.substr(from, comma - from));
    cells.push_back(line.substr(from));
    return cells;
  };
  std::string line;
  if (!std::getline(in, line)) return;  // empty file: nothing sampled yet
  const std::vector<std::string> header = split(line);
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw std::runtime_error(history_csv.string() + " has no column " + name);
    return std::size_t(it - header.begin());
  };
  const std::size_t time_col = column("time_s");
  std::vector<std::pair<std::size_t, std::size_t>> cols;
  for (const Storey& s : storeys_) {
    const std::string prefix = "storey" + std::to_string(s.number) + "_drift";
    cols.emplace_back(column(prefix + "_x_m"), column(prefix + "_y_m"));
  }
  auto number = [&](const std::string& text) {
    double v = 0.0;
    const auto res = std::from_chars(text.data(), text.data() + text.size(), v);
    if (res.ec != std::errc() || res.ptr != text.data() + text.size())
      throw std::runtime_error(history_csv.string() + ": '" + text + "' is not a number");
    return v;
  };
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    if (cells.size() != header.size()) throw std::runtime_error(history_csv.string() + ": a row has the wrong length");
    const double t = number(cells[time_col]);
    for (std::size_t i = 0; i < storeys_.size(); ++i)
      record(i, Eigen::Vector2d(number(cells[cols[i].first]), number(cells[cols[i].second])), t);
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

void StoreyDriftMonitor::record(std::size_t i, const Eigen::Vector2d& drift_m, double time_s) {
  drift_m_[i] = drift_m;
  const Eigen::Vector2d ratio = drift_ratio_rad(i);
  record_peaks(i, ratio, time_s);
  StoreyDriftRecord& r = records_[i];
  r.final_ratio_x_rad = ratio.x();
  r.final_ratio_y_rad = ratio.y();
  // Residual: the mean of the samples within the trailing window, from a
  // running sum (one add and one subtract per sample: its round-off stays
  // below 1e-16 of the largest ratio times the samples of a run, 1e-10 at
  // most, far below any drift worth reading).
  std::deque<TimedRatio>& w = window_[i];
  Eigen::Vector2d& sum = window_sum_[i];
  w.push_back({time_s, ratio});
  sum += ratio;
  while (w.front().time_s < time_s - kResidualDriftWindow_s * (1.0 - 1e-9)) {
    sum -= w.front().ratio;
    w.pop_front();
  }
  r.residual_ratio_x_rad = sum.x() / double(w.size());
  r.residual_ratio_y_rad = sum.y() / double(w.size());
  r.residual_window_s = time_s - w.front().time_s;
}

StoreyVerdict StoreyDriftMonitor::verdict(std::size_t i) const {
  const double peak = records_[i].peak_ratio_rad;
  if (peak >= limits_.collapse_drift_ratio_rad) return StoreyVerdict::Collapsed;
  if (peak > limits_.safety_drift_ratio_rad) return StoreyVerdict::Damaged;
  return StoreyVerdict::Standing;
}

}  // namespace fq
