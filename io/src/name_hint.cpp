#include "io/name_hint.h"

#include <algorithm>
#include <cctype>

namespace fq {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diag = up;
    }
  }
  return row[b.size()];
}

namespace {
// Lower case, without the separators users vary.
std::string folded(std::string_view s) {
  std::string out;
  for (const char c : s)
    if (c != '_' && c != '-' && c != ' ') out += char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}
}  // namespace

std::optional<std::string> nearest_name(std::string_view given, const std::vector<std::string>& names) {
  const std::string g = folded(given);
  if (g.empty()) return std::nullopt;
  for (const std::string& n : names)
    if (folded(n) == g) return n;
  for (const std::string& n : names)
    if (edit_distance(folded(n), g) <= 2) return n;
  return std::nullopt;
}

}  // namespace fq
