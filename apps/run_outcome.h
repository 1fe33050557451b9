// What a finished run of one case says on the terminal: its storeys' peak
// drift ratios and verdicts, its joints and its energy balance, so that a
// user of `framequake run` or `resume` learns the result without opening
// summary.json. The studies (study_commands.cpp) share the verdict wording.
#pragma once

#include <functional>
#include <ostream>
#include <string>

#include "io/case_runner.h"

namespace fq_app {

// A storey's verdict as the terminal and the tables print it. A run stopped
// before its end has collapsed for good if it collapsed, but is standing or
// damaged only "so far": the rest of the record might have changed that. A
// run that became unstable is not assessed: its drifts after the blow-up are
// the arithmetic's, not the structure's (a probe's unstable portal read
// "collapsed, 0.7583").
std::string verdict_text(const fq::CaseRunReport& r, const fq::StoreyOutcome& s);

// What became of the first joint to fail, after its label: " broke at t =
// A s", " lost a spring at t = A s and broke at t = B s", or " lost a spring
// and held at t = A s" (it never broke), each time written by `seconds`.
std::string first_failure_outcome(const fq::CaseRunReport& r, const std::function<std::string(double)>& seconds);

// One line per storey, one for the joints (when the case has any) and one
// for the energy balance, each starting "framequake: ".
void print_run_outcome(const fq::CaseRunReport& r, std::ostream& out);

}  // namespace fq_app
