#include "compare_rounds_core.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <sstream>

namespace fq::bench {

namespace {

SittingFormatError format_error(const std::string& source, int line, const std::string& what) {
  std::ostringstream m;
  m << source << ":" << line << ": " << what;
  return SittingFormatError(m.str());
}

}  // namespace

double parse_counter_value(const std::string& text) {
  if (text.empty()) throw std::invalid_argument("empty value");
  double scale = 1.0;
  std::string digits = text;
  switch (text.back()) {
    case 'k': scale = 1e3; break;
    case 'M': scale = 1e6; break;
    case 'G': scale = 1e9; break;
    case 'T': scale = 1e12; break;
    default: break;
  }
  if (scale != 1.0) digits.pop_back();
  if (digits.empty()) throw std::invalid_argument("'" + text + "' is not a number");
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(digits.c_str(), &end);
  if (end != digits.c_str() + digits.size() || errno == ERANGE)
    throw std::invalid_argument("'" + text + "' is not a number");
  return v * scale;
}

Sitting parse_sitting(std::istream& in, const std::string& source) {
  Sitting s;
  std::string line, build;
  int round = -1, number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("## round", 0) == 0) {
      std::istringstream words(line);
      std::string hashes, word_round, word_build;
      if (!(words >> hashes >> word_round >> round >> word_build >> build) || word_build != "build")
        throw format_error(source, number, "expected '## round <number> build <name>'");
      continue;
    }
    if (line.rfind("BM_", 0) != 0) continue;
    if (build.empty()) throw format_error(source, number, "a benchmark line before the first '## round' marker");
    std::istringstream words(line);
    BenchLine b;
    words >> b.name;
    std::string word, exact_hash;
    while (words >> word) {
      const auto eq = word.find('=');
      if (eq == std::string::npos || eq == 0) continue;  // the time columns and their units
      const std::string key = word.substr(0, eq), value = word.substr(eq + 1);
      if (key == "state_hash") {
        b.state_hash = value;
        continue;
      }
      // The whole hash in the benchmark's label (bench_support.h): the
      // counter's six digits stand in for it only in older files.
      if (key == "state_hash_hex") {
        exact_hash = value;
        continue;
      }
      try {
        b.counters[key] = parse_counter_value(value);
      } catch (const std::invalid_argument& e) {
        throw format_error(source, number, "counter " + key + ": " + e.what());
      }
    }
    if (!exact_hash.empty()) b.state_hash = exact_hash;
    auto& rounds = s.runs[build][b.name];
    if (!rounds.emplace(round, b).second) {
      std::ostringstream m;
      m << "a second line for " << b.name << " in round " << round << " of build " << build;
      throw format_error(source, number, m.str());
    }
  }
  return s;
}

double median(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("median of no values");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Comparison compare_builds(const Sitting& sitting, const std::string& old_build, const std::string& new_build,
                          const std::vector<std::string>& counters) {
  const auto old_it = sitting.runs.find(old_build), new_it = sitting.runs.find(new_build);
  if (old_it == sitting.runs.end()) throw std::invalid_argument("no runs of build '" + old_build + "'");
  if (new_it == sitting.runs.end()) throw std::invalid_argument("no runs of build '" + new_build + "'");
  const auto& old_runs = old_it->second;
  const auto& new_runs = new_it->second;
  Comparison c;
  for (const auto& [name, rounds] : new_runs)
    if (!old_runs.count(name)) c.only_in_one.push_back(name + " (only " + new_build + ")");
  for (const auto& [name, old_rounds] : old_runs) {
    const auto nit = new_runs.find(name);
    if (nit == new_runs.end()) {
      c.only_in_one.push_back(name + " (only " + old_build + ")");
      continue;
    }
    const auto& new_rounds = nit->second;
    for (const std::string& counter : counters) {
      std::vector<double> o, n, ratios;
      for (const auto& [r, line] : old_rounds)
        if (auto v = line.counters.find(counter); v != line.counters.end()) o.push_back(v->second);
      for (const auto& [r, line] : new_rounds) {
        const auto v = line.counters.find(counter);
        if (v == line.counters.end()) continue;
        n.push_back(v->second);
        const auto same_round = old_rounds.find(r);
        if (same_round == old_rounds.end()) continue;
        const auto ov = same_round->second.counters.find(counter);
        if (ov != same_round->second.counters.end() && ov->second != 0.0) ratios.push_back(v->second / ov->second);
      }
      if (o.empty() || n.empty()) continue;
      CounterComparison cc;
      cc.benchmark = name;
      cc.counter = counter;
      cc.old_runs = int(o.size());
      cc.new_runs = int(n.size());
      cc.old_median = median(o);
      cc.new_median = median(n);
      cc.paired_rounds = int(ratios.size());
      if (!ratios.empty()) {
        cc.ratio_median = median(ratios);
        cc.ratio_min = *std::min_element(ratios.begin(), ratios.end());
        cc.ratio_max = *std::max_element(ratios.begin(), ratios.end());
      }
      c.counters.push_back(cc);
    }
    HashCheck h;
    h.benchmark = name;
    for (const auto& [r, line] : old_rounds)
      if (!line.state_hash.empty()) h.old_hashes.insert(line.state_hash);
    for (const auto& [r, line] : new_rounds)
      if (!line.state_hash.empty()) h.new_hashes.insert(line.state_hash);
    if (!h.old_hashes.empty() || !h.new_hashes.empty()) c.hashes.push_back(h);
  }
  return c;
}

}  // namespace fq::bench
