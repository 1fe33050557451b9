// The collapse scales of a sweep's case and record (collapse_scales.csv,
// .md): the smallest amplitude scale at which a storey collapsed and the
// largest below it that stood, from the runs that completed. A frame's
// response need not grow with the scale (a record scaled up can miss the
// resonance that wrecked it at a smaller scale): a scale above the
// smallest collapse that stood makes the pair read as a threshold it is
// not, so those scales are listed too (acceptance probe).
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace fq_app {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One completed run of a case and record.
struct ScaleRun {
  double scale = 0.0;
  double pga_mps2 = 0.0;
  std::string collapsed_storeys;  // "1 2"; empty when none collapsed
};

struct CollapseBracket {
  double largest_completed = kNaN;      // NaN: no run completed
  double largest_stood = kNaN;          // largest scale below the smallest collapse that stood (NaN: none)
  double smallest_collapse = kNaN;      // NaN: none collapsed
  double pga_at_collapse_mps2 = kNaN;
  std::string storeys_at_collapse;
  std::vector<double> stood_above_collapse;  // ascending; non-empty: the results are not monotonic
};

// The bracket of `runs` (completed runs, in any order).
CollapseBracket bracket_collapse(std::vector<ScaleRun> runs);

// The scales that stood above the smallest collapse, space-separated, as
// the csv column stood_above_collapse writes them ("" when monotonic).
std::string stood_above_collapse_csv(const CollapseBracket& b);

// The footnote line of collapse_scales.md for a non-monotonic case and
// record ("" when monotonic).
std::string non_monotonic_note(const std::string& case_name, const std::string& record, const CollapseBracket& b);

}  // namespace fq_app
