// A drift ratio in the form building codes state drift limits in, "1/n"
// (1/120 for 0.00833 rad), for the terminal's summary of a run.
#pragma once

#include <string>

namespace fq_app {

// "1/n" with n = round(1 / ratio_rad) for a ratio of at least 1e-9 rad
// (n up to 1e9); "" for a smaller, zero, negative or non-finite ratio. A
// drift below a nanoradian says nothing as 1/n, and 1 / ratio overflowed
// the integer it was rounded to below about 1e-19 rad (a still frame's
// round-off drift of 2.8e-22 rad printed "1/-9223372036854775808", probe).
std::string drift_one_in_n(double ratio_rad);

}  // namespace fq_app
