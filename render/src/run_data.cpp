#include "render/run_data.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace fq::render {

namespace {

namespace fs = std::filesystem;

// Value of attribute `name` in one XML start tag, unescaped (the writer
// escapes & < > " ' in file names).
bool xml_attribute(const std::string& tag, const std::string& name, std::string& out_value) {
  const std::string key = " " + name + "=\"";
  const auto start = tag.find(key);
  if (start == std::string::npos) return false;
  const auto begin = start + key.size();
  const auto end = tag.find('"', begin);
  if (end == std::string::npos) return false;
  const std::string raw = tag.substr(begin, end - begin);
  out_value.clear();
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (raw[i] != '&') {
      out_value.push_back(raw[i]);
      continue;
    }
    static const std::pair<const char*, char> entities[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    bool matched = false;
    for (const auto& [text, c] : entities)
      if (raw.compare(i, std::char_traits<char>::length(text), text) == 0) {
        out_value.push_back(c);
        i += std::char_traits<char>::length(text) - 1;
        matched = true;
        break;
      }
    if (!matched) return false;
  }
  return true;
}

bool parse_double(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && errno != ERANGE;
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

void strip_cr(std::string& line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
}

std::vector<RunFrame> read_pvd(const fs::path& folder) {
  const fs::path pvd = folder / "case.pvd";
  std::ifstream in(pvd, std::ios::binary);
  if (!in)
    throw RenderInputError("'" + pvd.string() + "' not found: expected the output folder of `framequake run` (it holds case.pvd)");
  std::stringstream buf;
  buf << in.rdbuf();
  const std::string doc = buf.str();
  if (doc.find("<VTKFile") == std::string::npos || doc.find("type=\"Collection\"") == std::string::npos)
    throw RenderInputError("'" + pvd.string() + "' is not a ParaView collection (VTKFile type=\"Collection\")");
  std::vector<RunFrame> frames;
  for (std::size_t pos = doc.find("<DataSet"); pos != std::string::npos; pos = doc.find("<DataSet", pos + 1)) {
    const auto end = doc.find('>', pos);
    if (end == std::string::npos) throw RenderInputError("'" + pvd.string() + "': unterminated DataSet element");
    const std::string tag = doc.substr(pos, end - pos);
    std::string t, file;
    RunFrame f;
    if (!xml_attribute(tag, "timestep", t) || !parse_double(t, f.time_s) || !xml_attribute(tag, "file", file))
      throw RenderInputError("'" + pvd.string() + "': DataSet element without a numeric timestep and a file: " + tag);
    f.file = folder / file;
    if (!fs::exists(f.file))
      throw RenderInputError("'" + pvd.string() + "' lists '" + file + "', which does not exist in " + folder.string());
    frames.push_back(std::move(f));
  }
  if (frames.empty()) throw RenderInputError("'" + pvd.string() + "' lists no frames (was the run stopped before the first frame?)");
  std::stable_sort(frames.begin(), frames.end(), [](const RunFrame& a, const RunFrame& b) { return a.time_s < b.time_s; });
  return frames;
}

void read_history(const fs::path& folder, RunData& run) {
  const fs::path file = folder / "history.csv";
  std::ifstream in(file, std::ios::binary);
  if (!in) return;  // optional: no trace is drawn
  std::string line;
  if (!std::getline(in, line)) return;
  strip_cr(line);
  const std::vector<std::string> header = split_csv(line);
  int time_col = -1, accel_col[3] = {-1, -1, -1};
  static const char* accel_names[3] = {"ground_accel_x_mps2", "ground_accel_y_mps2", "ground_accel_z_mps2"};
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (header[c] == "time_s") time_col = int(c);
    for (int k = 0; k < 3; ++k)
      if (header[c] == accel_names[k]) accel_col[k] = int(c);
  }
  if (time_col < 0) throw RenderInputError("'" + file.string() + "': no time_s column in the header");
  std::size_t line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    strip_cr(line);
    if (line.empty()) continue;
    const std::vector<std::string> cells = split_csv(line);
    // A run killed mid-write may leave a short last row: stop there.
    if (cells.size() != header.size()) break;
    double t = 0.0;
    if (!parse_double(cells[std::size_t(time_col)], t))
      throw RenderInputError("'" + file.string() + "' line " + std::to_string(line_no) + ": time_s is not a number");
    run.history_time_s.push_back(t);
    for (int k = 0; k < 3; ++k) {
      if (accel_col[k] < 0) continue;
      double a = 0.0;
      if (!parse_double(cells[std::size_t(accel_col[k])], a))
        throw RenderInputError("'" + file.string() + "' line " + std::to_string(line_no) + ": " + accel_names[k] +
                               " is not a number");
      run.ground_accel_mps2[k].push_back(a);
    }
  }
}

void read_events(const fs::path& folder, RunData& run) {
  const fs::path file = folder / "events.csv";
  std::ifstream in(file, std::ios::binary);
  if (!in) return;
  std::string line;
  if (!std::getline(in, line)) return;
  strip_cr(line);
  const std::vector<std::string> header = split_csv(line);
  const auto col = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : int(it - header.begin());
  };
  const int time_col = col("time_s"), kind_col = col("kind"), joint_col = col("joint_id");
  if (time_col < 0 || kind_col < 0 || joint_col < 0)
    throw RenderInputError("'" + file.string() + "': expected columns time_s, kind and joint_id in the header");
  while (std::getline(in, line)) {
    strip_cr(line);
    const std::vector<std::string> cells = split_csv(line);
    if (cells.size() != header.size()) break;
    if (cells[std::size_t(kind_col)] != "joint_broken") continue;
    JointBreak b;
    double id = 0.0;
    if (!parse_double(cells[std::size_t(time_col)], b.time_s) || !parse_double(cells[std::size_t(joint_col)], id))
      throw RenderInputError("'" + file.string() + "': a joint_broken row without numeric time_s and joint_id");
    b.joint_id = int(id);
    run.breaks.push_back(b);
  }
}

}  // namespace

RunData load_run(const fs::path& folder) {
  if (!fs::is_directory(folder))
    throw RenderInputError("'" + folder.string() + "' is not a folder: expected the output folder of `framequake run`");
  RunData run;
  run.folder = folder;
  const fs::path clean = folder.lexically_normal();
  run.label = (clean.has_filename() ? clean.filename() : clean.parent_path().filename()).string();
  run.frames = read_pvd(folder);
  read_history(folder, run);
  read_events(folder, run);
  return run;
}

}  // namespace fq::render
