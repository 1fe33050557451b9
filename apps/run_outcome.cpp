// Terminal summary of one run (run_outcome.h).
#include "run_outcome.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "drift_fraction.h"
#include "io/storey_drift.h"

namespace fq_app {

std::string verdict_text(const fq::CaseRunReport& r, const fq::StoreyOutcome& s) {
  if (r.result.status == fq::RunStatus::Unstable) return "not assessed (unstable)";
  std::string text = fq::storey_verdict_name(s.verdict);
  if (r.result.status != fq::RunStatus::Completed && s.verdict != fq::StoreyVerdict::Collapsed) text += " so far";
  return text;
}

namespace {

// Six significant digits: a peak shown just under a limit must not read as
// the limit itself.
std::string number(double x) {
  std::ostringstream s;
  s << std::setprecision(6) << x;
  return s.str();
}

}  // namespace

std::string first_failure_outcome(const fq::CaseRunReport& r, const std::function<std::string(double)>& seconds) {
  const double failed_s = r.first_joint_failure_time_s, broke_s = r.first_joint_failure_break_time_s;
  if (broke_s == failed_s) return " broke at t = " + seconds(failed_s) + " s";
  if (std::isnan(broke_s)) return " lost a spring and held at t = " + seconds(failed_s) + " s";
  return " lost a spring at t = " + seconds(failed_s) + " s and broke at t = " + seconds(broke_s) + " s";
}

void print_run_outcome(const fq::CaseRunReport& r, std::ostream& out) {
  for (const fq::StoreyOutcome& s : r.storeys) {
    out << "framequake: storey " << s.number << " (" << number(s.height_m) << " m): peak drift ratio "
        << number(s.drift.peak_ratio_rad) << " rad";
    // 1/n, the form building codes state drift limits in; meaningless for
    // a storey that has fallen over.
    if (const std::string one_in_n = drift_one_in_n(
            s.drift.peak_ratio_rad, {r.assessment.safety_drift_ratio_rad, r.assessment.collapse_drift_ratio_rad});
        !one_in_n.empty() && s.drift.peak_ratio_rad <= r.assessment.collapse_drift_ratio_rad)
      out << " (" << one_in_n << ")";
    if (r.result.status != fq::RunStatus::Unstable) out << " at t = " << number(s.drift.peak_time_s) << " s";
    out << ", " << verdict_text(r, s);
    if (r.result.status != fq::RunStatus::Unstable && s.drift.collapse_time_s >= 0.0)
      out << " (reached the collapse limit at t = " << number(s.drift.collapse_time_s) << " s)";
    out << "\n";
  }
  if (!r.storeys.empty())
    out << "framequake: verdict limits: damaged beyond " << number(r.assessment.safety_drift_ratio_rad)
        << " rad, collapsed from " << number(r.assessment.collapse_drift_ratio_rad) << " rad\n";
  if (r.joint_count > 0) {
    out << "framequake: joints: " << r.joint_count << " (" << r.joints.intact << " elastic, " << r.joints.yielded
        << " yielded, " << r.joints.broken << " broken); first failure: ";
    if (r.first_joint_failure.empty())
      out << "none\n";
    else
      out << r.first_joint_failure << first_failure_outcome(r, number) << "\n";
  }
  out << "framequake: energy balance error " << number(r.energy_balance_error_relative)
      << " of the energy scale (summary.json \"energy\")\n";
}

}  // namespace fq_app
