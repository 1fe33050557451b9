#include "io/storey_drift.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "io/joint_builder.h"
#include "io/point_grid.h"

namespace fq {

const char* storey_verdict_name(StoreyVerdict v) {
  switch (v) {
    case StoreyVerdict::Standing: return "standing";
    case StoreyVerdict::Damaged: return "damaged";
    case StoreyVerdict::Collapsed: return "collapsed";
  }
  return "unknown";
}

namespace {

// A member of kind column as the storeys see it: its end nodes, low end
// first, and their heights snapped to the floor levels (find_storeys).
struct ColumnSegment {
  std::size_t member = 0;
  int low_node = -1, high_node = -1;  // node indices
  Vec3 low_m = Vec3::Zero(), high_m = Vec3::Zero();  // node positions (m)
  double low_z_m = 0.0, high_z_m = 0.0;               // snapped heights (m)
  // The point on the member's axis at height z (m); beyond an end it lies
  // on the axis extended, which a column end snapped a few mm to its
  // floor level asks for.
  Vec3 point_at(double z) const {
    const double f = (z - low_m.z()) / (high_m.z() - low_m.z());
    return low_m + f * (high_m - low_m);
  }
};

// A height at which a floor may lie: a column top that is a floor (a beam
// frames into it, or no column continues up from it) or the lowest column
// foot, with the vertical extent of the deepest beam framing into its
// node (m; 0 without one).
struct LevelCandidate {
  double z_m = 0.0;
  double beam_height_m = 0.0;
};

// A floor level: the median height of the candidates merged into it and
// the tolerance within which a column end belongs to it (m).
struct Level {
  double z_m = 0.0;
  double tolerance_m = kStoreyLevelTolerance_m;
};

// Vertical extent of a member's section (m): of a horizontal beam, the
// section's depth as rolled (width_m at a roll of 90 degrees).
double section_height_m(const CaseDef& def, const MemberDef& m, int node_a, int node_b) {
  const SectionDef& sec = def.sections[std::size_t(def.section_index(m.section))];
  const Vec3 a = def.nodes[std::size_t(node_a)].xyz_m;
  const Vec3 b = def.nodes[std::size_t(node_b)].xyz_m;
  const Mat3 r = member_orientation(a, b, m.roll_rad).toRotationMatrix();
  return std::abs(r(2, 1)) * sec.width_m + std::abs(r(2, 2)) * sec.depth_m;
}

}  // namespace

std::vector<Storey> find_storeys(const Model& model) {
  const CaseDef& def = model.def;
  const double tol = kStoreyLevelTolerance_m;
  std::vector<ColumnSegment> segments;
  std::vector<double> beam_height_m(def.nodes.size(), -1.0);  // deepest beam at each node; < 0: none
  std::vector<char> column_goes_up(def.nodes.size(), 0);        // a column has its low end here
  // Per node, the members ending there that may carry a floor there:
  // neither columns nor braces.
  std::vector<std::vector<std::size_t>> floor_members_at(def.nodes.size());
  const NameIndex node_ids(def.nodes, &NodeDef::id);
  for (std::size_t i = 0; i < def.members.size(); ++i) {
    const MemberDef& m = def.members[i];
    const int na = node_ids.find(m.node_a), nb = node_ids.find(m.node_b);
    if (m.kind != MemberKind::Column && m.kind != MemberKind::Brace)
      for (const int n : {na, nb}) floor_members_at[std::size_t(n)].push_back(i);
    if (m.kind == MemberKind::Beam) {
      const double h = section_height_m(def, m, na, nb);
      for (const int n : {na, nb}) beam_height_m[std::size_t(n)] = std::max(beam_height_m[std::size_t(n)], h);
      continue;
    }
    if (m.kind != MemberKind::Column) continue;
    ColumnSegment c;
    c.member = i;
    c.low_node = na;
    c.high_node = nb;
    c.low_m = def.nodes[std::size_t(na)].xyz_m;
    c.high_m = def.nodes[std::size_t(nb)].xyz_m;
    if (std::abs(c.low_m.z() - c.high_m.z()) < tol) continue;  // a horizontal "column" spans no storey
    if (c.low_m.z() > c.high_m.z()) {
      std::swap(c.low_m, c.high_m);
      std::swap(c.low_node, c.high_node);
    }
    segments.push_back(c);
    column_goes_up[std::size_t(c.low_node)] = 1;
  }
  if (segments.empty()) return {};

  // Floor levels. A column top is a floor when a beam frames into its node
  // (the floor's beams carry the storey above and tie the columns
  // together), or when no column continues up from it (a roof top, a free
  // post top: the top of the structure there). A column top with only a
  // brace or an `other` member at it, and a column continuing up, is a
  // joint along one column line (a column split for a knee brace), not a
  // floor: a level there cut the storey in two (geometry probe: a
  // two-storey frame read as three). The lowest column foot is the lowest
  // level; a foot higher up (a hillside step, a post on a beam) is none.
  std::vector<LevelCandidate> candidates;
  {
    std::vector<char> seen(def.nodes.size(), 0);
    auto add = [&](int node) {
      if (seen[std::size_t(node)]) return;
      seen[std::size_t(node)] = 1;
      candidates.push_back({def.nodes[std::size_t(node)].xyz_m.z(), std::max(0.0, beam_height_m[std::size_t(node)])});
    };
    for (const ColumnSegment& c : segments)
      if (beam_height_m[std::size_t(c.high_node)] >= 0.0 || !column_goes_up[std::size_t(c.high_node)]) add(c.high_node);
    add(std::min_element(segments.begin(), segments.end(), [](const ColumnSegment& p, const ColumnSegment& q) {
          return p.low_m.z() < q.low_m.z();
        })->low_node);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const LevelCandidate& p, const LevelCandidate& q) { return p.z_m < q.z_m; });
  // Merging. The nodes of one floor may be typed anywhere on its beams'
  // sections (a beam of vertical extent d occupies +-d/2 about its axis):
  // on the axis, or on the top or bottom face, up to d apart; and two
  // floors less than the depth of the deeper one's beams apart leave no
  // clear height between them for a storey. So candidates closer than the
  // depth of the deepest beam framing into either are one floor (a floor
  // node typed 5 mm high on 10 mm beams made a storey 5 mm tall of its
  // own, damaged, and renumbered the storey above; geometry probe), with
  // kStoreyLevelTolerance_m as the least tolerance (levels without beams).
  // Each candidate is compared with the lowest of its floor, so a floor
  // spans at most one beam depth however many nodes lie a little apart.
  // The floor's height is the median of its candidates' (one node typed
  // off level among several does not move it).
  std::vector<Level> levels;
  {
    std::size_t first = 0;
    while (first < candidates.size()) {
      double depth_m = candidates[first].beam_height_m;
      std::size_t end = first + 1;
      while (end < candidates.size() &&
             candidates[end].z_m - candidates[first].z_m <
                 std::max(tol, std::max(depth_m, candidates[end].beam_height_m))) {
        depth_m = std::max(depth_m, candidates[end].beam_height_m);
        ++end;
      }
      const std::size_t n = end - first, mid = first + n / 2;
      const double median_m = n % 2 ? candidates[mid].z_m : 0.5 * (candidates[mid - 1].z_m + candidates[mid].z_m);
      levels.push_back({median_m, std::max(tol, depth_m)});
      first = end;
    }
  }
  // Each column end within its floor's tolerance is taken at the floor's
  // height: for which storeys the column belongs to and for its top and
  // bottom points (a column ending 5 mm above its floor reaches it). An end
  // where beams frame in may lie anywhere on their section as well: within
  // the depth of the deepest of them. (Scale probe, 2026-11-27: columns
  // whose tops were typed 3 mm above the floor beams, on nodes of their
  // own, made the floor's level 0.293 m with the least tolerance, and the
  // storey above, standing on the beams' nodes at 0.29, was counted into
  // the storey below as 3 mm columns that halved its mean drift.)
  auto snapped = [&](double z, int node) {
    const double beam_m = beam_height_m[std::size_t(node)];
    const Level* best = nullptr;
    for (const Level& l : levels)
      if (std::abs(z - l.z_m) < std::max(l.tolerance_m, beam_m) &&
          (!best || std::abs(z - l.z_m) < std::abs(z - best->z_m)))
        best = &l;
    return best ? best->z_m : z;
  };
  for (ColumnSegment& c : segments) {
    c.low_z_m = snapped(c.low_m.z(), c.low_node);
    c.high_z_m = snapped(c.high_m.z(), c.high_node);
  }
  // Column segments whose two ends snap to one floor span no storey.
  segments.erase(std::remove_if(segments.begin(), segments.end(),
                                [&](const ColumnSegment& c) { return c.high_z_m - c.low_z_m < tol; }),
                 segments.end());

  // A member ending at a column top that no joint holds there is no floor
  // of that column (the joint planner's rule, io/joint_builder.h).
  const JoinedMemberEnds joined_ends(def);

  // Segments by their high node, in order: a column line is followed down
  // through its joints once per storey, and a scan of all segments per
  // joint grew with the square of the frame.
  std::unordered_map<int, std::vector<std::size_t>> ending_at;
  for (std::size_t b = 0; b < segments.size(); ++b) ending_at[segments[b].high_node].push_back(b);
  std::vector<Storey> storeys;
  for (std::size_t k = 1; k < levels.size(); ++k) {
    Storey s;
    s.bottom_z_m = levels[k - 1].z_m;
    s.top_z_m = levels[k].z_m;
    for (std::size_t t = 0; t < segments.size(); ++t) {
      // A column line of the band: a segment reaching the band's top level
      // from below it, followed down through the joints along its line
      // (nodes inside the band where another column segment ends) to the
      // segment at the band's bottom level, or to a foot inside the band
      // (a column on a hillside step, a post on a beam), which it counts
      // from. Where two segments end at one joint from below, the first in
      // the file is taken.
      const ColumnSegment& top = segments[t];
      if (top.low_z_m > s.top_z_m - tol || top.high_z_m < s.top_z_m - tol) continue;
      std::vector<std::size_t> line{t};
      while (segments[line.back()].low_z_m > s.bottom_z_m + tol) {
        const int joint = segments[line.back()].low_node;
        std::size_t below = segments.size();
        if (const auto at = ending_at.find(joint); at != ending_at.end())
          for (const std::size_t b : at->second)
            if (segments[b].low_z_m < segments[line.back()].low_z_m) {
              below = b;
              break;
            }
        if (below == segments.size()) break;
        line.push_back(below);
      }
      const ColumnSegment& bottom = segments[line.back()];
      const double foot_z = bottom.low_z_m > s.bottom_z_m + tol ? bottom.low_z_m : s.bottom_z_m;
      StoreyColumn sc;
      sc.bottom_body = model.member_body[bottom.member];
      sc.top_body = model.member_body[top.member];
      sc.bottom_start_m = bottom.point_at(foot_z);
      sc.top_start_m = top.point_at(s.top_z_m);
      sc.height_m = s.top_z_m - foot_z;
      sc.bottom_local_m = model.bodies.rotation[sc.bottom_body].transpose() *
                          (sc.bottom_start_m - model.bodies.position_m[sc.bottom_body]);
      sc.top_local_m =
          model.bodies.rotation[sc.top_body].transpose() * (sc.top_start_m - model.bodies.position_m[sc.top_body]);
      // The floor at this line's top: the members joined at its top node,
      // where that node is of the band's top level (StoreyColumn).
      if (std::abs(top.high_z_m - s.top_z_m) < tol)
        for (const std::size_t m : floor_members_at[std::size_t(top.high_node)]) {
          if (!joined_ends.joined(m, std::size_t(top.high_node))) continue;
          StoreyColumn::FloorPoint f;
          f.body = model.member_body[m];
          f.start_m = def.nodes[std::size_t(top.high_node)].xyz_m;
          f.local_m = model.bodies.rotation[f.body].transpose() * (f.start_m - model.bodies.position_m[f.body]);
          sc.floor_points.push_back(f);
        }
      s.columns.push_back(sc);
      // Named after its segments, lowest first ("c1a+c1b").
      std::string name;
      for (auto it = line.rbegin(); it != line.rend(); ++it)
        name += (name.empty() ? "" : "+") + def.members[segments[*it].member].id;
      s.column_names.push_back(name);
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
    const Vec3 top = bodies.to_world(c.top_body, c.top_local_m) - c.top_start_m;
    const Vec3 bottom = bodies.to_world(c.bottom_body, c.bottom_local_m) - c.bottom_start_m;
    const Vec3 drift = top - bottom;
    if (per_column) per_column->emplace_back(drift.x(), drift.y());
    sum += drift;
  }
  sum /= double(storey.columns.size());
  return {sum.x(), sum.y()};
}

double residual_drift_window_s(const CaseDef& def) {
  return kResidualDriftWindow_record_s * (def.ground_motion ? def.ground_motion->time_scale : 1.0);
}

StoreyDriftMonitor::StoreyDriftMonitor(std::vector<Storey> storeys, AssessmentDef limits, double dt_s,
                                       double residual_window_s)
    : storeys_(std::move(storeys)),
      limits_(limits),
      records_(storeys_.size()),
      drift_m_(storeys_.size(), Eigen::Vector2d::Zero()),
      residual_(storeys_.size()),
      dt_s_(dt_s) {
  if (!(dt_s > 0.0)) throw std::invalid_argument("StoreyDriftMonitor: the time step must be positive");
  if (!(residual_window_s > 0.0))
    throw std::invalid_argument("StoreyDriftMonitor: the residual drift's window must be positive");
  storey_below_.assign(storeys_.size(), -1);
  columns_below_.resize(storeys_.size());
  twist_.resize(storeys_.size());
  for (std::size_t i = 0; i < storeys_.size(); ++i) {
    for (std::size_t j = 0; j < storeys_.size(); ++j)
      if (j != i && std::abs(storeys_[j].top_z_m - storeys_[i].bottom_z_m) < kStoreyLevelTolerance_m)
        storey_below_[i] = int(j);
    // The floor below is measured where this storey stands on it: the
    // columns below whose tops are (in plan, within the level tolerance)
    // where this storey's columns start. A mezzanine column in the storey
    // below that carries nothing of this storey would otherwise move the
    // floor below (review probe: a frame without broken joints showed a
    // base slip of 0.35 mm). Where no column stands on one below (a
    // setback floor on beams), the whole floor below's mean.
    if (storey_below_[i] >= 0) {
      const Storey& below = storeys_[std::size_t(storey_below_[i])];
      // This storey's column feet in plan in a grid: each column below
      // meets only the feet near it, not all (quadratic at 10k columns).
      std::vector<Vec3> feet;
      feet.reserve(storeys_[i].columns.size());
      for (const StoreyColumn& c : storeys_[i].columns)
        feet.emplace_back(c.bottom_start_m.x(), c.bottom_start_m.y(), 0.0);
      const PointGrid grid(std::move(feet), kStoreyLevelTolerance_m);
      std::vector<int> near;
      for (std::size_t k = 0; k < below.columns.size(); ++k) {
        const Eigen::Vector2d top = below.columns[k].top_start_m.head<2>();
        const Vec3 reach(kStoreyLevelTolerance_m + 1e-6, kStoreyLevelTolerance_m + 1e-6, 0.0);
        near.clear();
        grid.candidates(Vec3(top.x(), top.y(), 0.0) - reach, Vec3(top.x(), top.y(), 0.0) + reach, near);
        for (const int c : near)
          if ((top - storeys_[i].columns[std::size_t(c)].bottom_start_m.head<2>()).norm() < kStoreyLevelTolerance_m) {
            columns_below_[i].push_back(k);
            break;
          }
      }
      if (columns_below_[i].empty())
        for (std::size_t k = 0; k < below.columns.size(); ++k) columns_below_[i].push_back(k);
    }
    TwistGeometry& g = twist_[i];
    const std::size_t n = storeys_[i].columns.size();
    Eigen::Vector2d top_c = Eigen::Vector2d::Zero(), bottom_c = Eigen::Vector2d::Zero();
    for (const StoreyColumn& c : storeys_[i].columns) {
      top_c += c.top_start_m.head<2>() / double(n);
      bottom_c += c.bottom_start_m.head<2>() / double(n);
    }
    for (const StoreyColumn& c : storeys_[i].columns) {
      g.top_r.push_back(c.top_start_m.head<2>() - top_c);
      g.bottom_r.push_back(c.bottom_start_m.head<2>() - bottom_c);
      g.top_r2 += g.top_r.back().squaredNorm();
      g.bottom_r2 += g.bottom_r.back().squaredNorm();
      g.r_max = std::max(g.r_max, g.top_r.back().norm());
    }
  }
  top_m_.resize(storeys_.size());
  bottom_m_.resize(storeys_.size());
  floor_m_.resize(storeys_.size());
  for (std::size_t i = 0; i < storeys_.size(); ++i) {
    top_m_[i].resize(storeys_[i].columns.size());
    bottom_m_[i].resize(storeys_[i].columns.size());
    floor_m_[i].resize(storeys_[i].columns.size());
  }
  const double window_steps = std::max(1.0, std::round(residual_window_s / dt_s));
  block_steps_ = std::max<std::int64_t>(1, std::int64_t(window_steps / 1000.0));
  window_blocks_ = std::size_t(std::ceil(window_steps / double(block_steps_)));
}

void StoreyDriftMonitor::sample(const BodyStore& bodies, std::int64_t step, double time_s) {
  if (step == last_step_) return;
  last_step_ = step;
  for (std::size_t i = 0; i < storeys_.size(); ++i) record(i, storey_drift_m(storeys_[i], bodies), time_s);
}

void StoreyDriftMonitor::track(const BodyStore& bodies, double time_s) {
  // Every column's points and its floor first: the floor drift of a storey
  // needs the floor at the tops of the storey below.
  for (std::size_t i = 0; i < storeys_.size(); ++i)
    for (std::size_t k = 0; k < storeys_[i].columns.size(); ++k) {
      const StoreyColumn& c = storeys_[i].columns[k];
      top_m_[i][k] = (bodies.to_world(c.top_body, c.top_local_m) - c.top_start_m).head<2>();
      bottom_m_[i][k] = (bodies.to_world(c.bottom_body, c.bottom_local_m) - c.bottom_start_m).head<2>();
      if (c.floor_points.empty()) {
        floor_m_[i][k] = top_m_[i][k];
        continue;
      }
      Vec3 floor = Vec3::Zero();
      for (const StoreyColumn::FloorPoint& f : c.floor_points) floor += bodies.to_world(f.body, f.local_m) - f.start_m;
      floor_m_[i][k] = floor.head<2>() / double(c.floor_points.size());
    }
  for (std::size_t i = 0; i < storeys_.size(); ++i) {
    const Storey& s = storeys_[i];
    const double height_m = s.height_m();
    // The storey's drift as storey_drift_m forms it: the mean of its
    // columns' top less bottom.
    Eigen::Vector2d drift_m = Eigen::Vector2d::Zero();
    for (std::size_t c = 0; c < s.columns.size(); ++c) drift_m += top_m_[i][c] - bottom_m_[i][c];
    drift_m /= double(s.columns.size());
    const Eigen::Vector2d ratio = drift_m / height_m;
    record_peaks(i, ratio, time_s);
    record_residual(i, ratio);
    StoreyDriftRecord& r = records_[i];
    for (std::size_t c = 0; c < s.columns.size(); ++c) {
      const double column_ratio = (top_m_[i][c] - bottom_m_[i][c]).norm() / s.columns[c].height_m;
      if (column_ratio > r.peak_column_ratio_rad) {
        r.peak_column_ratio_rad = column_ratio;
        r.peak_column = int(c);
      }
    }
    // Floor drift, top slip and base slip (StoreyDriftRecord): the floor
    // below where this storey stands on it, this storey's floor and its
    // column tops and bottoms, each as the mean over its points.
    Eigen::Vector2d below_m = Eigen::Vector2d::Zero();
    if (storey_below_[i] >= 0) {
      for (const std::size_t k : columns_below_[i]) below_m += floor_m_[std::size_t(storey_below_[i])][k];
      below_m /= double(columns_below_[i].size());
    }
    Eigen::Vector2d floor_mean_m = Eigen::Vector2d::Zero(), top_mean_m = Eigen::Vector2d::Zero(),
                    bottom_mean_m = Eigen::Vector2d::Zero();
    for (std::size_t c = 0; c < s.columns.size(); ++c) {
      floor_mean_m += floor_m_[i][c];
      top_mean_m += top_m_[i][c];
      bottom_mean_m += bottom_m_[i][c];
    }
    const double n = double(s.columns.size());
    floor_mean_m /= n;
    top_mean_m /= n;
    bottom_mean_m /= n;
    r.peak_floor_ratio_rad = std::max(r.peak_floor_ratio_rad, (floor_mean_m - below_m).norm() / height_m);
    r.peak_top_slip_m = std::max(r.peak_top_slip_m, (floor_mean_m - top_mean_m).norm());
    r.peak_base_slip_m = std::max(r.peak_base_slip_m, (bottom_mean_m - below_m).norm());
    // Twist: least-squares turns of the top and bottom points about z.
    const TwistGeometry& g = twist_[i];
    if (g.top_r2 > 0.0 && g.bottom_r2 > 0.0) {
      double top_turn = 0.0, bottom_turn = 0.0;
      for (std::size_t c = 0; c < s.columns.size(); ++c) {
        const Eigen::Vector2d& dt = top_m_[i][c];
        const Eigen::Vector2d& db = bottom_m_[i][c];
        top_turn += g.top_r[c].x() * dt.y() - g.top_r[c].y() * dt.x();
        bottom_turn += g.bottom_r[c].x() * db.y() - g.bottom_r[c].y() * db.x();
      }
      const double twist = std::abs(top_turn / g.top_r2 - bottom_turn / g.bottom_r2) * g.r_max / height_m;
      r.peak_twist_ratio_rad = std::max(r.peak_twist_ratio_rad, twist);
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
                           r.residual_window_s, r.peak_column_ratio_rad, r.peak_floor_ratio_rad, r.peak_top_slip_m,
                           r.peak_base_slip_m, r.peak_twist_ratio_rad})
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
  // The storeys themselves are not stored: a resume rebuilds them from the
  // case (find_storeys) and reads only what was recorded of them. Where the
  // storey rules have changed since the checkpoint was written (2026-11-27:
  // floors only where a beam frames in or no column continues up, levels
  // merged within a beam's depth), the change removed levels or moved a
  // level by less than 1 mm (the median of heights within 1 mm, not the
  // lowest): such a case has fewer storeys than its checkpoint, which the
  // count below refuses, or the same storeys with the same columns.
  in.section("storeys");
  const std::uint64_t n = in.u64("storey count");
  if (n != records_.size())
    in.fail("the checkpoint has " + std::to_string(n) + " storeys, the case " + std::to_string(records_.size()));
  if (in.i64("residual block") != block_steps_) in.fail("the residual's blocks are of another size");
  for (std::size_t i = 0; i < records_.size(); ++i) {
    StoreyDriftRecord& r = records_[i];
    for (double* v : {&r.peak_ratio_x_rad, &r.peak_ratio_y_rad, &r.peak_ratio_rad, &r.peak_time_s, &r.collapse_time_s,
                      &r.final_ratio_x_rad, &r.final_ratio_y_rad, &r.residual_ratio_x_rad, &r.residual_ratio_y_rad,
                      &r.residual_window_s, &r.peak_column_ratio_rad, &r.peak_floor_ratio_rad, &r.peak_top_slip_m,
                      &r.peak_base_slip_m, &r.peak_twist_ratio_rad})
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

std::string StoreyDriftMonitor::peak_at_end_warning(std::size_t i, double end_time_s) const {
  const StoreyDriftRecord& r = records_[i];
  const StoreyVerdict v = verdict(i);
  if (v == StoreyVerdict::Collapsed || !(r.peak_ratio_rad >= 0.5 * limits_.safety_drift_ratio_rad) ||
      !(end_time_s > 0.0) || r.peak_time_s < (1.0 - kPeakAtEndFraction) * end_time_s)
    return "";
  std::ostringstream w;
  w << std::setprecision(4) << "storey " << storeys_[i].number << "'s drift peaked at " << r.peak_ratio_rad
    << " rad at t = " << r.peak_time_s << " s, in the last " << 100.0 * kPeakAtEndFraction
    << " % of the run (which ended at " << end_time_s << " s): it may still have been growing, so its verdict ("
    << storey_verdict_name(v)
    << ") holds for this window only; a longer one (ground_motion.window_length_s, time.duration_s) would show "
       "where it goes";
  return w.str();
}

std::string StoreyDriftMonitor::slip_warning(std::size_t i, int broken_column_joints, int column_joints) const {
  const StoreyDriftRecord& r = records_[i];
  const StoreyVerdict storey = verdict(i), floor = verdict_for_peak(r.peak_floor_ratio_rad, limits_);
  if (int(floor) <= int(storey)) return "";
  const Storey& s = storeys_[i];
  const char* below = storey_below_[i] < 0 ? "the foundation" : "the floor below";
  // Which slid (kSlipShareNamed): at least one of the two always is named.
  const double excess_m = (r.peak_floor_ratio_rad - r.peak_ratio_rad) * s.height_m();
  const bool top = r.peak_top_slip_m >= kSlipShareNamed * excess_m;
  const bool base = r.peak_base_slip_m >= kSlipShareNamed * excess_m;
  std::ostringstream w;
  w << std::setprecision(3) << "storey " << s.number << "'s floor moved " << r.peak_floor_ratio_rad
    << " rad of its height relative to " << below << ", which would make it " << storey_verdict_name(floor)
    << ", while its columns tilted " << r.peak_ratio_rad << " rad (" << storey_verdict_name(storey) << "): ";
  if (top) w << "the floor slid up to " << 1e3 * r.peak_top_slip_m << " mm on its column tops";
  if (top && base) w << " and ";
  if (base) w << "the columns' feet slid up to " << 1e3 * r.peak_base_slip_m << " mm on " << below;
  // Why it slid, as far as the caller knows (closed-form probe, stop 41:
  // a cantilever's arm that fell when its joint broke read as a floor
  // sliding on a joint that held).
  const bool one_column = s.columns.size() == 1;
  const char* columns = one_column ? "its column" : "its columns";
  if (column_joints < 0)
    w << " (events.csv lists the joints that broke; a joint soft in shear lets its members slide while it holds)";
  else if (broken_column_joints > 0 && column_joints == 1)
    w << " (the joint holding " << columns << " broke; events.csv says when)";
  else if (broken_column_joints > 0)
    w << " (" << broken_column_joints << " of the " << column_joints << " joints holding " << columns
      << " broke; events.csv lists them)";
  else if (column_joints > 0)
    w << " (" << (column_joints == 1 ? "the joint" : "none of the joints") << " holding " << columns
      << (column_joints == 1 ? " did not break" : " broke")
      << ": a joint soft in shear lets its members slide while it holds)";
  else
    w << " (no joint holds " << columns << ": " << (one_column ? "it stands" : "they stand")
      << " and slide" << (one_column ? "s" : "") << " on " << (one_column ? "its" : "their") << " contacts)";
  w << "; the verdict is that of the tilt (peak_floor_drift_ratio_rad, peak_top_slip_m and peak_base_slip_m in "
       "summary.json; cases/README.md, assessment)";
  return w.str();
}

std::string StoreyDriftMonitor::twist_warning(std::size_t i) const {
  const StoreyDriftRecord& r = records_[i];
  const StoreyVerdict storey = verdict(i), column = verdict_for_peak(r.peak_column_ratio_rad, limits_);
  if (r.peak_column < 0 || int(column) <= int(storey)) return "";
  const Storey& s = storeys_[i];
  // The column quoted, and for one shorter than the storey (its foot
  // inside the band) the height its ratio is taken over.
  std::ostringstream label;
  label << std::setprecision(3) << "'" << s.column_names[std::size_t(r.peak_column)] << "'";
  const double own_height_m = s.columns[std::size_t(r.peak_column)].height_m;
  if (s.height_m() - own_height_m > kStoreyLevelTolerance_m)
    label << " (" << own_height_m << " m tall in the storey's " << s.height_m() << " m; its ratio is over its own height)";
  const std::string column_label = label.str();
  std::ostringstream w;
  w << std::setprecision(3);
  // A mean of zero with a column drifting is a pure twist (columns on
  // opposite sides drifting opposite ways).
  const bool apart =
      !(r.peak_ratio_rad > 0.0) || r.peak_column_ratio_rad > (1.0 + kTwistColumnExcess) * r.peak_ratio_rad;
  // Columns far apart in drift whose floor did not turn: one side leaned
  // while the other stood or slid (acceptance probe: frame B under Kobe
  // x1.25, north columns leaning 0.172 rad after their feet broke, south
  // ones sliding upright, floor turned by nothing, was called a twist).
  const bool turned = r.peak_twist_ratio_rad > kTwistColumnExcess * r.peak_ratio_rad;
  if (apart && !turned) {
    w << "storey " << s.number << "'s columns did not move alike: its drift, the mean of its " << s.columns.size()
      << " columns, peaked at " << r.peak_ratio_rad << " rad (" << storey_verdict_name(storey) << "), but column " << column_label << " alone drifted " << r.peak_column_ratio_rad << " rad, which would make it "
      << storey_verdict_name(column) << ", while the floor did not turn (twist at most " << r.peak_twist_ratio_rad
      << " rad): some columns leaned further than others (a column broken loose at a joint, or columns of other "
         "stiffness or length in one storey); the verdict uses the mean (cases/README.md, assessment)";
  } else if (apart) {
    w << "storey " << s.number << " twists: its drift, the mean of its " << s.columns.size() << " columns, peaked at "
      << r.peak_ratio_rad << " rad (" << storey_verdict_name(storey) << "), but column " << column_label << " alone drifted "
      << r.peak_column_ratio_rad << " rad, which would make it " << storey_verdict_name(column)
      << "; the verdict uses the mean (cases/README.md, assessment)";
  } else {
    // The columns drifted alike (within kTwistColumnExcess): no twist, but
    // a verdict within that of a limit the largest column alone passes
    // (geometry probe: 0.0597 rad against a mean of 0.0588 at a collapse
    // limit of 0.0588 was called a twist).
    const bool collapse = column == StoreyVerdict::Collapsed;
    w << "storey " << s.number << "'s drift, the mean of its " << s.columns.size() << " columns, peaked at "
      << r.peak_ratio_rad << " rad (" << storey_verdict_name(storey) << "), under the "
      << (collapse ? "collapse" : "safety") << " limit of "
      << (collapse ? limits_.collapse_drift_ratio_rad : limits_.safety_drift_ratio_rad)
      << " rad, which its largest column, " << column_label << ", passes alone at " << r.peak_column_ratio_rad << " rad, "
      << std::setprecision(2) << 100.0 * (r.peak_column_ratio_rad / r.peak_ratio_rad - 1.0)
      << " % above the mean: its columns drifted alike (no twist), and the verdict, which uses the mean, lies within "
         "that of the limit (cases/README.md, assessment)";
  }
  return w.str();
}

}  // namespace fq
