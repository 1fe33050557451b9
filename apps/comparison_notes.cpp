#include "comparison_notes.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

namespace fq_app {

std::string collapse_order_note(const std::vector<LabelledReport>& cases) {
  std::string lines;
  for (const auto& [label, report] : cases) {
    // An unstable run's drifts after the blow-up are the arithmetic's, not
    // the structure's: it is not assessed (the table says so), and is no
    // collapse (a probe's forced run read "unstable: storey 1 at 0.004 s").
    if (report == nullptr || report->result.status == fq::RunStatus::Unstable) continue;
    std::vector<std::pair<double, int>> fallen;  // (collapse time, storey number)
    for (const fq::StoreyOutcome& s : report->storeys)
      if (s.drift.collapse_time_s >= 0.0) fallen.emplace_back(s.drift.collapse_time_s, s.number);
    if (fallen.empty()) continue;
    std::sort(fallen.begin(), fallen.end());  // by time, then storey number
    lines += "- " + label + ":";
    for (std::size_t k = 0; k < fallen.size(); ++k) {
      char time[32];
      std::snprintf(time, sizeof time, "%.3f", fallen[k].first);
      lines += std::string(k ? "," : "") + " storey " + std::to_string(fallen[k].second) + " at " + time + " s";
    }
    lines += "\n";
  }
  if (lines.empty()) return {};
  return "\nStoreys collapsed, in the order they passed the collapse limit (a storey that falls first is the weak "
         "one, whatever the peaks):\n" +
         lines;
}

std::string warnings_note(const std::vector<LabelledReport>& cases) {
  std::string lines;
  for (const auto& [label, report] : cases) {
    if (report == nullptr) continue;
    for (const std::string& w : report->warnings) lines += "- " + label + ": " + w + "\n";
  }
  if (lines.empty()) return {};
  return "\nWarnings of the runs (also in each run's summary.json, `warnings`):\n" + lines;
}

std::string contact_model_note(const std::vector<LabelledContactModel>& cases) {
  const bool all_default = std::all_of(cases.begin(), cases.end(), [](const LabelledContactModel& c) {
    return c.second.empty() || c.second == "touch";
  });
  if (all_default) return {};
  std::string lines;
  for (const auto& [label, model] : cases)
    lines += "- " + label + ": " + (model.empty() ? std::string("no contacts") : model) + "\n";
  return "\nContact across intact joints (`contact.intact_nodes`, cases/README.md; the verdicts depend on it):\n" +
         lines;
}

std::string time_integration_note(const std::vector<CaseTimeIntegration>& cases) {
  const bool alike = std::all_of(cases.begin(), cases.end(), [&](const CaseTimeIntegration& c) {
    return c.integrator == cases.front().integrator && c.dt_s == cases.front().dt_s;
  });
  if (alike) return {};
  std::string lines;
  for (const CaseTimeIntegration& c : cases) {
    // The shortest text that reads back as the same double: two steps that
    // differ are never printed alike.
    char dt[32];
    const auto end = std::to_chars(dt, dt + sizeof dt, c.dt_s, std::chars_format::general).ptr;
    lines += "- " + c.label + ": " + c.integrator + ", dt_s = " + std::string(dt, end) + " s\n";
  }
  return "\nTime integration (`time.integrator`, `time.dt_s`; the balance errors, and beyond round-off the motions, "
         "depend on them):\n" +
         lines;
}

std::string ground_motion_note(const std::vector<CaseGroundMotion>& cases) {
  if (cases.empty()) return {};
  auto peak = [](double pga_mps2) -> std::string {
    if (std::isnan(pga_mps2)) return "";
    if (!(pga_mps2 > 0.0)) return "; no horizontal acceleration";
    char text[96];
    std::snprintf(text, sizeof text, "; horizontal PGA %.3g m/s² (%.3g g)", pga_mps2,
                  pga_mps2 / fq::kStandardGravity_mps2);
    return text;
  };
  auto described = [](const CaseGroundMotion& c) { return c.motion.empty() ? std::string("none") : c.motion; };
  const bool alike = std::all_of(cases.begin(), cases.end(),
                                 [&](const CaseGroundMotion& c) { return c.identity == cases.front().identity; });
  if (alike) {
    // The peak of a case that completed (the same motion, applied whole,
    // gives the same peak).
    double pga = std::numeric_limits<double>::quiet_NaN();
    for (const CaseGroundMotion& c : cases)
      if (!std::isnan(c.pga_mps2)) {
        pga = c.pga_mps2;
        break;
      }
    return "\nGround motion (every case): " + described(cases.front()) + peak(pga) + "\n";
  }
  std::string lines;
  for (const CaseGroundMotion& c : cases) lines += "- " + c.label + ": " + described(c) + peak(c.pga_mps2) + "\n";
  return "\nGround motion of each case (they differ: the verdicts compare the frames under different shaking):\n" +
         lines;
}

}  // namespace fq_app
