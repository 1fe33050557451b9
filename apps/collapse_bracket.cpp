#include "collapse_bracket.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace fq_app {

CollapseBracket bracket_collapse(std::vector<ScaleRun> runs) {
  std::sort(runs.begin(), runs.end(), [](const ScaleRun& a, const ScaleRun& b) { return a.scale < b.scale; });
  CollapseBracket b;
  for (const ScaleRun& r : runs) {
    b.largest_completed = r.scale;
    if (r.collapsed_storeys.empty()) {
      if (std::isnan(b.smallest_collapse))
        b.largest_stood = r.scale;
      else
        b.stood_above_collapse.push_back(r.scale);
    } else if (std::isnan(b.smallest_collapse)) {
      b.smallest_collapse = r.scale;
      b.pga_at_collapse_mps2 = r.pga_mps2;
      b.storeys_at_collapse = r.collapsed_storeys;
    }
  }
  return b;
}

std::string stood_above_collapse_csv(const CollapseBracket& b) {
  std::ostringstream s;
  s << std::setprecision(9);
  for (std::size_t k = 0; k < b.stood_above_collapse.size(); ++k) s << (k ? " " : "") << b.stood_above_collapse[k];
  return s.str();
}

std::string non_monotonic_note(const std::string& case_name, const std::string& record, const CollapseBracket& b) {
  if (b.stood_above_collapse.empty()) return "";
  std::ostringstream s;
  s << std::setprecision(6) << "- " << case_name << ", " << record << ": not monotonic: collapsed at "
    << b.smallest_collapse << " but stood at ";
  for (std::size_t k = 0; k < b.stood_above_collapse.size(); ++k)
    s << (k == 0 ? "" : k + 1 == b.stood_above_collapse.size() ? " and " : ", ") << b.stood_above_collapse[k];
  s << "; the two scale columns bracket the smallest collapse only, not a threshold above which it always "
       "collapses";
  return s.str();
}

}  // namespace fq_app
