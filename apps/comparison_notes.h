// The notes under the comparison table (comparison.md of `framequake
// compare`) that a retrofit decision needs beside the peaks and verdicts:
// in which order the storeys of each case collapsed, and each run's
// warnings. A retrofit probe braced frame A's first storey and read
// "collapsed / collapsed" for both frames in the table, while only
// summary.json said that the braced frame's second storey had fallen first
// (2.60 s) and its first storey after it; and a twist warning that would
// have made a storey collapsed was on the terminal only.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "io/case_runner.h"

namespace fq_app {

// One case of the comparison: its label and, for a run that produced a
// report, the report (nullptr otherwise).
using LabelledReport = std::pair<std::string, const fq::CaseRunReport*>;

// "\nStoreys collapsed, in the order they passed the collapse limit:\n- A:
// storey 1 at 3.170 s, storey 2 at 3.716 s\n" for the cases with a
// collapsed storey (collapse_time_s >= 0); "" when none collapsed. An
// unstable run is not listed: it is not assessed.
std::string collapse_order_note(const std::vector<LabelledReport>& cases);

// "\nWarnings of the runs (also in each summary.json):\n- A: text\n..."
// for the cases with warnings; "" when none has any.
std::string warnings_note(const std::vector<LabelledReport>& cases);

// The contact model of each case (contact.intact_nodes: "touch",
// "ground_only", "none"; "" for a case without contacts) listed under the
// table when any case with contacts is not on the default, touch: the
// verdicts depend on it (docs/performance.md, "Contacts across intact
// joints"), and the table does not show it. "" when every case is on touch.
using LabelledContactModel = std::pair<std::string, std::string>;
std::string contact_model_note(const std::vector<LabelledContactModel>& cases);

// Each case's integrator and time step, listed under the table when the
// cases do not all share both: the balance errors, and beyond round-off the
// motions, depend on them, and the table does not show them (a black-box
// probe compared rk4, velocity_verlet and central_difference runs whose
// balance errors of 1.5e-7, 1.7e-5 and 5.7e-9 nothing explained). "" when
// every case has the same integrator and dt_s.
struct CaseTimeIntegration {
  std::string label;
  std::string integrator;  // time.integrator's name
  double dt_s = 0.0;
};
std::string time_integration_note(const std::vector<CaseTimeIntegration>& cases);

// The ground motion each case ran under, always listed under the table: the
// verdicts compare frames only under the same shaking, and the table does
// not show it (an input probe compared a case under Takatori with one under
// El Centro and nothing said so). `motion` describes the records, axes,
// scales and window ("" for a case without ground motion); `identity` is
// the same with each record's whole path, by which the cases are compared
// (two records of one name in different folders differ); `pga_mps2` is the
// horizontal peak a completed run applied (NaN: it did not complete, so its
// peak may be that of part of the motion). One line when every case's
// motion is the same, a line per case otherwise.
struct CaseGroundMotion {
  std::string label;
  std::string motion;
  std::string identity;
  double pga_mps2 = 0.0;
};
std::string ground_motion_note(const std::vector<CaseGroundMotion>& cases);

}  // namespace fq_app
