// Storeys of a framed structure, their inter-storey drift and the verdict on
// each (cases/README.md, `assessment`).
//
// Storey levels are the floors: the heights of the column tops that a beam
// frames into or that no column continues up from (a roof top, a free post
// top), and the lowest column foot. A column top with a column continuing
// up and no beam (a column split at mid-height for a knee brace; a brace or
// an `other` member there does not make a floor) is a joint along one
// column line, not a level. Levels closer than the depth of the deepest
// beam framing into either (at least kStoreyLevelTolerance_m) are one floor,
// at their median height, and a column end within that depth of a floor is
// taken at the floor's height (a floor node typed 5 mm off level). Storey k
// (1-based) is the band between level k-1 and level k; its columns are the
// column lines reaching its top level from at or below it: a column segment
// reaching the top level, followed down through the joints along its line
// to the segment at the band's bottom level. Each line contributes two
// material points on its axis, at the band's top height on the top segment
// and at its bottom height on the bottom segment (or the line's own foot
// where that lies inside the band: a column on a hillside step, a post on
// a beam), each fixed in its segment's body frame. The drift of the storey
// (m) is the mean over its column lines of the horizontal displacement of
// the top point relative to the bottom point; the drift ratio (rad) is
// drift / height. While the joints
// hold, these points coincide with the nodes and this is the usual relative
// displacement of two floors (displacements are relative to the ground,
// DESIGN.md). After the joints fail the points follow the columns that
// carried the storey: a storey that drops upright onto a collapsed storey
// below keeps a small drift.
//
// The floor itself is measured apart from the columns: at each column
// line's top node, a point on every member that is neither a column nor a
// brace (a beam, an `other`) ending and joined there, fixed in its body at
// the node (StoreyColumn::floor_points). A floor that slides on column tops
// whose joints stay whole but give in shear (a tenon soft across its
// shoulder) moves while the column points stay put: measured on the
// columns alone, it drifted nothing (top-slip probe: a floor 12.5 mm,
// 0.042 rad, off its columns read 4e-6 rad without a warning).
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "dem_core/body_store.h"
#include "dem_core/state_io.h"
#include "io/case_def.h"
#include "io/model.h"

namespace fq {

// One column line of a storey: one column member, or several joined end to
// end at joints that are no floor level (find_storeys). Its two points lie
// on the bodies of its bottom and top segments (one body for one member).
struct StoreyColumn {
  BodyId bottom_body = kNoBody;
  BodyId top_body = kNoBody;
  Vec3 bottom_local_m = Vec3::Zero();  // point at the band's bottom, bottom_body's frame (m)
  Vec3 top_local_m = Vec3::Zero();     // point at the band's top, top_body's frame (m)
  Vec3 bottom_start_m = Vec3::Zero();  // its world position at t = 0 (m)
  Vec3 top_start_m = Vec3::Zero();
  // The column line's own height, top point less bottom point (m): the
  // storey's height, or less for a foot inside the band (a column on a
  // hillside step, a post on a beam). A column's drift ratio is over its
  // own height: a short column takes the floor's sway over its shorter
  // length, and over the storey's height its tilt read 0.19 / 0.29 of what
  // it was (geometry probe, 2026-11-27: a hillside column tilting 0.0404
  // rad, past the safety limit, was reported at 0.0272 without a warning).
  double height_m = 0.0;
  // The floor where this line's top carries it: a point on each member
  // that is neither a column nor a brace, ends at the top segment's top
  // node and is joined there (a joint at that node holds it: joints
  // generated at the node, or an override naming it), fixed in that
  // member's body at the node. The floor's displacement at this column is
  // the mean of theirs; empty (no such member, or a top that is no node at
  // the band's top level: a column running on through the floor) means
  // the column's own top point.
  struct FloorPoint {
    BodyId body = kNoBody;
    Vec3 local_m = Vec3::Zero();  // in body's frame (m)
    Vec3 start_m = Vec3::Zero();  // the node: its world position at t = 0 (m)
  };
  std::vector<FloorPoint> floor_points;
};

struct Storey {
  int number = 0;            // 1 = lowest
  double bottom_z_m = 0.0;   // level heights (m)
  double top_z_m = 0.0;
  double height_m() const { return top_z_m - bottom_z_m; }
  std::vector<StoreyColumn> columns;
  // Per column line, its members' ids from the lowest up, joined by '+'
  // ("c1a+c1b"); one member's line is its id.
  std::vector<std::string> column_names;
};

// The least distance between two floor levels (where no beam frames into
// either: the tolerance is otherwise the deepest beam's depth), and a
// column whose ends lie closer than this in height spans no storey (m).
inline constexpr double kStoreyLevelTolerance_m = 1e-3;

// Storeys of a built model (header); empty when it has no (non-horizontal)
// columns.
std::vector<Storey> find_storeys(const Model& model);

// Current drift of a storey along world x and y (m); with `per_column`,
// also each column's own drift (top point relative to bottom point, m).
Eigen::Vector2d storey_drift_m(const Storey& storey, const BodyStore& bodies,
                               std::vector<Eigen::Vector2d>* per_column = nullptr);

enum class StoreyVerdict { Standing, Damaged, Collapsed };
const char* storey_verdict_name(StoreyVerdict v);
// The verdict a peak drift ratio (rad) gets under `limits`.
StoreyVerdict verdict_for_peak(double peak_ratio_rad, const AssessmentDef& limits);

// Running peaks of one storey's drift ratio. The peaks, the collapse time
// and the residual drift are taken at every step (StoreyDriftMonitor::
// track), so that they do not depend on how often history rows are
// written; the final drift is that of the last history row (sample).
struct StoreyDriftRecord {
  double peak_ratio_x_rad = 0.0;  // max |drift ratio x|
  double peak_ratio_y_rad = 0.0;  // max |drift ratio y|
  double peak_ratio_rad = 0.0;    // max magnitude of the (x, y) drift ratio
  double peak_time_s = 0.0;       // when peak_ratio_rad was reached
  double final_ratio_x_rad = 0.0; // at the last sample
  double final_ratio_y_rad = 0.0;
  // Residual drift: the mean over the steps of the last
  // residual window of the run (the whole run if shorter; to within
  // about two thousandths of the window, StoreyDriftMonitor; residual_window_s is the
  // time from the first to the last step averaged), not the last sample,
  // which a frame still swaying after the shaking ends puts anywhere
  // within its sway. Taken over the history rows until stop 28, it moved
  // with the row interval (a portal: 0.00302 rad at 70 ms rows, 0.00127 at
  // every step; output probe).
  double residual_ratio_x_rad = 0.0;
  double residual_ratio_y_rad = 0.0;
  double residual_window_s = 0.0;
  double collapse_time_s = -1.0;  // first step at or beyond the collapse limit; < 0: never
  // The largest drift ratio magnitude any one column line of the storey
  // reached (rad), and which (index into Storey::columns; -1: none yet).
  // The storey's drift is the mean of its columns', so a storey that twists
  // (one side braced, the other not) has a column well past it; the verdict
  // uses the mean, and the run warns when a column's own peak would have
  // given a worse one (StoreyDriftMonitor::twist_warning).
  double peak_column_ratio_rad = 0.0;
  int peak_column = -1;
  // The storey's drift follows its columns' tilt: a floor that slides on
  // its column tops, or columns whose feet slide on the floor below, leave
  // it as it was. The floor's own movement: its drift relative to the floor
  // below, the mean horizontal displacement of the storey's floor points
  // (StoreyColumn::floor_points; a column top without them counts its own
  // top point) less that of the floor below's (the storey whose top level
  // is this one's bottom level, at the columns this storey stands on; the
  // foundation, which does not move relative to the ground, for the
  // lowest), as a ratio of the height (rad). The top slip: how far the mean
  // of the floor points moved off the mean of the storey's column top
  // points (m); the base slip: how far the mean of its column bottom
  // points moved off the floor below's floor points (m). As vectors the
  // floor drift is the top slip plus the column drift plus the base slip.
  // While the joints stay stiff in shear both slips stay near zero and the
  // two drifts agree; a floor slides on its column tops where their joints
  // are soft in shear or broken (top-slip probe: 12.5 mm on joints of
  // 40 N/m in shear, whole), and column feet slide where the joints at the
  // feet are (acceptance probe: frame B under Takatori x0.75, feet slid
  // 34.6 mm, column drift 0.038, floor drift 0.119 rad, the floor then
  // taken at the column tops). Peaks taken at every step.
  double peak_floor_ratio_rad = 0.0;
  double peak_top_slip_m = 0.0;
  double peak_base_slip_m = 0.0;
  // Twist: the turn about z of the storey's top points (least squares)
  // less that of its bottom points, times the distance of its farthest
  // column from their centre, as a ratio of the height (rad): the drift a
  // turn of the floor alone gives that column. Peak taken at every step.
  double peak_twist_ratio_rad = 0.0;
};

// Trailing window over which the residual drift is averaged, in RECORD
// seconds: a run whose ground motion has time scale s (simulation s per
// record s) averages over the last s x 3 simulated seconds
// (residual_drift_window_s). The mean of a sway about a permanent offset
// over a whole number of its periods is the offset; over a window W it is
// off by at most the sway amplitude times T / (pi W). A model scaled by
// similitude has its periods scaled by s as well, so a window in record
// seconds holds the same number of periods at every scale: the frames'
// first sway (0.14 s in the 1/10 model, 0.44 s at full scale) 6.8 times,
// off by at most 4.7 % of the amplitude still swaying at the end; a
// three-storey variant's (0.27 s in the model) 3.5 times, 9 %. (A window
// of a fixed simulated second, until 2026-11-27, held 7 periods of the
// model and 2.3 of the same frame at full scale, whose residual then
// differed: +6e-5 against -3.2e-3 rad over a 4 s window of Kobe; geometry
// probe.) Without ground motion, s = 1.
inline constexpr double kResidualDriftWindow_record_s = 3.0;
// The residual's window in simulated seconds for a case (above).
double residual_drift_window_s(const CaseDef& def);

// A column line's peak drift ratio more than this fraction above its
// storey's peak (the mean of the storey's columns) is a twist. A floor
// that only translates drifts its columns alike, up to their own bending
// and joint play: in the shipped frames, a storey's largest column peaked
// 0.0 and 0.25 % above the mean in A (whose storeys fell), 1.1 and 1.2 %
// in C, 0.09 % in B's second storey (peaks taken at every step), and
// 1.5 % in a probe's braced frame; B's first storey, whose joints broke,
// had a column 26 % above its mean, and a storey braced on one side only
// (workflow probe) one past 2.3 times it. A floor that turns by phi about its centre
// of twist moves a column at r from it phi r further than the mean: a
// column 10 % above the mean is a turn plainly beyond the scatter of
// storeys that swayed alike, and well short of the twists that matter.
inline constexpr double kTwistColumnExcess = 0.10;
// The same fraction of the storey's peak for the turn of its floor
// (peak_twist_ratio_rad): a column far above the mean whose floor did not
// turn moved for another reason (its foot slid or broke loose while the
// others stood), and the warning says so instead of calling it a twist.

// The share of the floor drift's excess over the column drift (peaks, in
// m: their difference times the height) that a slip's peak must reach for
// the slip warning to name it as a cause. The floor drift's vector is the
// top slip's plus the column drift's plus the base slip's, so at the floor
// drift's peak the two slips' peaks add to at least the excess: one of
// them is at least half of it and is always named, and a quarter names
// the other as well when it carried a fair part of the excess, not when
// it is the play of joints that held.
inline constexpr double kSlipShareNamed = 0.25;

// A storey's peak within this fraction of the run's end (a retrofit probe:
// frame B at 1.25 times the Kobe record peaked at 6.316 s of a 6.324 s run,
// still growing, while the record's window went on shaking) is reported as
// possibly still growing. 2 % of the frames' 6.3 s is 0.13 s, about one
// period of their first sway (0.14 s): a peak earlier than that has been
// followed by at least most of a swing back.
inline constexpr double kPeakAtEndFraction = 0.02;

// Follows every storey of a model through a run. track() is called after
// every step (Simulation::add_step_monitor) and keeps the peaks and the
// residual; sample() is called once per history row (it ignores a
// repeated call at the same step) and keeps the latest drift, the final
// drift, and the peaks as well (a caller that only samples gets the peaks
// of its samples).
//
// The residual is summed in blocks of B whole steps, B = the window's
// steps / 1000 (at least 1): the window holds the last 1000 complete blocks
// and the block under way, so it spans the last residual window to
// within two blocks and a step (about 2 ms of 1 s; a step that does not
// divide the block's length rounds it down) and keeps about 1000 block
// sums per storey, not one number per step.
class StoreyDriftMonitor {
 public:
  // dt_s: the run's time step (s), which sets the residual's blocks;
  // residual_window_s: the residual's window in simulated seconds
  // (residual_drift_window_s for a case).
  StoreyDriftMonitor(std::vector<Storey> storeys, AssessmentDef limits, double dt_s, double residual_window_s);

  void sample(const BodyStore& bodies, std::int64_t step, double time_s);
  // The peaks, the collapse time and the residual, from the current poses.
  void track(const BodyStore& bodies, double time_s);
  // The peaks, the collapse times, the final drift and the residual's
  // blocks, for a checkpoint (section "storeys").
  void save_state(StateWriter& out) const;
  // Throws StateFormatError when the section does not fit these storeys.
  void load_state(StateReader& in);

  const std::vector<Storey>& storeys() const { return storeys_; }
  const std::vector<StoreyDriftRecord>& records() const { return records_; }
  const AssessmentDef& limits() const { return limits_; }
  // Latest sampled drift (m) of storey index i (0-based).
  const Eigen::Vector2d& drift_m(std::size_t i) const { return drift_m_[i]; }
  Eigen::Vector2d drift_ratio_rad(std::size_t i) const { return drift_m_[i] / storeys_[i].height_m(); }
  StoreyVerdict verdict(std::size_t i) const;
  // The warning for storey i when one of its columns alone drifted far
  // enough for a worse verdict than the storey's mean gives; empty
  // otherwise. It says the storey twists only when that column's peak lies
  // more than kTwistColumnExcess above the mean's; otherwise it says the
  // columns drifted alike and the verdict lies that close to a limit its
  // largest column passes.
  std::string twist_warning(std::size_t i) const;
  // The warning for storey i when its floor drift (the column drift plus
  // the top and base slips) would give a worse verdict than its column
  // drift; empty otherwise. It says which slid: the floor on its column
  // tops, the columns' feet on the floor below, or both (each named when
  // its peak is at least kSlipShareNamed of the floor drift's excess over
  // the column drift, times the height), and that the verdict stays the
  // column drift's. A joint soft in shear lets a floor slide while it
  // holds, so the slip alone does not say a joint broke: the caller that
  // knows the joints passes how many of those holding the storey's columns
  // broke (`broken_column_joints`) of how many there are (`column_joints`),
  // and the warning says which it was; -1 for both: not known, and the
  // warning names both causes.
  std::string slip_warning(std::size_t i, int broken_column_joints = -1, int column_joints = -1) const;
  // The warning for storey i, not collapsed, whose peak drift ratio of at
  // least half the safety limit came in the last kPeakAtEndFraction of a
  // run that ended at end_time_s: the drift was still growing when the run
  // ended, so the verdict holds for that window only; empty otherwise.
  std::string peak_at_end_warning(std::size_t i, double end_time_s) const;

 private:
  void record(std::size_t i, const Eigen::Vector2d& drift_m, double time_s);
  void record_peaks(std::size_t i, const Eigen::Vector2d& ratio, double time_s);
  void record_residual(std::size_t i, const Eigen::Vector2d& ratio);
  // Scratch of track(): each column's top and bottom point displacements
  // and the floor's displacement at its top (m), turned into the world once
  // per step for the drifts, the floor drift and the twist alike.
  std::vector<std::vector<Eigen::Vector2d>> top_m_, bottom_m_, floor_m_;
  // Per storey: the storey whose top level is its bottom level (-1: the
  // foundation), the columns of that storey whose tops carry this storey's
  // columns (the floor below, where this storey stands on it; all of them
  // where none does), and its top and bottom points' offsets from their
  // centre in the horizontal plane at t = 0 (m), with the farthest distance.
  std::vector<int> storey_below_;
  std::vector<std::vector<std::size_t>> columns_below_;
  struct TwistGeometry {
    std::vector<Eigen::Vector2d> top_r, bottom_r;
    double top_r2 = 0.0, bottom_r2 = 0.0, r_max = 0.0;
  };
  std::vector<TwistGeometry> twist_;

  std::vector<Storey> storeys_;
  AssessmentDef limits_;
  std::vector<StoreyDriftRecord> records_;
  std::vector<Eigen::Vector2d> drift_m_;
  // The residual's blocks (class comment): per storey, the complete
  // blocks' sums of the drift ratio, their running total, and the block
  // under way.
  struct ResidualBlocks {
    std::deque<Eigen::Vector2d> sums;
    Eigen::Vector2d total = Eigen::Vector2d::Zero();  // of `sums`
    Eigen::Vector2d open_sum = Eigen::Vector2d::Zero();
    std::int64_t open_steps = 0;
  };
  std::vector<ResidualBlocks> residual_;
  double dt_s_ = 0.0;
  std::int64_t block_steps_ = 1;
  std::size_t window_blocks_ = 1;
  std::int64_t last_step_ = -1;
};

}  // namespace fq
