// `framequake compare` and `framequake sweep` through the real binary: the
// files they promise, tables that agree with the runs' own time histories,
// the peak ground acceleration against the record's documented peak, and
// bad input refused before anything is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iomanip>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "app_process.h"
#include "hanger_case.h"
#include "forced_cube_case.h"

namespace {

namespace fs = std::filesystem;
using fq_test::read_text;
using fq_test::run_app;
using fq_test::TempDir;

const fs::path kSource = FQ_SOURCE_DIR;

// A 0.1 m spruce cube resting on the ground (contacts of restitution 0.5,
// friction 0.4): `head` lines after the format line (a name), the time
// section's flow map, `extra` lines before the blocks, and the
// ground_motion section's lines.
std::string cube_case(const std::string& head, const std::string& time, const std::string& extra,
                      const std::string& ground_motion) {
  std::string text = "framequake_case: 1\n";
  text.append(head).append("time: ").append(time).append("\n");
  text.append("materials: [{name: spruce, density_kg_per_m3: 450}]\n").append(extra);
  text.append("blocks: [{id: cube, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.05], material: spruce}]\n");
  text.append("contact:\n  ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.5, friction_coefficient: 0.4}\n");
  text.append("ground_motion:\n").append(ground_motion);
  return text;
}

// Its ground_motion lines for the JMA Kobe NS record along `axis`.
std::string kobe_ns_along(const std::string& axis) {
  std::string text = "  components:\n    - {file: ";
  text.append((kSource / "cases/ground_motions/RSN1106_KOBE_KJM000.AT2").string())
      .append(", format: peer_at2, axis: ")
      .append(axis)
      .append("}\n");
  return text;
}

// `text` with the first `from` replaced by `to`; a test failure naming
// `from` when the text does not hold it (a shipped case that changed).
void replace_once(std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos) {
    ADD_FAILURE() << "the text does not hold \"" << from << "\"";
    return;
  }
  text.replace(at, from.size(), to);
}

// The shipped case cases/<file> with its record read by absolute path, so
// that a copy written into a test's folder reads the same record, and then
// `edits` (from, to) applied in order, each once.
std::string shipped_case_elsewhere(const std::string& file,
                                   std::initializer_list<std::pair<std::string, std::string>> edits = {}) {
  std::string text = read_text(kSource / "cases" / file);
  replace_once(text, "file: ground_motions/", "file: " + (kSource / "cases/ground_motions").string() + "/");
  for (const auto& [from, to] : edits) replace_once(text, from, to);
  return text;
}

using Table = std::vector<std::map<std::string, std::string>>;

Table read_csv(const fs::path& file) {
  std::stringstream in(read_text(file));
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    return cells;
  };
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line);
  Table rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

// Largest |(ratio_x, ratio_y)| of storey 1 over a run's history.csv rows.
double peak_storey1_ratio_from_history(const fs::path& history) {
  std::stringstream in(read_text(history));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::stringstream h(line);
    for (std::string c; std::getline(h, c, ',');) header.push_back(c);
  }
  const auto col = [&](const std::string& n) { return std::size_t(std::find(header.begin(), header.end(), n) - header.begin()); };
  const std::size_t ix = col("storey1_drift_ratio_x_rad"), iy = col("storey1_drift_ratio_y_rad");
  EXPECT_LT(ix, header.size());
  EXPECT_LT(iy, header.size());
  double peak = 0.0;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream r(line);
    for (std::string c; std::getline(r, c, ',');) v.push_back(std::stod(c));
    peak = std::max(peak, std::hypot(v[ix], v[iy]));
  }
  return peak;
}

// A PNG holding only a tEXt chunk `key`=`text` (CRCs left zero: framequake
// reads the chunks, it does not check them), enough to tell by its text.
std::string png_with_text(const std::string& key, const std::string& text) {
  auto chunk = [](const std::string& type, const std::string& data) {
    const auto n = std::uint32_t(data.size());
    std::string c{char(n >> 24), char(n >> 16 & 0xff), char(n >> 8 & 0xff), char(n & 0xff)};
    return c + type + data + std::string(4, '\0');
  };
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("tEXt", key + std::string(1, '\0') + text) + chunk("IEND", "");
}

bool is_png(const fs::path& file) {
  const std::string head = read_text(file).substr(0, 8);
  return head == std::string("\x89PNG\r\n\x1a\n", 8);
}

// The text of a PNG's tEXt chunk `key` ("" when there is none).
std::string png_text(const fs::path& file, const std::string& key) {
  const std::string bytes = read_text(file);
  std::size_t at = 8;  // after the signature
  while (at + 12 <= bytes.size()) {
    const auto byte = [&](std::size_t i) { return std::uint32_t(static_cast<unsigned char>(bytes[i])); };
    const std::uint32_t length = byte(at) << 24 | byte(at + 1) << 16 | byte(at + 2) << 8 | byte(at + 3);
    const std::string type = bytes.substr(at + 4, 4);
    if (at + 12 + length > bytes.size()) break;
    if (type == "tEXt") {
      const std::string data = bytes.substr(at + 8, length);
      const std::size_t nul = data.find('\0');
      if (nul != std::string::npos && data.substr(0, nul) == key) return data.substr(nul + 1);
    }
    at += 12 + length;
  }
  return "";
}

TEST(StudyCommands, CompareWritesEachRunTheTableAndTheFigure) {
  TempDir dir;
  const fs::path out = dir.path() / "cmp";
  const auto r = run_app({"compare", (kSource / "cases/demo_portal_frame.yaml").string(),
                          (kSource / "cases/demo_falling_block.yaml").string(), "--out", out.string(),
                          "--window-length", "0.5"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"demo_portal_frame", "demo_falling_block"}) {
    EXPECT_TRUE(fs::exists(out / name / "case.pvd")) << name;
    EXPECT_TRUE(fs::exists(out / name / "summary.json")) << name;
  }
  const Table rows = read_csv(out / "comparison.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("case"), "demo_portal_frame");
  EXPECT_EQ(rows[1].at("case"), "demo_falling_block");
  EXPECT_EQ(rows[0].at("status"), "completed");
  // The table's peak is the run's, taken at every step: at least the
  // largest drift ratio of its 1 ms history rows, and above it by no more
  // than a sway of period T sampled every 1 ms can miss its crest by,
  // 1 - cos(pi 0.001 / T): 5e-4 of the peak for T >= 0.1 s (this frame's
  // upward zero crossings of the drift lie 0.13-0.32 s apart).
  const double peak = std::stod(rows[0].at("storey1_peak_drift_ratio_rad"));
  EXPECT_GT(peak, 0.0);
  const double rows_peak = peak_storey1_ratio_from_history(out / "demo_portal_frame/history.csv");
  EXPECT_GE(peak, rows_peak * (1.0 - 1e-9));
  EXPECT_LE(peak, rows_peak * (1.0 + 5e-4));
  EXPECT_EQ(rows[1].at("storey1_peak_drift_ratio_rad"), "");  // blocks have no storeys
  // Each row names how its run was integrated: both demo cases give
  // dt_s: 1.0e-5 and no time.integrator (central difference, the default).
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("integrator"), "central_difference");
    EXPECT_EQ(std::stod(row.at("dt_s")), 1.0e-5);
  }
  // --window-length is a quick look also for a case that runs on after its
  // motion: the falling-block demo's duration_s of 1 s stops with the
  // 0.5 s window (time scale 1).
  std::smatch m;
  const std::string block_summary = read_text(out / "demo_falling_block/summary.json");
  ASSERT_TRUE(std::regex_search(block_summary, m, std::regex("\"simulated_time_s\": ([0-9.eE+-]+)")));
  EXPECT_NEAR(std::stod(m[1]), 0.5, 1e-3);
  const std::string md = read_text(out / "comparison.md");
  EXPECT_NE(md.find("| demo_portal_frame | completed |"), std::string::npos) << md;
  EXPECT_NE(r.out.find("| demo_portal_frame |"), std::string::npos);  // the table is also printed
  EXPECT_TRUE(is_png(out / "first_storey_drift.png"));
  EXPECT_EQ(r.err.find("warning:"), std::string::npos) << "sound runs carry no warnings: " << r.err;
}

// A forced run's warnings (io/case_runner.h, kWarn*) are printed under its
// line (the case: forced_cube_case.h).
TEST(StudyCommands, CompareShowsTheWarningsOfAForcedRun) {
  TempDir dir;
  std::ofstream(dir.path() / "cube.yaml") << fq_test::kForcedCubeCase;
  const fs::path out = dir.path() / "cmp";
  const auto r = run_app({"compare", (dir.path() / "cube.yaml").string(), "--out", out.string(), "--force",
                          "--no-figure"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("cube: completed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("\n  warning: dt_s = 0.001 s is 4.2"), std::string::npos) << r.err;
  // ... and comparison.md keeps it under the table (apps/comparison_notes.h).
  const std::string md = fq_test::read_text(out / "comparison.md");
  EXPECT_NE(md.find("\nWarnings of the runs (also in each run's summary.json, `warnings`):\n- cube: dt_s = 0.001 s is 4.2"),
            std::string::npos)
      << md;
}

// Two cases of different time steps: comparison.md lists each case's
// integrator and dt_s under the table (apps/comparison_notes.h), which it
// did not (black-box probe).
TEST(StudyCommands, CompareNamesEachCasesIntegratorAndStepWhenTheyDiffer) {
  TempDir dir;
  std::string finer = fq_test::kForcedCubeCase;
  const std::string coarse_time = "time: {dt_s: 1.0e-3,", name = "name: cube\n";
  ASSERT_NE(finer.find(coarse_time), std::string::npos);
  finer.replace(finer.find(coarse_time), coarse_time.size(), "time: {dt_s: 5.0e-4,");
  finer.replace(finer.find(name), name.size(), "name: cube_fine\n");
  std::ofstream(dir.path() / "cube.yaml") << fq_test::kForcedCubeCase;
  std::ofstream(dir.path() / "cube_fine.yaml") << finer;
  const fs::path out = dir.path() / "cmp";
  const auto r = run_app({"compare", (dir.path() / "cube.yaml").string(), (dir.path() / "cube_fine.yaml").string(),
                          "--out", out.string(), "--force", "--no-figure"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string md = fq_test::read_text(out / "comparison.md");
  EXPECT_NE(md.find("\nTime integration (`time.integrator`, `time.dt_s`;"), std::string::npos) << md;
  EXPECT_NE(md.find("- cube: central_difference, dt_s = 0.001 s\n"), std::string::npos) << md;
  EXPECT_NE(md.find("- cube_fine: central_difference, dt_s = 0.0005 s\n"), std::string::npos) << md;
}

// The sweep's PGA is the horizontal ground acceleration's magnitude, so a
// frame turned about the vertical with its record reports the record's
// peak (818.1 cm/s^2 at 8.52 s, ../shared/data/ground_motions/README.md)
// along the diagonal too, not its x or y part (8.181 / sqrt 2 = 5.785).
TEST(StudyCommands, SweepPgaDoesNotDependOnTheRecordsHorizontalDirection) {
  TempDir dir;
  for (const char* axis : {"x", "[1, 1, 0]", "[-0.6, 0.8, 0]"}) {
    const std::string name = std::string("cube_") + (axis[0] == 'x' ? "x" : axis[1] == '1' ? "diagonal" : "oblique");
    // The oblique run with a step of many digits, which the table gives
    // exactly (it read 9.99052133e-05 with nine digits; black-box probe).
    const std::string dt = name == "cube_oblique" ? "9.99052132701422e-05" : "0.0001";
    std::ofstream(dir.path() / (name + ".yaml"))
        << cube_case("", "{dt_s: " + dt + ", duration_s: 0.2}", "", "  window_start_s: 8.4\n" + kobe_ns_along(axis));
    const fs::path out = dir.path() / ("sweep_" + name);
    if (axis[0] == 'x') {
      // A sweep.csv of the form before the integrator and dt_s columns
      // (stop 40), as a recorded study wrote it (the header and first row
      // of validation/results/frames_sweep_kobe/sweep.csv before stop 42,
      // which wrote it again in the new form), is
      // ours to replace: two storeys, 17 columns, as wide as the new form
      // with one storey.
      fs::create_directories(out);
      std::ofstream(out / "sweep.csv")
          << "case,record,scale,pga_mps2,pga_g,status,storey1_peak_drift_ratio_rad,storey1_verdict,"
             "storey2_peak_drift_ratio_rad,storey2_verdict,collapsed,first_joint_failure_s,broken_joints,joints,"
             "energy_balance_error_relative,wall_s,output\n"
             "frame_A,RSN1106_KOBE_KJM000,0.5,4.09049542,0.41711445,completed,0.0372586803,damaged,0.0330041295,"
             "standing,0,,0,24,2.17174403e-09,5.95719425,"
             "validation/results/frames_sweep_kobe/frame_A_RSN1106_KOBE_KJM000_x0.5\n";
      ASSERT_EQ(read_text(out / "sweep.csv").find("integrator"), std::string::npos);
    }
    const auto r = run_app({"sweep", (dir.path() / (name + ".yaml")).string(), "--scales", "1", "--out",
                            out.string(), "--no-figure"},
                           dir.path());
    ASSERT_EQ(r.code, 0) << r.err;
    const Table rows = read_csv(out / "sweep.csv");
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_NEAR(std::stod(rows[0].at("pga_mps2")), 8.181, 0.001) << axis;
    EXPECT_EQ(rows[0].at("integrator"), "central_difference");  // the cube case's default
    EXPECT_EQ(rows[0].at("dt_s"), dt == "0.0001" ? "1e-04" : dt);  // its dt_s, digit for digit
  }
}

// A vertical record given with --record to a case whose component drives x
// is warned about once, before the first run, not after every run (workflow
// probe: the warning came with each run's result, after the runs). The
// record's own header names the component 'UP' (the fact the warning uses).
TEST(StudyCommands, SweepWarnsOfAVerticalRecordAlongXBeforeItsRuns) {
  TempDir dir;
  std::ofstream(dir.path() / "cube.yaml") << cube_case("", "{dt_s: 1.0e-4, duration_s: 0.05}", "", kobe_ns_along("x"));
  const fs::path out = dir.path() / "sweep";
  const auto r = run_app({"sweep", (dir.path() / "cube.yaml").string(), "--scales", "0.5,1", "--record",
                          (kSource / "cases/ground_motions/RSN1106_KOBE_KJM-UP.AT2").string(), "--out", out.string(),
                          "--no-figure"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string warning = "is a vertical component ('UP' in its header";
  const std::size_t first = r.err.find(warning);
  ASSERT_NE(first, std::string::npos) << r.err;
  EXPECT_LT(first, r.err.find("sweep of 2 run(s)")) << r.err;
  EXPECT_LT(first, r.err.find("[1/2]")) << r.err;
  EXPECT_EQ(r.err.find(warning, first + 1), std::string::npos) << "said more than once:\n" << r.err;
  // The runs still record it in their own report.
  const Table rows = read_csv(out / "sweep.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows)
    EXPECT_NE(read_text(fs::path(row.at("output")) / "summary.json").find(warning), std::string::npos);
}

// A case's own warnings (here a node no member ends at) hold for every run
// of a study: said once, before the runs, not under each run (review probe:
// a sweep of two scales said it twice, of six scales six times).
TEST(StudyCommands, ACasesOwnWarningIsSaidOnceBeforeTheRuns) {
  TempDir dir;
  std::ofstream(dir.path() / "cube.yaml") << cube_case("", "{dt_s: 1.0e-4, duration_s: 0.05}",
                                                       "nodes: [{id: spare, xyz_m: [1, 1, 0]}]\n", kobe_ns_along("x"));
  const fs::path out = dir.path() / "sweep";
  const auto r = run_app({"sweep", (dir.path() / "cube.yaml").string(), "--scales", "0.5,1", "--out", out.string(),
                          "--no-figure"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string warning = "1 node is the end of no member ('spare' (line 4))";
  const std::size_t first = r.err.find(warning);
  ASSERT_NE(first, std::string::npos) << r.err;
  EXPECT_LT(first, r.err.find("[1/2]")) << r.err;
  EXPECT_EQ(r.err.find(warning, first + 1), std::string::npos) << "said more than once:\n" << r.err;
  // Each run still records it in its own summary.
  for (const auto& row : read_csv(out / "sweep.csv"))
    EXPECT_NE(read_text(fs::path(row.at("output")) / "summary.json").find("the end of no member"), std::string::npos);
}

// Two cases whose warnings read alike (two variants of one scene whose
// blocks overlap alike) each get theirs, named with the case, before the
// runs (final review probe: the second case's warning was dropped as said).
TEST(StudyCommands, EachCaseIsWarnedOfItsOwnWarningsThoughTheTextsMatch) {
  TempDir dir;
  const std::string text =
      "framequake_case: 1\n"
      "time: {dt_s: 1.0e-4, duration_s: 0.02}\n"
      "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
      "blocks:\n"
      "  - {id: low, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.05], material: spruce}\n"
      "  - {id: high, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.149], material: spruce}\n"
      "contact:\n"
      "  ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.5, friction_coefficient: 0.4}\n";
  std::ofstream(dir.path() / "variant_a.yaml") << text;
  std::ofstream(dir.path() / "variant_b.yaml") << text;
  const auto r = run_app({"compare", (dir.path() / "variant_a.yaml").string(), (dir.path() / "variant_b.yaml").string(),
                          "--out", (dir.path() / "cmp").string(), "--no-figure", "--jobs", "1"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string overlap = "1 pair of bodies not held by a joint overlap at the start ('low' and 'high'";
  const std::size_t a = r.err.find("case variant_a: " + overlap), b = r.err.find("case variant_b: " + overlap);
  EXPECT_NE(a, std::string::npos) << r.err;
  EXPECT_NE(b, std::string::npos) << r.err;
  EXPECT_LT(std::max(a, b), r.err.find("[1/2]")) << r.err;
}

// The sweep's PGA is what the run felt: a run shorter than its window
// never feels the rest of it. A ramp record a(t) = 10 t m/s^2 (samples every
// 0.1 s over 10 s, two_column), whole window, run of 0.25 s: the record is
// linear between its samples, so the run's peak is a(0.25 s) = 2.5 m/s^2,
// not the window's 100 (probe: a 1 s run of Kobe NS reported the record's
// 8.18 m/s^2 where it had felt 0.0015).
TEST(StudyCommands, SweepPgaIsThatOfThePartOfTheWindowTheRunFelt) {
  TempDir dir;
  {
    std::ofstream record(dir.path() / "ramp.txt");
    for (int k = 0; k <= 100; ++k) record << 0.1 * k << " " << 1.0 * k << "\n";
  }
  std::ofstream(dir.path() / "short.yaml")
      << cube_case("", "{dt_s: 1.0e-4, duration_s: 0.25}", "",
                   "  components: [{file: ramp.txt, format: two_column, axis: x}]\n");
  const fs::path out = dir.path() / "sweep";
  const auto r = run_app({"sweep", (dir.path() / "short.yaml").string(), "--scales", "1", "--out", out.string(),
                          "--no-figure"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const Table rows = read_csv(out / "sweep.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NEAR(std::stod(rows[0].at("pga_mps2")), 2.5, 1e-6);
  // The run's own summary says which record it felt, and the same peak.
  const std::string summary = read_text(fs::path(rows[0].at("output")) / "summary.json");
  EXPECT_NE(summary.find("\"record\":\"" + (dir.path() / "ramp.txt").lexically_normal().string() + "\""),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("\"window_length_s\":0.25}"), std::string::npos) << summary;  // the run's 0.25 s of it
  EXPECT_NE(summary.find("\"peak_horizontal_mps2\":2.5,"), std::string::npos) << summary;
  // The component's own peak over the same 0.25 s (which component is the
  // strongest, when components are oblique).
  EXPECT_NE(summary.find("\"amplitude_scale\":1,\"peak_mps2\":2.5,"), std::string::npos) << summary;
  const auto info = run_app({"info", (dir.path() / "short.yaml").string()}, dir.path());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("horizontal |(a_x, a_y)| 2.5 m/s^2 over the run's 0.25 s"), std::string::npos) << info.out;
}

TEST(StudyCommands, SweepScalesTheMotionAndFindsNoCollapseInTheDemoPortal) {
  TempDir dir;
  const fs::path out = dir.path() / "sweep";
  const auto r = run_app({"sweep", (kSource / "cases/demo_portal_frame.yaml").string(), "--scales", "1,0.5",
                          "--out", out.string()},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const Table rows = read_csv(out / "sweep.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(std::stod(rows[0].at("scale")), 0.5);  // sorted
  EXPECT_EQ(std::stod(rows[1].at("scale")), 1.0);
  // The portal's window (record 6-9 s) holds the record's peak: 818.1 cm/s^2
  // at 8.52 s (../shared/data/ground_motions/README.md).
  EXPECT_NEAR(std::stod(rows[1].at("pga_mps2")), 8.181, 0.001);
  EXPECT_NEAR(std::stod(rows[0].at("pga_mps2")), 0.5 * std::stod(rows[1].at("pga_mps2")), 1e-9);
  EXPECT_EQ(rows[0].at("record"), "RSN1106_KOBE_KJM000");
  // Each run's folder is there.
  for (const auto& row : rows) EXPECT_TRUE(fs::exists(fs::path(row.at("output")) / "summary.json"));
  const Table scales = read_csv(out / "collapse_scales.csv");
  ASSERT_EQ(scales.size(), 1u);
  EXPECT_EQ(scales[0].at("case"), "demo_portal_frame");
  // Collapse columns agree with the rows.
  const bool collapsed_at_1 = rows[1].at("collapsed") == "1";
  EXPECT_EQ(scales[0].at("smallest_scale_with_collapse").empty(), !(collapsed_at_1 || rows[0].at("collapsed") == "1"));
  EXPECT_EQ(scales[0].at("stood_above_collapse"), "");  // two scales: nothing stood above a collapse
  EXPECT_TRUE(fs::exists(out / "collapse_scales.md"));
  EXPECT_TRUE(is_png(out / "sweep.png"));
  // The runs' drift limits are drawn, once (the figure had none; acceptance
  // probe): fq_plot.py says which in the PNG's Limits text.
  EXPECT_EQ(png_text(out / "sweep.png", "Limits"), "damage 0.0333333 rad, collapse 0.1 rad: demo_portal_frame");
}

// Every run of a sweep gets a folder of its own: scales that differ only in
// the 7th digit (the label kept six before, and both runs wrote into one
// folder), and two records of one file name are refused before anything
// runs.
TEST(StudyCommands, SweepRunsNeverShareAFolder) {
  TempDir dir;
  const std::string portal = (kSource / "cases/demo_portal_frame.yaml").string();
  const fs::path out = dir.path() / "sweep";
  const auto r = run_app({"sweep", portal, "--scales", "1,1.0000001", "--window-length", "0.05", "--no-figure",
                          "--out", out.string()},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const Table rows = read_csv(out / "sweep.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_NE(rows[0].at("output"), rows[1].at("output"));
  for (const auto& row : rows) EXPECT_TRUE(fs::exists(fs::path(row.at("output")) / "summary.json")) << row.at("output");

  fs::create_directories(dir.path() / "other");
  fs::copy_file(kSource / "cases/ground_motions/RSN1106_KOBE_KJM090.AT2",
                dir.path() / "other/RSN1106_KOBE_KJM000.AT2");
  const fs::path never = dir.path() / "never";
  const auto same = run_app({"sweep", portal, "--record", (kSource / "cases/ground_motions/RSN1106_KOBE_KJM000.AT2").string(),
                             "--record", (dir.path() / "other/RSN1106_KOBE_KJM000.AT2").string(), "--out", never.string()},
                            dir.path());
  EXPECT_EQ(same.code, 2) << same.err;
  EXPECT_NE(same.err.find("has the file name of"), std::string::npos) << same.err;
  EXPECT_FALSE(fs::exists(never));
}

// The tables count only what ran to the end. A run that fails (here its
// output folder cannot be made: a file stands in its place) keeps its row
// with every column of the header, empty; an unstable run (the portal at
// dt = 1e-3 s, forced) is no collapse of the structure and is listed under
// the collapse table instead of setting its "smallest scale with collapse".
// A study removes the tables and figure of an earlier study in its folder
// before any run starts, so that a study that fails or is stopped cannot
// leave them beside its own runs (a probe's failed compare left the old
// comparison.md saying "completed"); one it cannot remove stops it before
// anything runs (exit 3).
TEST(StudyCommands, AStudyRemovesTheEarlierStudysTablesBeforeItRuns) {
  TempDir dir;
  const std::string portal = (kSource / "cases/demo_portal_frame.yaml").string();
  const fs::path cmp = dir.path() / "cmp";
  fs::create_directories(cmp);
  // An earlier study's table and figure, as it wrote them (by their start).
  std::ofstream(cmp / "comparison.md") << "| case | status |\n|---|---|\n| stale | completed |\n";
  std::ofstream(cmp / "first_storey_drift.png", std::ios::binary)
      << png_with_text("Software", "framequake fq_plot.py first_storey_drift.png; Matplotlib 3.6.3");
  const auto r = run_app({"compare", portal, "--window-length", "0.05", "--no-figure", "--out", cmp.string()},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_text(cmp / "comparison.md").find("stale"), std::string::npos);
  EXPECT_FALSE(fs::exists(cmp / "first_storey_drift.png")) << "--no-figure must not leave the earlier figure";

  // A collapse_scales.csv of ours from before its stood_above_collapse
  // column is replaced too.
  const fs::path older = dir.path() / "older";
  fs::create_directories(older);
  std::ofstream(older / "collapse_scales.csv")
      << "case,record,largest_scale_without_collapse,smallest_scale_with_collapse,pga_at_collapse_mps2,"
         "collapsed_storeys_at_that_scale\nframe_B,kobe,1.25,1.5,12.27,1 2\n";
  const auto o = run_app({"sweep", portal, "--scales", "1", "--window-length", "0.05", "--no-figure", "--out",
                          older.string()},
                         dir.path());
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(read_text(older / "collapse_scales.csv").find("frame_B"), std::string::npos);

  const fs::path blocked = dir.path() / "blocked";
  fs::create_directories(blocked / "collapse_scales.md" / "inside");  // a folder with content: cannot be removed
  const auto b = run_app({"sweep", portal, "--scales", "1", "--window-length", "0.05", "--no-figure", "--out",
                          blocked.string()},
                         dir.path());
  EXPECT_EQ(b.code, 3) << b.err;
  EXPECT_NE(b.err.find("is not a table or figure of an earlier framequake study"), std::string::npos) << b.err;
  EXPECT_EQ(std::distance(fs::directory_iterator(blocked), fs::directory_iterator()), 1) << "a run started";

  // A user's own file under a table's name is neither removed nor
  // replaced, and nothing runs (it was deleted by name; CLI probe).
  const fs::path notes = dir.path() / "notes";
  fs::create_directories(notes);
  std::ofstream(notes / "comparison.md") << "my notes on the frames\n";
  const auto n = run_app({"compare", portal, "--window-length", "0.05", "--no-figure", "--out", notes.string()},
                         dir.path());
  EXPECT_EQ(n.code, 3) << n.err;
  EXPECT_NE(n.err.find("comparison.md is not a table or figure of an earlier framequake study"), std::string::npos)
      << n.err;
  EXPECT_EQ(read_text(notes / "comparison.md"), "my notes on the frames\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(notes), fs::directory_iterator()), 1) << "a run started";
}

// Only what a study of ours wrote is replaced. A user's own matplotlib
// figure named like ours says "Matplotlib" in its PNG text as ours do, and
// was deleted (tester's probe); ours carry fq_plot.py's mark naming the
// figure. A table of ours to which the user added a row is the user's now.
// Our own tables and figure are recognised, also when the folder's name
// holds a comma, which the csv quotes.
TEST(StudyCommands, AUsersOwnFigureOrRowsUnderATablesNameStopTheStudy) {
  TempDir dir;
  const std::string portal = (kSource / "cases/demo_portal_frame.yaml").string();
  const auto compare = [&](const fs::path& out, bool figure) {
    std::vector<std::string> args{"compare", portal, "--window-length", "0.05", "--out", out.string()};
    if (!figure) args.push_back("--no-figure");
    return run_app(args, dir.path());
  };
  const fs::path ours = dir.path() / "frames, first look";
  ASSERT_EQ(compare(ours, true).code, 0);
  ASSERT_TRUE(is_png(ours / "first_storey_drift.png"));
  ASSERT_EQ(read_csv(ours / "comparison.csv").size(), 1u);
  const auto again = compare(ours, true);
  EXPECT_EQ(again.code, 0) << "our own tables and figure are replaced: " << again.err;
  // A table of the form before the integrator and dt_s columns (stop 40)
  // is ours too: the same table with those two columns taken out.
  {
    std::string earlier = read_text(ours / "comparison.csv");
    const auto cut = [&](const std::string& from) {  // from its comma to the next one's
      const std::size_t at = earlier.find(from);
      ASSERT_NE(at, std::string::npos) << earlier;
      earlier.erase(at, earlier.find(',', at + from.size()) - at);
    };
    cut(",integrator,dt_s");
    cut(",central_difference,");
    ASSERT_EQ(earlier.find("central_difference"), std::string::npos) << earlier;
    std::ofstream(ours / "comparison.csv", std::ios::binary) << earlier;
    const auto over_earlier = compare(ours, true);
    EXPECT_EQ(over_earlier.code, 0) << "an earlier form of our table is replaced: " << over_earlier.err;
    EXPECT_NE(read_text(ours / "comparison.csv").find(",central_difference,"), std::string::npos);
  }

  // A row the user added to our comparison.csv.
  const std::string table = read_text(ours / "comparison.csv");
  const std::string with_row = table + "frame_D,completed,0.02,,,damaged (by hand)\n";
  std::ofstream(ours / "comparison.csv", std::ios::binary) << with_row;
  const auto row = compare(ours, false);
  EXPECT_EQ(row.code, 3) << row.err;
  EXPECT_NE(row.err.find((ours / "comparison.csv").string() + " is not a table or figure of an earlier framequake study"),
            std::string::npos)
      << row.err;
  EXPECT_EQ(read_text(ours / "comparison.csv"), with_row);
  // Our own row copied (a study never writes one case twice): the user's.
  const std::string copied = table + table.substr(table.find('\n') + 1);
  std::ofstream(ours / "comparison.csv", std::ios::binary) << copied;
  const auto twice = compare(ours, false);
  EXPECT_EQ(twice.code, 3) << twice.err;
  EXPECT_EQ(read_text(ours / "comparison.csv"), copied);

  // The user's own comparison.md beside our comparison.csv: refused with
  // nothing touched, our table included (it was deleted before the
  // refusal; workflow probe).
  std::ofstream(ours / "comparison.csv", std::ios::binary) << table;
  std::ofstream(ours / "comparison.md", std::ios::binary) << "# my notes on the frames\n";
  const auto md = compare(ours, false);
  EXPECT_EQ(md.code, 3) << md.err;
  EXPECT_NE(md.err.find("comparison.md is not a table or figure of an earlier framequake study"), std::string::npos)
      << md.err;
  EXPECT_EQ(read_text(ours / "comparison.csv"), table) << "our table was removed by a study that was refused";
  EXPECT_TRUE(fs::exists(ours / "first_storey_drift.png"));
  EXPECT_EQ(read_text(ours / "comparison.md"), "# my notes on the frames\n");

  // A user's own matplotlib figures under the names of ours.
  const fs::path own = dir.path() / "own";
  fs::create_directories(own);
  for (const char* name : {"first_storey_drift.png", "sweep.png"}) {
    const std::string draw = "/usr/bin/python3 -c \"import sys, matplotlib; matplotlib.use('Agg'); "
                             "import matplotlib.pyplot as plt; plt.plot([0, 1]); plt.savefig(sys.argv[1])\" '" +
                             (own / name).string() + "'";
    ASSERT_EQ(std::system(draw.c_str()), 0) << draw;
  }
  const std::string figure = read_text(own / "first_storey_drift.png");
  ASSERT_NE(figure.find("Matplotlib"), std::string::npos) << "not the figure the probe made";
  const auto c = compare(own, true);
  EXPECT_EQ(c.code, 3) << c.err;
  EXPECT_NE(c.err.find("first_storey_drift.png is not a table or figure of an earlier framequake study"),
            std::string::npos)
      << c.err;
  EXPECT_TRUE(read_text(own / "first_storey_drift.png") == figure) << "the user's figure was replaced";
  const std::string sweep_figure = read_text(own / "sweep.png");
  const auto s = run_app({"sweep", portal, "--scales", "1", "--window-length", "0.05", "--out", own.string()},
                         dir.path());
  EXPECT_EQ(s.code, 3) << s.err;
  EXPECT_NE(s.err.find("sweep.png is not a table or figure of an earlier framequake study"), std::string::npos)
      << s.err;
  EXPECT_TRUE(read_text(own / "sweep.png") == sweep_figure) << "the user's figure was replaced";
  EXPECT_EQ(std::distance(fs::directory_iterator(own), fs::directory_iterator()), 2) << "a run started";

  // A comparison figure of the framequake before the mark (stop 27), which
  // fq_plot.py gave the Description "<case> along <direction>" per trace,
  // is ours: the main job run again into its old out/compare must not be
  // refused. A figure with another Description is the user's.
  const fs::path legacy = dir.path() / "legacy", other = dir.path() / "other";
  for (const auto& [folder, description] : {std::pair{legacy, std::string("frame_A along x; frame_B along -y")},
                                            std::pair{other, std::string("my own sketch")}}) {
    fs::create_directories(folder);
    const std::string draw = "/usr/bin/python3 -c \"import sys, matplotlib; matplotlib.use('Agg'); "
                             "import matplotlib.pyplot as plt; plt.plot([0, 1]); "
                             "plt.savefig(sys.argv[1], metadata={'Description': sys.argv[2]})\" '" +
                             (folder / "first_storey_drift.png").string() + "' '" + description + "'";
    ASSERT_EQ(std::system(draw.c_str()), 0) << draw;
  }
  EXPECT_EQ(compare(legacy, false).code, 0);
  EXPECT_FALSE(fs::exists(legacy / "first_storey_drift.png")) << "the old figure of ours was kept";
  const std::string other_figure = read_text(other / "first_storey_drift.png");
  EXPECT_EQ(compare(other, false).code, 3);
  EXPECT_TRUE(read_text(other / "first_storey_drift.png") == other_figure);
}

// Ctrl-C while the figure is drawn stops the plotting process: the study
// says it was stopped on request and exits 130, with its tables written,
// instead of blaming a missing matplotlib with exit 3 (CLI probe). The
// plotting interpreter here (FQ_PYTHON) interrupts itself with SIGINT.
TEST(StudyCommands, CtrlCWhileTheFigureIsDrawnIsAStopNotAFailure) {
  TempDir dir;
  const fs::path fake = dir.path() / "python_interrupted.sh";
  // (It answers the check before the runs, fq_plot.py --check, as a
  // python with matplotlib does.)
  std::ofstream(fake) << "#!/bin/sh\n[ \"$2\" = --check ] && exit 0\nkill -INT $$\nsleep 5\n";
  fs::permissions(fake, fs::perms::owner_all);
  ::setenv("FQ_PYTHON", fake.c_str(), 1);
  const fs::path cmp = dir.path() / "cmp";
  const auto r = run_app({"compare", (kSource / "cases/demo_falling_block.yaml").string(), "--window-length", "0.05",
                          "--out", cmp.string()},
                         dir.path());
  ::unsetenv("FQ_PYTHON");
  EXPECT_EQ(r.code, 130) << r.err;
  EXPECT_NE(r.err.find("the figure was not drawn: stopped on request"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("python3-matplotlib"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(cmp / "comparison.md"));
}

// The compare table's footnote gives each case's own drift limits when they
// differ (it gave the first case's for all, contradicting the row of a case
// with stricter ones; workflow probe), even when they differ only past the
// fourth decimal (1/30 against 0.03334 were merged as 0.0333; new-features
// probe), and says when --window-length cut the record (a verdict may
// change with the part of the record left out).
TEST(StudyCommands, CompareFootnoteGivesEachCasesLimitsAndTheShortenedWindow) {
  TempDir dir;
  std::string strict =
      shipped_case_elsewhere("demo_portal_frame.yaml", {{"name: demo_portal_frame", "name: strict_portal"}});
  strict += "\nassessment: {safety_drift_ratio_rad: 0.03334}\n";
  std::ofstream(dir.path() / "strict.yaml") << strict;
  const fs::path out = dir.path() / "cmp";
  const auto r = run_app({"compare", (kSource / "cases/demo_portal_frame.yaml").string(),
                          (dir.path() / "strict.yaml").string(), "--window-length", "0.05", "--out", out.string(),
                          "--no-figure"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string md = read_text(out / "comparison.md");
  EXPECT_NE(md.find("Verdicts: demo_portal_frame: collapsed = peak storey drift ratio >= 0.1 rad, damaged = above "
                    "0.0333333 rad, standing otherwise; strict_portal: collapsed = peak storey drift ratio >= 0.1 rad, "
                    "damaged = above 0.03334 rad, standing otherwise"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("Ground motion cut to the first 0.05 record seconds of each case's window (--window-length)"),
            std::string::npos)
      << md;
  // One case: one sentence, and no window note without --window-length.
  const auto one = run_app({"compare", (kSource / "cases/demo_falling_block.yaml").string(), "--out",
                            (dir.path() / "one").string(), "--no-figure"},
                           dir.path());
  ASSERT_EQ(one.code, 0) << one.err;
  const std::string md1 = read_text(dir.path() / "one" / "comparison.md");
  EXPECT_NE(md1.find("Verdicts: collapsed = peak storey drift ratio >= 0.1 rad, damaged = above 0.0333333 rad"),
            std::string::npos)
      << md1;
  EXPECT_EQ(md1.find("Ground motion cut"), std::string::npos) << md1;
}

// The sweep figure plots each run's largest storey, not its first only (a
// braced first storey moves the damage up, which the figure hid; workflow
// probe). A sweep.csv of two runs whose second storey drifts more: the
// series drawn (the PNG's Description, written by fq_plot.py) holds the
// second storey's peaks.
TEST(StudyCommands, TheSweepFigurePlotsTheLargestStorey) {
  TempDir dir;
  std::ofstream(dir.path() / "sweep.csv")
      << "case,record,scale,pga_mps2,pga_g,status,collapsed,storey1_peak_drift_ratio_rad,storey1_verdict,"
         "storey2_peak_drift_ratio_rad,storey2_verdict\n"
         "braced,kobe,0.5,4.0,0.41,completed,0,0.005,standing,0.031,standing\n"
         "braced,kobe,1,8.0,0.82,completed,0,0.006,standing,0.045,damaged\n";
  const std::string command = "/usr/bin/python3 '" + (kSource / "scripts/plot/fq_plot.py").string() + "' sweep '" +
                              dir.path().string() + "' && /usr/bin/python3 -c \"import sys; from PIL import Image; "
                              "print(Image.open(sys.argv[1]).info['Description'])\" '" +
                              (dir.path() / "sweep.png").string() + "' > '" + (dir.path() / "d.txt").string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_EQ(read_text(dir.path() / "d.txt"), "braced, kobe: 0.031 0.045\n");
}

// The weak point: comparison.md and each summary.json name the first joint
// to fail and when (events.csv gives joint and body numbers only; workflow
// probe). The breaking-cantilever demo: its first spring deletion in
// events.csv (the reference) is at the joint of the column and the arm.
TEST(StudyCommands, TheFirstJointToFailIsNamed) {
  TempDir dir;
  const fs::path out = dir.path() / "cmp";
  const auto r = run_app({"compare", (kSource / "cases/demo_breaking_cantilever.yaml").string(), "--out", out.string(),
                          "--no-figure"},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  std::stringstream events(read_text(out / "demo_breaking_cantilever" / "events.csv"));
  std::string line, time_s;
  bool broke = false;  // a joint_broken row at the first deletion's time
  while (std::getline(events, line)) {
    const std::string t = line.substr(0, line.find(','));
    if (time_s.empty() && line.find(",spring_deleted,") != std::string::npos) time_s = t;
    if (!time_s.empty() && t == time_s && line.find(",joint_broken,") != std::string::npos) broke = true;
  }
  ASSERT_FALSE(time_s.empty()) << "the demo must break a joint";
  const std::string label = "node top: column column - beam arm (type weak_tenon)";
  const std::string md = read_text(out / "comparison.md");
  std::ostringstream expected;
  // Its name as events.csv gives it: node:member_a-member_b of the case file.
  expected << "- demo_breaking_cantilever: " << label << ", joint top:column-arm "
           << (broke ? "broke" : "lost a spring and held") << " at t = " << std::fixed
           << std::setprecision(3) << std::stod(time_s) << " s";
  EXPECT_NE(md.find(expected.str()), std::string::npos) << md;
  EXPECT_NE(read_text(out / "demo_breaking_cantilever" / "summary.json").find("\"first_joint_failure\": \"" + label + "\""),
            std::string::npos);
}

// The figure script is looked for where FQ_PLOT_SCRIPT says, then beside
// the program (scripts/plot/ under its folder, or one or two up), then in
// the source tree it was built from; only the last was tried (workflow
// probe: a copied program beside its own scripts/plot/fq_plot.py failed,
// after all its runs). Stand-in scripts, run by /bin/sh as FQ_PYTHON,
// write which one was called.
TEST(StudyCommands, TheFigureScriptIsFoundBesideTheProgramOrWhereFqPlotScriptSays) {
  TempDir dir;
  const std::string block = (kSource / "cases/demo_falling_block.yaml").string();
  auto stand_in = [](const fs::path& p, const std::string& tag) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << "[ \"$1\" = --check ] && exit 0\necho " << tag
                     << " > \"$2/called.txt\"\ntouch \"$2/first_storey_drift.png\"\n";
  };
  // A copy of the program with a script beside it.
  const fs::path bin = dir.path() / "bin";
  fs::create_directories(bin);
  fs::copy_file(FQ_APP_PATH, bin / "framequake");
  fs::permissions(bin / "framequake", fs::perms::owner_all);
  stand_in(bin / "scripts/plot/fq_plot.py", "beside");
  const std::string command = "FQ_PYTHON=/bin/sh '" + (bin / "framequake").string() + "' compare '" + block +
                              "' --window-length 0.05 --out '" + (dir.path() / "o1").string() + "' > '" +
                              (dir.path() / "o1.log").string() + "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(dir.path() / "o1.log");
  EXPECT_EQ(read_text(dir.path() / "o1" / "called.txt"), "beside\n");
  // FQ_PLOT_SCRIPT first.
  stand_in(dir.path() / "elsewhere" / "my_plot.py", "env");
  ::setenv("FQ_PYTHON", "/bin/sh", 1);
  ::setenv("FQ_PLOT_SCRIPT", (dir.path() / "elsewhere" / "my_plot.py").c_str(), 1);
  const auto r = run_app({"compare", block, "--window-length", "0.05", "--out", (dir.path() / "o2").string()},
                         dir.path());
  ::unsetenv("FQ_PLOT_SCRIPT");
  ::unsetenv("FQ_PYTHON");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_text(dir.path() / "o2" / "called.txt"), "env\n");
  // FQ_PLOT_SCRIPT naming no file is an error before any run (it fell
  // back to another copy without a word), and a script that writes no
  // figure is not announced as having drawn one (new-features probe).
  ::setenv("FQ_PLOT_SCRIPT", (dir.path() / "nowhere.py").c_str(), 1);
  const auto missing = run_app({"compare", block, "--window-length", "0.05", "--out", (dir.path() / "o3").string()},
                               dir.path());
  ::unsetenv("FQ_PLOT_SCRIPT");
  EXPECT_EQ(missing.code, 3) << missing.err;
  EXPECT_NE(missing.err.find("FQ_PLOT_SCRIPT names '"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir.path() / "o3" / "comparison.csv")) << "a run started";
  std::ofstream(dir.path() / "silent.sh") << "exit 0\n";
  ::setenv("FQ_PYTHON", "/bin/sh", 1);
  ::setenv("FQ_PLOT_SCRIPT", (dir.path() / "silent.sh").c_str(), 1);
  const auto silent = run_app({"compare", block, "--window-length", "0.05", "--out", (dir.path() / "o4").string()},
                              dir.path());
  ::unsetenv("FQ_PLOT_SCRIPT");
  ::unsetenv("FQ_PYTHON");
  EXPECT_EQ(silent.code, 3) << silent.err;
  EXPECT_NE(silent.err.find("ended without writing"), std::string::npos) << silent.err;
  EXPECT_EQ(silent.out.find("figure in"), std::string::npos) << silent.out;
}

// A figure the disk refuses (ENOSPC: its temporary file is a link to
// /dev/full) is reported in one line naming the file and the system's
// reason, exit 3, and leaves no temporary file; a full disk gave a 50-line
// traceback, the advice to install matplotlib and a 0-byte .tmp.png
// (tester's probe). The install hint is kept for a missing matplotlib
// (here: Debian's python3 without its site packages, -S).
TEST(StudyCommands, AFigureTheDiskRefusesIsOneLineAndLeavesNoTemporaryFile) {
  TempDir dir;
  const fs::path cmp = dir.path() / "cmp";
  fs::create_directories(cmp);
  const fs::path temporary = cmp / "first_storey_drift.png.tmp.png";
  fs::create_symlink("/dev/full", temporary);
  const std::string portal = (kSource / "cases/demo_portal_frame.yaml").string();
  const auto r = run_app({"compare", portal, "--window-length", "0.05", "--out", cmp.string()}, dir.path());
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("cannot write " + (cmp / "first_storey_drift.png").string() + ": No space left on device\n"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("Traceback"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("python3-matplotlib"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'),
            std::count(r.err.begin(), r.err.begin() + std::ptrdiff_t(r.err.find("cannot write")), '\n') + 1)
      << "more than one line after the figure's error: " << r.err;
  EXPECT_FALSE(fs::exists(fs::symlink_status(temporary)));
  EXPECT_FALSE(fs::exists(cmp / "first_storey_drift.png"));
  EXPECT_TRUE(fs::exists(cmp / "comparison.csv"));

  const fs::path no_site = dir.path() / "python_without_matplotlib.sh";
  std::ofstream(no_site) << "#!/bin/sh\nexec /usr/bin/python3 -S \"$@\"\n";
  fs::permissions(no_site, fs::perms::owner_all);
  ::setenv("FQ_PYTHON", no_site.c_str(), 1);
  const auto m = run_app({"compare", portal, "--window-length", "0.05", "--out", (dir.path() / "cmp2").string()},
                         dir.path());
  ::unsetenv("FQ_PYTHON");
  EXPECT_EQ(m.code, 3) << m.err;
  EXPECT_NE(m.err.find("matplotlib is missing"), std::string::npos) << m.err;
  EXPECT_NE(m.err.find("python3-matplotlib: bash scripts/install_deps.sh"), std::string::npos) << m.err;
  EXPECT_EQ(m.err.find("Traceback"), std::string::npos) << m.err;
  // Said before the first run (fq_plot.py --check), as the README says:
  // the study ran every case first, then failed (docs probe, 2026-11-27).
  EXPECT_NE(m.err.find("(nothing was run)"), std::string::npos) << m.err;
  EXPECT_FALSE(fs::exists(dir.path() / "cmp2" / "comparison.csv")) << "a run started";
  EXPECT_FALSE(fs::exists(dir.path() / "cmp2" / "demo_portal_frame")) << "a run started";
  // So is an interpreter that is not there.
  ::setenv("FQ_PYTHON", (dir.path() / "no_such_python").c_str(), 1);
  const auto absent = run_app({"compare", portal, "--window-length", "0.05", "--out", (dir.path() / "cmp3").string()},
                              dir.path());
  ::unsetenv("FQ_PYTHON");
  EXPECT_EQ(absent.code, 3) << absent.err;
  EXPECT_NE(absent.err.find("exited with status 127 (it needs Debian's python3 with python3-matplotlib"),
            std::string::npos)
      << absent.err;
  EXPECT_NE(absent.err.find("(nothing was run)"), std::string::npos) << absent.err;
  EXPECT_FALSE(fs::exists(dir.path() / "cmp3" / "demo_portal_frame")) << "a run started";
}

// The comparison gives the peak drift along y as well as x, and the figure
// draws each storey's drift ratio magnitude |(x, y)|, which the verdict is
// taken from: the demo portal shaken along y (out of its plane) drifts
// along y only, which an x-only table and figure showed as no drift at all
// (geometry probe); compared with the same portal shaken along x, one
// figure drew both along one axis, so one of them lay flat on zero (a user
// probe). Drawn along its strongest motion's direction instead, a frame
// that swayed across it (two components, an oblique record) was drawn
// under the damage line beside a legend that said damaged (review probe;
// tests/apps/test_fq_plot.py draws those cases): each trace's peak is now
// its history's peak |(x, y)|, which is its summary's to the sampling.
TEST(StudyCommands, CompareReportsDriftAlongYForAMotionAlongY) {
  TempDir dir;
  const std::string portal = shipped_case_elsewhere("demo_portal_frame.yaml", {{"axis: x", "axis: y"}});
  std::ofstream(dir.path() / "portal_y.yaml", std::ios::binary) << portal;
  std::string portal_x = portal;
  replace_once(portal_x, "axis: y", "axis: x");
  const std::string name = "name: ";
  ASSERT_NE(portal_x.find(name), std::string::npos);
  portal_x.insert(portal_x.find('\n', portal_x.find(name)), "_along_x");
  std::ofstream(dir.path() / "portal_x.yaml", std::ios::binary) << portal_x;
  const fs::path cmp = dir.path() / "cmp";
  const auto r = run_app({"compare", (dir.path() / "portal_y.yaml").string(), (dir.path() / "portal_x.yaml").string(),
                          "--window-length", "0.3", "--out", cmp.string()},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const Table rows = read_csv(cmp / "comparison.csv");
  ASSERT_EQ(rows.size(), 2u);
  const double peak = std::stod(rows[0].at("storey1_peak_drift_ratio_rad"));
  EXPECT_GT(peak, 1e-4);
  // A motion along y of a symmetric portal: the drift is along y alone.
  EXPECT_EQ(std::stod(rows[0].at("storey1_peak_drift_ratio_y_rad")), peak);
  EXPECT_LT(std::stod(rows[0].at("storey1_peak_drift_ratio_x_rad")), 1e-9 * peak);
  EXPECT_TRUE(is_png(cmp / "first_storey_drift.png"));
  const std::string x_case = rows[1].at("case");
  EXPECT_EQ(x_case.substr(x_case.size() - 8), "_along_x");
  // Each trace drawn is the magnitude of the history's (x, y): its peak,
  // in the figure's Description, is the history's and the table's.
  std::string description;
  for (const auto& row : rows) {
    const double drawn = peak_storey1_ratio_from_history(fs::path(row.at("output")) / "history.csv");
    const double table = std::stod(row.at("storey1_peak_drift_ratio_rad"));
    EXPECT_GE(table, drawn * (1.0 - 1e-9)) << row.at("case");
    EXPECT_LE(table, drawn * (1.0 + 5e-4)) << row.at("case");
    char peak_text[32];
    std::snprintf(peak_text, sizeof peak_text, "%.6g", drawn);
    description += (description.empty() ? "" : "; ") + row.at("case") + ": |(x, y)| peaks " + peak_text;
  }
  EXPECT_EQ(png_text(cmp / "first_storey_drift.png", "Description"), description);
  // One panel per storey (the portal has one), each case in it.
  EXPECT_EQ(png_text(cmp / "first_storey_drift.png", "Panels"), "storey 1: " + rows[0].at("case") + ", " + x_case);
}

// A sweep under a vertical record alone: the horizontal PGA is 0 at every
// scale (the record has no horizontal part), which collapse_scales.md says,
// and the figure draws the runs against their scales (input probe, stop 41:
// every run at x = 0; the figure's own test is test_fq_plot.py).
TEST(StudyCommands, ASweepWithoutHorizontalMotionSaysItsPgaIsZero) {
  TempDir dir;
  std::string portal = read_text(kSource / "cases/demo_portal_frame.yaml");
  const std::string record = "file: ground_motions/RSN1106_KOBE_KJM000.AT2, format: peer_at2, axis: x";
  ASSERT_NE(portal.find(record), std::string::npos);
  portal.replace(portal.find(record), record.size(),
                 "file: " + (kSource / "cases/ground_motions").string() +
                     "/RSN1106_KOBE_KJM-UP.AT2, format: peer_at2, axis: z");
  std::ofstream(dir.path() / "up.yaml", std::ios::binary) << portal;
  const fs::path out = dir.path() / "sw";
  const auto r = run_app({"sweep", (dir.path() / "up.yaml").string(), "--scales", "1,2", "--jobs", "1",
                          "--window-length", "0.1", "--no-figure", "--out", out.string()},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto& row : read_csv(out / "sweep.csv")) EXPECT_EQ(row.at("pga_mps2"), "0") << row.at("scale");
  const std::string md = read_text(out / "collapse_scales.md");
  EXPECT_NE(md.find("\nNo horizontal ground motion (PGA, here and in sweep.csv, is the horizontal peak, 0 for these; "
                    "sweep.png draws them against the amplitude scale):\n- demo_portal_frame, record "
                    "RSN1106_KOBE_KJM-UP\n"),
            std::string::npos)
      << md;
}

// Every run's folder is checked before the first run starts: a folder a
// run would refuse (a user's own files in it), or a case named like one of
// the tables, stops the study with nothing run (a probe's compare ran one
// case, then failed the other at its folder). A case cannot be named '.'.
TEST(StudyCommands, EveryRunsFolderIsCheckedBeforeTheFirstRun) {
  TempDir dir;
  const std::string block = (kSource / "cases/demo_falling_block.yaml").string();
  const std::string portal = shipped_case_elsewhere("demo_portal_frame.yaml");
  std::ofstream(dir.path() / "portal.yaml", std::ios::binary) << portal;
  const fs::path cmp = dir.path() / "cmp";
  fs::create_directories(cmp / "demo_portal_frame");
  std::ofstream(cmp / "demo_portal_frame" / "notes.txt") << "a user's own notes";
  const auto r = run_app({"compare", block, (dir.path() / "portal.yaml").string(), "--window-length", "0.05",
                          "--no-figure", "--out", cmp.string()},
                         dir.path());
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("holds no previous framequake run"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nothing was run"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(cmp / "demo_falling_block")) << "a run started before the check";
  EXPECT_TRUE(fs::exists(cmp / "demo_portal_frame" / "notes.txt"));

  std::string named = portal;
  const std::string name = "name: demo_portal_frame";
  ASSERT_NE(named.find(name), std::string::npos);
  named.replace(named.find(name), name.size(), "name: comparison.md");
  std::ofstream(dir.path() / "table_named.yaml", std::ios::binary) << named;
  const fs::path cmp2 = dir.path() / "cmp2";
  const auto t = run_app({"compare", (dir.path() / "table_named.yaml").string(), "--window-length", "0.05",
                          "--no-figure", "--out", cmp2.string()},
                         dir.path());
  EXPECT_EQ(t.code, 3) << t.err;
  EXPECT_NE(t.err.find("the name of one of the study's tables"), std::string::npos) << t.err;
  EXPECT_FALSE(fs::exists(cmp2 / "comparison.md"));

  named.replace(named.find("name: comparison.md"), std::string("name: comparison.md").size(), "name: .");
  std::ofstream(dir.path() / "dot.yaml", std::ios::binary) << named;
  const auto d = run_app({"compare", (dir.path() / "dot.yaml").string(), "--no-figure", "--out",
                          (dir.path() / "cmp3").string()},
                         dir.path());
  EXPECT_EQ(d.code, 2) << d.err;
  EXPECT_NE(d.err.find("field 'name'"), std::string::npos) << d.err;
}

// A run stopped before its end (Ctrl-C) has not shown how it would stand
// through the rest of the record: its verdicts read "so far" (collapsed
// would be final). The portal demo runs on for 100 s past its record here,
// so Ctrl-C always comes before the end.
TEST(StudyCommands, AStoppedRunsVerdictIsOnlySoFar) {
  TempDir dir;
  std::ofstream(dir.path() / "longer.yaml", std::ios::binary) << shipped_case_elsewhere(
      "demo_portal_frame.yaml", {{"  dt_s: 1.0e-5\n", "  dt_s: 1.0e-5\n  duration_s: 100.0\n"}});
  const fs::path cmp = dir.path() / "cmp";
  // One run at a time: the falling-block demo, second, never starts.
  fq_test::AppProcess app({"compare", (dir.path() / "longer.yaml").string(),
                           (kSource / "cases/demo_falling_block.yaml").string(), "--jobs", "1", "--no-figure", "--out",
                           cmp.string()},
                          dir.path());
  for (int i = 0; i < 60000 && !fs::exists(cmp / "demo_portal_frame" / "case.pvd"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  app.signal(SIGINT);
  ASSERT_EQ(app.wait(), 130) << app.err();
  const std::string md = read_text(cmp / "comparison.md");
  EXPECT_NE(md.find("| demo_portal_frame | stopped |"), std::string::npos) << md;
  // Standing or damaged, as far as it got (the portal yields near 0.7 s).
  const std::regex so_far("(standing|damaged) so far");
  EXPECT_TRUE(std::regex_search(md, so_far)) << md;
  EXPECT_TRUE(std::regex_search(app.err(), so_far)) << app.err();
  // The run that never started has a row of the table's width, empty but
  // for the case's integrator and dt_s.
  const std::string csv = read_text(cmp / "comparison.csv");
  // Each row of a table as wide as its header; the count of rows.
  const auto rows_of_header_width = [](const std::string& table) {
    std::stringstream lines(table);
    std::string header;
    std::getline(lines, header);
    const auto fields = [](const std::string& line) { return std::count(line.begin(), line.end(), ',') + 1; };
    int rows = 0;
    for (std::string line; std::getline(lines, line); ++rows) EXPECT_EQ(fields(line), fields(header)) << line;
    return rows;
  };
  EXPECT_EQ(rows_of_header_width(csv), 2);
  EXPECT_NE(csv.find("demo_falling_block,not run"), std::string::npos) << csv;
  // A run that never ran still names the case's integrator and step, in
  // their columns; its wall time and folder are empty.
  const Table table = read_csv(cmp / "comparison.csv");
  ASSERT_EQ(table.size(), 2u);
  EXPECT_EQ(table[1].at("integrator"), "central_difference") << csv;
  EXPECT_EQ(table[1].at("dt_s"), "1e-05") << csv;
  EXPECT_EQ(table[1].at("wall_s"), "") << csv;
  EXPECT_EQ(table[1].at("output"), "") << csv;
  // Under a heading of its own (a line after the warnings read as one),
  // the stopped run as well as the one that never started (input probe,
  // stop 41: the stopped run was left out).
  EXPECT_TRUE(std::regex_search(
      md, std::regex("\nRuns that did not finish:\n- demo_portal_frame: stopped at t = [0-9]+\\.[0-9]{3} s \\(its "
                     "row's figures are those up to then\\)\n- demo_falling_block: not run: stopped on request "
                     "\\(Ctrl-C, SIGTERM or SIGHUP\\)")))
      << md;
  // Which shaking each case ran under (the same probe: nothing said the
  // cases' records differed): the portal's window of its record, as the
  // case file gives it (6 s on, 3 s long, time scale 0.3162), and the
  // falling block's (7.6 s on, 1 s long), neither with a peak: neither
  // completed, so a peak would be that of part of the motion.
  EXPECT_NE(md.find("\nGround motion of each case (they differ: the verdicts compare the frames under different "
                    "shaking):\n- demo_portal_frame: RSN1106_KOBE_KJM000.AT2 along x, record seconds 6 to 9 at time "
                    "scale 0.3162\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("\n- demo_falling_block: RSN1106_KOBE_KJM000.AT2 along x, record seconds 7.6 to 8.6\n"),
            std::string::npos)
      << md;
  // On stderr too, as not run, not as a failure (CLI probe).
  EXPECT_NE(app.err().find("demo_falling_block: not run: stopped on request"), std::string::npos) << app.err();
  EXPECT_EQ(app.err().find("FAILED"), std::string::npos) << app.err();

  // sweep's table likewise: the scale that never ran has a row of the
  // table's width with the case's integrator and step in their columns.
  const fs::path swp = dir.path() / "swp";
  fq_test::AppProcess sweep({"sweep", (dir.path() / "longer.yaml").string(), "--scales", "0.5,1", "--jobs", "1",
                             "--no-figure", "--out", swp.string()},
                            dir.path());
  const auto first_run_writes = [&] {  // the first scale's folder, whatever the record's name in it
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(swp, ec))
      if (fs::exists(entry.path() / "case.pvd")) return true;
    return false;
  };
  for (int i = 0; i < 60000 && !first_run_writes(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  sweep.signal(SIGINT);
  ASSERT_EQ(sweep.wait(), 130) << sweep.err();
  const std::string sweep_csv = read_text(swp / "sweep.csv");
  EXPECT_EQ(rows_of_header_width(sweep_csv), 2);
  const Table sweep_table = read_csv(swp / "sweep.csv");
  ASSERT_EQ(sweep_table.size(), 2u);
  EXPECT_EQ(sweep_table[1].at("status"), "not run") << sweep_csv;
  EXPECT_EQ(sweep_table[1].at("integrator"), "central_difference") << sweep_csv;
  EXPECT_EQ(sweep_table[1].at("dt_s"), "1e-05") << sweep_csv;
  EXPECT_EQ(sweep_table[1].at("wall_s"), "") << sweep_csv;
}

// The portal demo running on for 100 s past its record, its record by
// absolute path, written into `dir` as longer.yaml: a run or study that is
// still going when a second process starts.
fs::path write_long_portal(const fs::path& dir) {
  std::ofstream(dir / "longer.yaml", std::ios::binary) << shipped_case_elsewhere(
      "demo_portal_frame.yaml", {{"  dt_s: 1.0e-5\n", "  dt_s: 1.0e-5\n  duration_s: 100.0\n"}});
  return dir / "longer.yaml";
}

void wait_for_file(const fs::path& file) {
  for (int i = 0; i < 60000 && !fs::exists(file); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

// A study holds its --out folder for its whole duration: a second study
// into it is refused (exit 3, nothing run), as a second run is. Two
// compares into one folder both ended with 0 and the table of the one that
// finished last replaced the other's (tester's probe).
TEST(StudyCommands, ASecondStudyIntoTheFolderOfARunningStudyIsRefused) {
  TempDir dir;
  const fs::path longer = write_long_portal(dir.path());
  const fs::path cmp = dir.path() / "cmp";
  fq_test::AppProcess first({"compare", longer.string(), "--no-figure", "--out", cmp.string()}, dir.path());
  wait_for_file(cmp / "demo_portal_frame" / "case.pvd");
  const fs::path io2 = dir.path() / "second";
  fs::create_directories(io2);
  const auto second = run_app({"sweep", (kSource / "cases/demo_falling_block.yaml").string(), "--scales", "1",
                               "--window-length", "0.05", "--no-figure", "--out", cmp.string()},
                              io2);
  EXPECT_EQ(second.code, 3) << second.err;
  EXPECT_NE(second.err.find("output folder '" + cmp.string() + "' is in use by another framequake process"),
            std::string::npos)
      << second.err;
  EXPECT_FALSE(fs::exists(cmp / "sweep.csv"));
  EXPECT_FALSE(fs::exists(cmp / ("demo_falling_block_RSN1106_KOBE_KJM000_x1"))) << "a run of the second started";
  first.signal(SIGINT);
  ASSERT_EQ(first.wait(), 130) << first.err();
  const Table rows = read_csv(cmp / "comparison.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("case"), "demo_portal_frame");
}

// A study into the folder of a running `run` (or resume) is refused
// likewise: a compare wrote its tables and run folders into a resumed
// run's folder (tester's probe).
TEST(StudyCommands, AStudyIntoTheFolderOfARunningRunIsRefused) {
  TempDir dir;
  const fs::path longer = write_long_portal(dir.path());
  const fs::path out = dir.path() / "run";
  fq_test::AppProcess run({"run", longer.string(), "--quiet", "--out", out.string()}, dir.path());
  wait_for_file(out / "case.pvd");
  const fs::path io2 = dir.path() / "second";
  fs::create_directories(io2);
  const auto study = run_app({"compare", (kSource / "cases/demo_falling_block.yaml").string(), "--window-length",
                              "0.05", "--no-figure", "--out", out.string()},
                             io2);
  EXPECT_EQ(study.code, 3) << study.err;
  EXPECT_NE(study.err.find("is in use by another framequake process"), std::string::npos) << study.err;
  EXPECT_FALSE(fs::exists(out / "comparison.csv"));
  EXPECT_FALSE(fs::exists(out / "demo_falling_block")) << "a run of the study started";
  run.signal(SIGINT);
  EXPECT_EQ(run.wait(), 130) << run.err();
}

// On a file system without flock a study goes on and says once that its
// folder is not locked, not again under each run (each run's summary.json
// keeps it); it was refused with exit 3. ENOLCK is stood in for by
// FQ_TEST_FLOCK_ERRNO (io/folder_lock.h).
TEST(StudyCommands, AStudyGoesOnWithoutLocksWhereTheFileSystemHasNone) {
  TempDir dir;
  const fs::path out = dir.path() / "sweep";
  ::setenv("FQ_TEST_FLOCK_ERRNO", std::to_string(ENOLCK).c_str(), 1);
  const auto r = run_app({"sweep", (kSource / "cases/demo_falling_block.yaml").string(), "--scales", "1,2",
                          "--window-length", "0.05", "--no-figure", "--out", out.string()},
                         dir.path());
  ::unsetenv("FQ_TEST_FLOCK_ERRNO");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string said = "going on without the lock";
  const std::size_t first = r.err.find(said);
  EXPECT_NE(first, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(said, first + 1), std::string::npos) << "said more than once:\n" << r.err;
  EXPECT_NE(r.err.find("warning: cannot lock output folder '" + out.string() + "': No locks available"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(read_csv(out / "sweep.csv").size(), 2u);
}

// --window-length longer than a case's own window keeps that window, and
// says so (it was capped without a word).
TEST(StudyCommands, AWindowLengthLongerThanTheCasesWindowIsNoted) {
  TempDir dir;
  const auto r = run_app({"compare", (kSource / "cases/demo_portal_frame.yaml").string(), "--window-length", "200",
                          "--no-figure", "--out", (dir.path() / "cmp").string()},
                         dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("note: --window-length 200 s is not shorter than the window of 'demo_portal_frame' (3 record "
                       "s); its whole window is used"),
            std::string::npos)
      << r.err;
}

// The tables' note on --window-length says what each run applied of its
// record. A window not longer than the option is run whole, and the note
// said "cut to the first 100 record seconds" of it (records probe: a 6 s
// window). Two blocks on a 0.3 s record (samples 0.00-0.30 s, written
// below): "whole" runs the record to its end, "windowed" its own window of
// record seconds 0.05 to 0.25. At --window-length 100 neither is cut; at
// 0.25 "whole" is cut to 0.25 s and "windowed" (0.2 s) runs whole.
TEST(StudyCommands, TheWindowNoteSaysWhatEachRunApplied) {
  TempDir dir;
  {
    std::ofstream record(dir.path() / "short.txt");
    record << std::fixed << std::setprecision(2);
    for (int k = 0; k <= 30; ++k) record << 0.01 * k << " " << 0.5 << "\n";
  }
  auto block = [&](const std::string& name, const std::string& window) {
    std::ofstream(dir.path() / (name + ".yaml"))
        << cube_case("name: " + name + "\n", "{dt_s: 1.0e-4}", "",
                     window + "  components: [{file: short.txt, format: two_column, axis: x}]\n");
    return (dir.path() / (name + ".yaml")).string();
  };
  const std::string whole = block("whole", ""),
                    windowed = block("windowed", "  window_start_s: 0.05\n  window_length_s: 0.2\n");

  const auto longer = run_app({"compare", whole, windowed, "--window-length", "100", "--no-figure", "--out",
                               (dir.path() / "cmp100").string()},
                              dir.path());
  ASSERT_EQ(longer.code, 0) << longer.err;
  const std::string md100 = read_text(dir.path() / "cmp100" / "comparison.md");
  EXPECT_EQ(md100.find("cut to the first"), std::string::npos) << md100;
  EXPECT_NE(md100.find("Ground motion with --window-length 100 s:\n"
                       "- whole: not cut (its window is not longer than 100 s): it ran the whole record (0.3 s)\n"
                       "- windowed: not cut (its window is not longer than 100 s): it ran its whole window, record "
                       "seconds 0.05 to 0.25 (0.2 s)\n"),
            std::string::npos)
      << md100;

  const auto mixed = run_app({"compare", whole, windowed, "--window-length", "0.25", "--no-figure", "--out",
                              (dir.path() / "cmp025").string()},
                             dir.path());
  ASSERT_EQ(mixed.code, 0) << mixed.err;
  const std::string md025 = read_text(dir.path() / "cmp025" / "comparison.md");
  EXPECT_NE(md025.find("- whole: cut to the first 0.25 record seconds of its window; the verdicts hold for that "
                       "part of the record only\n"
                       "- windowed: not cut (its window is not longer than 0.25 s): it ran its whole window, record "
                       "seconds 0.05 to 0.25 (0.2 s)\n"),
            std::string::npos)
      << md025;

  // A run its time.duration_s ends after 0.05 record seconds, inside the
  // 0.1 s the option leaves of its 0.2 s window: not cut by the option,
  // and not its whole window either (review probe: it was said to have run
  // its whole window).
  std::string brief_text = read_text(windowed);
  brief_text.replace(brief_text.find("name: windowed"), 14, "name: brief");
  brief_text.replace(brief_text.find("time: {dt_s: 1.0e-4}"), 20, "time: {dt_s: 1.0e-4, duration_s: 0.05}");
  brief_text.replace(brief_text.find("window_start_s: 0.05"), 20, "window_start_s: 0.0");
  std::ofstream(dir.path() / "brief.yaml") << brief_text;
  const auto limited = run_app({"compare", (dir.path() / "brief.yaml").string(), windowed, "--window-length", "0.1",
                                "--no-figure", "--out", (dir.path() / "cmp01").string()},
                               dir.path());
  ASSERT_EQ(limited.code, 0) << limited.err;
  const std::string md01 = read_text(dir.path() / "cmp01" / "comparison.md");
  EXPECT_NE(md01.find("- brief: not cut: its time.duration_s of 0.05 s ended the run after record seconds 0 to 0.05 "
                      "(0.05 s), before 0.1 s of its window\n"
                      "- windowed: cut to the first 0.1 record seconds of its window"),
            std::string::npos)
      << md01;

  // A sweep's collapse table says the same.
  const auto sweep = run_app({"sweep", whole, "--scales", "1", "--window-length", "100", "--no-figure", "--out",
                              (dir.path() / "sweep100").string()},
                             dir.path());
  ASSERT_EQ(sweep.code, 0) << sweep.err;
  const std::string smd = read_text(dir.path() / "sweep100" / "collapse_scales.md");
  EXPECT_EQ(smd.find("cut to the first"), std::string::npos) << smd;
  EXPECT_NE(smd.find("- whole, record short: not cut (its window is not longer than 100 s): it ran the whole record "
                     "(0.3 s)\n"),
            std::string::npos)
      << smd;

  // With --record the window is that record's: a 0.5 s record (NPTS 51,
  // DT 0.01) is cut to 0.4 s although the case's own 0.3 s record is not
  // longer than 0.4 s, which the note on stderr said of the run.
  // A PEER record of `npts` samples of 0.01 g, 0.01 s apart.
  auto write_at2 = [&](const std::string& file, int npts) {
    std::ofstream at2(dir.path() / file);
    at2 << "PEER NGA STRONG MOTION DATABASE RECORD\nSynthetic, 1/1/2000, Nowhere, 0\n"
           "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=   "
        << npts << ", DT=   .0100 SEC\n";
    for (int k = 0; k < npts; ++k) at2 << "  .1000000E-01" << (k % 5 == 4 ? "\n" : "");
    at2 << "\n";
  };
  write_at2("longer.AT2", 51);
  const auto with_record = run_app({"sweep", whole, "--scales", "1", "--record", (dir.path() / "longer.AT2").string(),
                                    "--window-length", "0.4", "--no-figure", "--out", (dir.path() / "sweep04").string()},
                                   dir.path());
  ASSERT_EQ(with_record.code, 0) << with_record.err;
  EXPECT_EQ(with_record.err.find("is not shorter than the window"), std::string::npos) << with_record.err;
  EXPECT_NE(read_text(dir.path() / "sweep04" / "collapse_scales.md")
                .find("Ground motion cut to the first 0.4 record seconds of each case's window (--window-length): "
                      "the collapse scales hold for that part of the record only."),
            std::string::npos);

  // Without --window-length, a --record that ends inside a case's window
  // cuts it: a 0.15 s record (NPTS 16) under "windowed" (record seconds
  // 0.05 to 0.25) runs 0.1 of its 0.2 s, and the table says so; "whole"
  // runs the new record to its end, its window, and is not listed. The
  // table gives the scale as given (0.004, which two decimals made 0.00).
  write_at2("shorter.AT2", 16);
  const auto cut = run_app({"sweep", whole, windowed, "--scales", "0.004", "--record",
                            (dir.path() / "shorter.AT2").string(), "--no-figure", "--out",
                            (dir.path() / "sweep_cut").string()},
                           dir.path());
  ASSERT_EQ(cut.code, 0) << cut.err;
  const std::string cut_md = read_text(dir.path() / "sweep_cut" / "collapse_scales.md");
  EXPECT_NE(cut_md.find("Windows cut by a --record's end (each such run applied less of the shaking than the case's "
                        "window asks for; the collapse scales hold for that part):\n"
                        "- windowed with shorter.AT2: the record ends 0.15 s in, so the window from 0.05 s ran 0.1 "
                        "record seconds of the 0.2 s asked for\n"),
            std::string::npos)
      << cut_md;
  EXPECT_EQ(cut_md.find("- whole with"), std::string::npos) << cut_md;
  EXPECT_NE(cut_md.find("| whole | shorter | 0.004 | none up to 0.004 |"), std::string::npos) << cut_md;
  // A usual scale keeps the table's two decimals (the recorded studies'
  // tables read so).
  const auto usual = run_app({"sweep", whole, "--scales", "0.5", "--record", (dir.path() / "shorter.AT2").string(),
                              "--no-figure", "--out", (dir.path() / "sweep_usual").string()},
                             dir.path());
  ASSERT_EQ(usual.code, 0) << usual.err;
  EXPECT_NE(read_text(dir.path() / "sweep_usual" / "collapse_scales.md").find("| whole | shorter | 0.50 | none up to 0.50 |"),
            std::string::npos);
}

// The collapse table counts only runs that completed: an unstable run is
// listed under it, not assessed. (A run failing at its folder, the first
// half of this test until 2026-11-26, is now refused before any run:
// EveryRunsFolderIsCheckedBeforeTheFirstRun; rows of runs that never ran:
// AStoppedRunsVerdictIsOnlySoFar.)
TEST(StudyCommands, TablesCountOnlyRunsThatCompleted) {
  TempDir dir;
  std::ofstream(dir.path() / "coarse.yaml", std::ios::binary)
      << shipped_case_elsewhere("demo_portal_frame.yaml", {{"dt_s: 1.0e-5", "dt_s: 1.0e-3"}});
  const fs::path sweep = dir.path() / "sweep";
  const auto u = run_app({"sweep", (dir.path() / "coarse.yaml").string(), "--scales", "1", "--force", "--no-figure",
                          "--out", sweep.string()},
                         dir.path());
  EXPECT_EQ(u.code, 1) << u.err;
  const Table rows_u = read_csv(sweep / "sweep.csv");
  ASSERT_EQ(rows_u.size(), 1u);
  EXPECT_EQ(rows_u[0].at("status"), "unstable");
  // Not assessed: the drifts after a blow-up are the arithmetic's (a probe's
  // unstable portal was listed as collapsed and drawn with the x marker).
  EXPECT_EQ(rows_u[0].at("storey1_verdict"), "not_assessed");
  EXPECT_EQ(rows_u[0].at("collapsed"), "");
  const Table scales = read_csv(sweep / "collapse_scales.csv");
  ASSERT_EQ(scales.size(), 1u);
  EXPECT_EQ(scales[0].at("smallest_scale_with_collapse"), "");
  const std::string md = read_text(sweep / "collapse_scales.md");
  EXPECT_NE(md.find("no run completed"), std::string::npos) << md;
  EXPECT_EQ(md.find("| none |"), std::string::npos) << "no run completed, so no scale stood: " << md;
  EXPECT_NE(md.find("Not counted above (the run did not complete):"), std::string::npos) << md;
  EXPECT_NE(md.find(": unstable"), std::string::npos) << md;
}

// compare's notes agree with its table: an unstable run (the portal at
// dt = 1e-3 s, forced) is "not assessed (unstable)" there, and was also
// listed under "Storeys collapsed, in the order ..." as "storey 1 at
// 0.004 s" (black-box probe), as if the frame had fallen.
TEST(StudyCommands, CompareDoesNotListAnUnstableRunAsCollapsed) {
  TempDir dir;
  std::ofstream(dir.path() / "coarse.yaml", std::ios::binary)
      << shipped_case_elsewhere("demo_portal_frame.yaml", {{"dt_s: 1.0e-5", "dt_s: 1.0e-3"}});
  const fs::path out = dir.path() / "cmp";
  const auto r = run_app({"compare", (dir.path() / "coarse.yaml").string(), "--force", "--no-figure", "--out",
                          out.string()},
                         dir.path());
  EXPECT_EQ(r.code, 1) << r.err;
  const std::string md = read_text(out / "comparison.md");
  EXPECT_NE(md.find("not assessed (unstable)"), std::string::npos) << md;
  EXPECT_EQ(md.find("Storeys collapsed"), std::string::npos) << md;
  // Its joints torn apart by the blow-up are no weak point: said so.
  EXPECT_NE(md.find("at t = 0.004 s (the run became unstable: this may be the blow-up's doing)"), std::string::npos)
      << md;
}

// comparison.md's "First joint to fail" says whether that joint broke or
// lost a spring and held. Two 0.1 kg hangers, each on a single-point joint
// whose trilinear normal spring reaches its ultimate force of 1.5 N at
// t = 1.5 s as the ground accelerates upward at 10 t m/s^2 (statics:
// F = m a_g = 0.1 x 10 t N; hanger_case.h): one
// breaks with its spring (fracture any_spring_deleted), one holds on its
// shear springs (never).
TEST(StudyCommands, CompareSaysWhetherTheFirstJointToFailBrokeOrHeld) {
  TempDir dir;
  fq_test::write_hanger_ramp(dir.path());
  std::vector<std::string> files;
  for (const std::string criterion : {"any_spring_deleted", "never"}) {
    std::ofstream(dir.path() / (criterion + ".yaml")) << fq_test::hanger_case("hanger_" + criterion, criterion);
    files.push_back((dir.path() / (criterion + ".yaml")).string());
  }
  const fs::path out = dir.path() / "cmp";
  const auto r = run_app({"compare", files[0], files[1], "--no-figure", "--out", out.string()}, dir.path());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string md = read_text(out / "comparison.md");
  const std::string joint = ": support top: ground - other hanger (type tri), joint top:ground-hanger ";
  EXPECT_NE(md.find("First joint to fail:\n- hanger_any_spring_deleted" + joint + "broke at t = 1.50"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- hanger_never" + joint + "lost a spring and held at t = 1.50"), std::string::npos) << md;
  EXPECT_EQ(md.find("unstable"), std::string::npos) << md;
}

// The stable limit info prints is one a user can copy into dt_s: printed
// rounded down, so run and info accept it. The portal demo's limit,
// 1.184375...e-4 s, printed to six digits by the stream's own rounding as
// 0.000118438, which both refused.
TEST(StudyCommands, TheStableLimitInfoPrintsIsAcceptedAsTheTimeStep) {
  TempDir dir;
  std::string portal = shipped_case_elsewhere("demo_portal_frame.yaml");
  std::ofstream(dir.path() / "portal.yaml", std::ios::binary) << portal;
  const auto info = run_app({"info", (dir.path() / "portal.yaml").string()}, dir.path());
  ASSERT_EQ(info.code, 0) << info.err;
  const std::string tag = "stable limit ";
  const std::size_t at = info.out.find(tag);
  ASSERT_NE(at, std::string::npos) << info.out;
  const std::string limit = info.out.substr(at + tag.size(), info.out.find(' ', at + tag.size()) - at - tag.size());
  replace_once(portal, "dt_s: 1.0e-5", "dt_s: " + limit);
  std::ofstream(dir.path() / "at_limit.yaml", std::ios::binary) << portal;
  const auto again = run_app({"info", (dir.path() / "at_limit.yaml").string()}, dir.path());
  EXPECT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("time step   " + limit + " s"), std::string::npos) << again.out;
  EXPECT_EQ(again.out.find("ABOVE THE STABLE LIMIT"), std::string::npos) << limit << "\n" << again.out;
}

TEST(StudyCommands, BadInputIsRefusedBeforeAnythingIsWritten) {
  TempDir dir;
  const fs::path out = dir.path() / "never";
  const std::string portal = (kSource / "cases/demo_portal_frame.yaml").string();
  // A case that loads but that run refuses at its start (dt 4.2 times the
  // stable estimate): compare and sweep check every case before running
  // any, so the portal beside it is not run either.
  std::ofstream(dir.path() / "cube.yaml", std::ios::binary) << fq_test::kForcedCubeCase;
  const std::string cube = (dir.path() / "cube.yaml").string();
  // The portal with dt = 1e-3 s, 8.4 times its stable estimate, for sweep
  // (which needs a ground motion); its record by absolute path.
  std::ofstream(dir.path() / "coarse.yaml", std::ios::binary) << shipped_case_elsewhere(
      "demo_portal_frame.yaml", {{"dt_s: 1.0e-5", "dt_s: 1.0e-3"}, {"name: demo_portal_frame", "name: coarse_portal"}});
  const std::string coarse_portal = (dir.path() / "coarse.yaml").string();
  // A PEER record of 0.05 s, shorter than the falling-block demo's window
  // start (7.6 s).
  std::ofstream(dir.path() / "short.AT2") << "PEER NGA STRONG MOTION DATABASE RECORD\nTest\n"
                                             "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    6, DT=   .0100 SEC\n"
                                             "  .1E-02  .2E-02 -.1E-02  .0E+00  .3E-02  .0E+00\n";
  const std::string block = (kSource / "cases/demo_falling_block.yaml").string();
  // A case whose own ground-motion window (5e-5 s) is shorter than its step
  // (1e-4 s), which a run takes to its duration_s (0.01 s): --window-length
  // stops it with the motion, and the option is named, not the case's
  // duration_s (review probe: it was blamed on duration_s's line).
  std::ofstream(dir.path() / "ramp.txt") << "0 0\n0.01 0.1\n0.02 0\n0.03 0\n";
  std::ofstream(dir.path() / "short_window.yaml")
      << "framequake_case: 1\nname: short_window\ntime: {dt_s: 1.0e-4, duration_s: 0.01}\n"
         "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
         "blocks: [{id: cube, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: spruce}]\n"
         "ground_motion: {window_length_s: 5.0e-5, components: [{file: ramp.txt, format: two_column, axis: x}]}\n";
  const std::string short_window = (dir.path() / "short_window.yaml").string();
  // The same case without duration_s runs for its window; with a --record of
  // 5e-5 s (two samples) that is less than its step: refused naming the
  // record, before any run (review probe: an internal error, exit 4).
  std::string no_duration = read_text(short_window);
  no_duration.replace(no_duration.find(", duration_s: 0.01"), std::string(", duration_s: 0.01").size(), "");
  no_duration.replace(no_duration.find("window_length_s: 5.0e-5, "), std::string("window_length_s: 5.0e-5, ").size(),
                      "");
  std::ofstream(dir.path() / "no_duration.yaml") << no_duration;
  std::ofstream(dir.path() / "tiny.AT2") << "PEER NGA STRONG MOTION DATABASE RECORD\nTest\n"
                                            "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    2, DT=   .0000500 SEC\n"
                                            "  .1E-02  .2E-02\n";
  struct Case {
    std::vector<std::string> args;
    std::string message;
  } cases[] = {
      {{"compare", portal, (dir.path() / "missing.yaml").string(), "--out", out.string()}, "missing.yaml"},
      {{"compare", portal, portal, "--out", out.string()},
       "demo_portal_frame.yaml:37: field 'name': two cases are named 'demo_portal_frame'"},
      {{"sweep", portal, "--scales", "1,", "--out", out.string()}, "--scales expects a positive number, got ''"},
      {{"sweep", block, "--record", (dir.path() / "short.AT2").string(), "--out", out.string()},
       "demo_falling_block.yaml:59: field 'ground_motion.window_start_s': the window starts at 7.6"},
      {{"compare", "--out", out.string()}, "missing CASE"},
      {{"compare", portal, "--window-length", "-1", "--out", out.string()}, "--window-length expects a positive number"},
      // Less than one step: the option is named, not the case's line.
      {{"compare", portal, "--window-length", "1e-9", "--out", out.string()},
       "option '--window-length': expected at least one time step"},
      {{"sweep", (dir.path() / "no_duration.yaml").string(), "--scales", "1", "--record",
        (dir.path() / "tiny.AT2").string(), "--out", out.string()},
       "tiny.AT2: option '--record': expected at least one time step: with this record, 'short_window' runs for its "
       "window of 5e-05 record s"},
      {{"compare", short_window, "--window-length", "0.02", "--out", out.string()},
       "option '--window-length': expected at least one time step: with --window-length, 'short_window' stops with "
       "its ground motion"},
      {{"sweep", portal, "--scales", "1,x", "--out", out.string()}, "--scales expects a positive number, got 'x'"},
      {{"sweep", portal, "--record", (dir.path() / "no.AT2").string(), "--out", out.string()}, "no.AT2"},
      // A two-column file is not read as a PEER record, and the message says
      // where such a record goes (it named only the header line that failed).
      {{"sweep", portal, "--record", (dir.path() / "ramp.txt").string(), "--out", out.string()},
       "(--record reads PEER .AT2 records; a record in another format goes in the case file, "
       "ground_motion.components)"},
      {{"sweep", portal, "--jobs", "0", "--out", out.string()}, "--jobs expects a whole number"},
      {{"compare", portal, cube, "--out", out.string()}, "cube.yaml:3: field 'time.dt_s': dt_s = 0.001 s exceeds"},
      {{"sweep", portal, coarse_portal, "--scales", "1", "--out", out.string()}, "coarse.yaml:43: field 'time.dt_s'"},
  };
  for (const Case& c : cases) {
    const auto r = run_app(c.args, dir.path());
    EXPECT_EQ(r.code, 2) << c.message << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.message;
  }
}

}  // namespace
