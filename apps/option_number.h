// Numbers given to command-line options (--threads, --jobs, --scales,
// --window-length, --checkpoint-every), read as the case file reads its
// numbers (io/src/case_file.cpp, std::from_chars): decimal only. strtod and
// strtol also took hexadecimal ("--scales 0x1" ran a scale of 1 in a
// folder "..._x1", while the case file refuses 0x10), leading spaces and
// "inf"/"nan" spellings. Anything else is a usage error naming the value.
#pragma once

#include <string>

namespace fq_app {

// A whole number from `lo` to `hi` in decimal digits (an optional '-'; no
// sign '+', spaces, exponent or hexadecimal), else usage_error
// "OPTION expects a whole number from LO to HI, got 'TEXT'" with `usage`.
int whole_number_option(const std::string& option, const std::string& text, int lo, int hi, const char* usage);

// A finite decimal number > 0 (an optional leading '+', digits, a '.' and an
// exponent "e-3" as in the case file), else usage_error
// "OPTION expects a positive number, got 'TEXT'" with `usage`.
double positive_number_option(const std::string& option, const std::string& text, const char* usage);

// The same checks without the error: whether `text` is such a number.
bool read_whole_number(const std::string& text, long& out);
bool read_decimal_number(const std::string& text, double& out);

}  // namespace fq_app
