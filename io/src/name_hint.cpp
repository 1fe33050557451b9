#include "io/name_hint.h"

#include <algorithm>
#include <cctype>

namespace fq {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // Rows i - 2, i - 1 and i of the table of distances between prefixes.
  std::vector<std::size_t> before(b.size() + 1), previous(b.size() + 1), row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    before.swap(previous);
    previous.swap(row);
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      row[j] = std::min({previous[j] + 1, row[j - 1] + 1, previous[j - 1] + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      // Two neighbouring letters swapped ("quite" for "quiet") count as one edit.
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) row[j] = std::min(row[j], before[j - 2] + 1);
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

std::vector<std::string> options_in_usage(std::string_view usage) {
  std::vector<std::string> options;
  // An option is the first word of a line of the usage's option list
  // ("  --out DIR   output folder"); "--option=value" in a sentence is not one.
  std::size_t line = 0;
  while (line < usage.size()) {
    std::size_t next = usage.find('\n', line);
    if (next == std::string_view::npos) next = usage.size();
    std::size_t at = usage.find_first_not_of(' ', line);
    if (at < next && usage.compare(at, 2, "--") == 0 && at + 2 < next &&
        std::isalpha(static_cast<unsigned char>(usage[at + 2]))) {
      std::size_t end = at + 2;
      while (end < next && (std::isalnum(static_cast<unsigned char>(usage[end])) || usage[end] == '-')) ++end;
      std::string option(usage.substr(at, end - at));
      if (std::find(options.begin(), options.end(), option) == options.end()) options.push_back(std::move(option));
    }
    line = next + 1;
  }
  return options;
}

std::optional<std::string> nearest_option(std::string_view given, std::string_view usage) {
  const std::vector<std::string> options = options_in_usage(usage);
  if (auto near = nearest_name(given, options)) return near;
  const std::string g = folded(given);
  // Else the longest option the word begins with ("--outline-color" is
  // "--outline", not "--out")...
  std::optional<std::string> found;
  std::size_t longest = 0;
  for (const std::string& o : options) {
    const std::string f = folded(o);
    if (g.size() > f.size() && f.size() > longest && g.compare(0, f.size(), f) == 0) found = o, longest = f.size();
  }
  if (found || g.size() < 3) return found;
  // ...else the one option that begins with the word.
  for (const std::string& o : options) {
    const std::string f = folded(o);
    if (f.size() <= g.size() || f.compare(0, g.size(), g) != 0) continue;
    if (found) return std::nullopt;
    found = o;
  }
  return found;
}

std::string did_you_mean(const std::optional<std::string>& hint) {
  return hint ? " (did you mean '" + *hint + "'?)" : "";
}

std::string unknown_option_message(std::string_view given, std::string_view usage) {
  return "unknown option '" + std::string(given) + "'" + did_you_mean(nearest_option(given, usage));
}

}  // namespace fq
