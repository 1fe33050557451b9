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
  // The closest after folding (0 edits: the same name), within two edits,
  // and within one of a name of fewer than six letters ("r", "ok" and "4"
  // are not "rk4"; review probe).
  std::optional<std::string> best;
  std::size_t best_distance = 3;
  for (const std::string& n : names) {
    const std::string f = folded(n);
    const std::size_t d = edit_distance(f, g), allowed = f.size() < 6 ? 1 : 2;
    if (d <= allowed && d < best_distance) best = n, best_distance = d;
  }
  return best;
}

}  // namespace fq
