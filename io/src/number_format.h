// Private to io: the one way output files print a double. Shortest text that
// reads back to the same double (std::to_chars), so CSV and JSON values can
// be compared bitwise with what the engine held; no locale involved.
#pragma once

#include <charconv>
#include <cstdint>
#include <string>
#include <system_error>

namespace fq::detail {

inline void append_number(std::string& out, double x) {
  char buf[32];  // shortest double form is at most 24 characters
  const auto res = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, res.ptr);
}

inline void append_integer(std::string& out, std::int64_t i) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof buf, i);
  out.append(buf, res.ptr);
}

inline std::string format_number(double x) {
  std::string s;
  append_number(s, x);
  return s;
}

}  // namespace fq::detail
