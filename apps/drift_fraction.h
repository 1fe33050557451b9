// A drift ratio in the form building codes state drift limits in, "1/n"
// (1/120 for 0.00833 rad), for the terminal's summary of a run.
#pragma once

#include <string>
#include <vector>

namespace fq_app {

// "1/n" with n = round(1 / ratio_rad) for a ratio of at least 1e-9 rad
// (n up to 1e9); "" for a smaller, zero, negative or non-finite ratio. A
// drift below a nanoradian says nothing as 1/n, and 1 / ratio overflowed
// the integer it was rounded to below about 1e-19 rad (a still frame's
// round-off drift of 2.8e-22 rad printed "1/-9223372036854775808", probe).
// n gets as many decimals (up to 6) as it takes to stay on the ratio's side
// of each of `limits_rad` (the verdict limits): 0.032884 rad is 1/30.4,
// not "1/30", beside a damage limit of 1/30 it is below (input probe,
// stop 41).
std::string drift_one_in_n(double ratio_rad, const std::vector<double>& limits_rad = {});

}  // namespace fq_app
