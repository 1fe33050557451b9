#include "option_number.h"

#include <charconv>
#include <cmath>
#include <string_view>
#include <system_error>

#include "usage_error.h"

namespace fq_app {

bool read_whole_number(const std::string& text, long& out) {
  const char* const first = text.data();
  const char* const last = first + text.size();
  const auto [end, ec] = std::from_chars(first, last, out);
  return !text.empty() && ec == std::errc() && end == last;
}

bool read_decimal_number(const std::string& text, double& out) {
  std::string_view s = text;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);  // as the case file's numbers
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return !s.empty() && ec == std::errc() && end == s.data() + s.size() && std::isfinite(out);
}

int whole_number_option(const std::string& option, const std::string& text, int lo, int hi, const char* usage) {
  long n = 0;
  if (!read_whole_number(text, n) || n < lo || n > hi)
    usage_error(option + " expects a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                    ", got '" + text + "'",
                usage);
  return int(n);
}

double positive_number_option(const std::string& option, const std::string& text, const char* usage) {
  double v = 0.0;
  if (!read_decimal_number(text, v) || !(v > 0.0)) usage_error(option + " expects a positive number, got '" + text + "'", usage);
  return v;
}

}  // namespace fq_app
