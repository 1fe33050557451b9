// Bad input at the command line, through the real `framequake` binary.
//
// Each row of kCaseRows / kRecordRows breaks one thing in an otherwise valid
// case (kBaseCase) or record (kBaseRecord). Expected: exit code 2 (usage /
// bad input, apps/main.cpp), stderr naming the file, the line of the broken
// text (counted in the texts below: the row says which line it edits),
// the field path (cases/README.md spelling, accelerogram.h field names) and
// what was expected; and no output folder created. The expected lines and
// fields come from where each row puts its fault, the message words from the
// contracts in io/case_file.h and io/accelerogram.h, not from the program.
#include <gtest/gtest.h>
#include <thread>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app_process.h"
#include "forced_cube_case.h"

namespace {

namespace fs = std::filesystem;
using fq_test::run_app;
using fq_test::TempDir;

// Line numbers are fixed by this text; rows refer to them.
const char* const kBaseCase =
    "framequake_case: 1\n"                                                                      // 1
    "name: cli_errors\n"                                                                        // 2
    "time:\n"                                                                                   // 3
    "  dt_s: 1.0e-4\n"                                                                          // 4
    "  duration_s: 0.01\n"                                                                      // 5
    "materials:\n"                                                                              // 6
    "  - name: spruce\n"                                                                        // 7
    "    density_kg_per_m3: 450\n"                                                              // 8
    "sections:\n"                                                                               // 9
    "  - name: s50\n"                                                                           // 10
    "    width_m: 0.05\n"                                                                       // 11
    "    depth_m: 0.05\n"                                                                       // 12
    "nodes:\n"                                                                                  // 13
    "  - {id: a, xyz_m: [0, 0, 0]}\n"                                                           // 14
    "  - {id: b, xyz_m: [0, 0, 1]}\n"                                                           // 15
    "members:\n"                                                                                // 16
    "  - {id: col, kind: column, nodes: [a, b], section: s50, material: spruce}\n"              // 17
    "blocks:\n"                                                                                 // 18
    "  - {id: cube, size_m: [0.1, 0.1, 0.1], center_m: [1, 0, 0.05], material: spruce}\n"       // 19
    "ground_motion:\n"                                                                          // 20
    "  components:\n"                                                                           // 21
    "    - {file: rec.AT2, format: peer_at2, axis: x}\n";                                       // 22

// A PEER .AT2 record: 4 header lines, 6 values in g.
const char* const kBaseRecord =
    "PEER NGA STRONG MOTION DATABASE RECORD\n"            // 1
    "Test event, 1 Jan 2000, station, 000\n"              // 2
    "ACCELERATION TIME SERIES IN UNITS OF G\n"            // 3
    "NPTS=    6, DT=   .0100 SEC\n"                       // 4
    "  .1000000E-02  .2000000E-02 -.1000000E-02  .0000000E+00  .3000000E-02\n"  // 5
    "  .1000000E-02\n";                                   // 6

struct Row {
  const char* name;
  const char* find;     // text replaced in the base file ("" = whole file)
  const char* replace;  // replacement
  const char* file;     // file the message must name: "case.yaml" or "rec.AT2"
  int line;             // expected line; 0 = the file as a whole (no line printed)
  const char* field;    // expected field path ("" = none printed)
  const char* message;  // words the explanation must contain
};

std::string substitute(std::string base, const Row& r) {
  if (std::string(r.find).empty()) return r.replace;
  const auto at = base.find(r.find);
  if (at == std::string::npos) ADD_FAILURE() << r.name << ": row text not found in the base file: " << r.find;
  else base.replace(at, std::string(r.find).size(), r.replace);
  return base;
}

// Faults in the case file.
const Row kCaseRows[] = {
    {"yaml_syntax_error", "name: cli_errors\n", "name: cli_errors: extra\n", "case.yaml", 2, "",
     "YAML syntax error"},
    {"unknown_key", "  dt_s: 1.0e-4\n", "  dt: 1.0e-4\n", "case.yaml", 4, "time.dt", "unknown key 'dt'"},
    {"unknown_top_level_key", "sections:\n", "section:\n", "case.yaml", 9, "section", "unknown key 'section'"},
    {"key_twice", "  duration_s: 0.01\n", "  duration_s: 0.01\n  dt_s: 2.0e-4\n", "case.yaml", 6, "time.dt_s",
     "appears twice"},
    {"wrong_type_text_for_number", "density_kg_per_m3: 450", "density_kg_per_m3: heavy", "case.yaml", 8,
     "materials[0].density_kg_per_m3", "expected a positive number"},
    {"wrong_type_quoted_number", "width_m: 0.05", "width_m: \"0.05\"", "case.yaml", 11, "sections[0].width_m",
     "quoted text"},
    {"wrong_type_scalar_for_list", "materials:\n  - name: spruce\n    density_kg_per_m3: 450\n",
     "materials: spruce\n\n\n", "case.yaml", 6, "materials", "expected a list of materials"},
    {"non_finite_number", "dt_s: 1.0e-4", "dt_s: inf", "case.yaml", 4, "time.dt_s", "finite"},
    {"yaml_nan", "dt_s: 1.0e-4", "dt_s: .nan", "case.yaml", 4, "time.dt_s", "expected a positive number"},
    {"missing_field", "    depth_m: 0.05\n", "", "case.yaml", 10, "sections[0].depth_m",
     "missing required key 'depth_m'"},
    {"missing_required_section", "framequake_case: 1\n", "\n", "case.yaml", 2, "framequake_case",
     "missing required key 'framequake_case'"},
    {"negative_dimension", "width_m: 0.05", "width_m: -0.05", "case.yaml", 11, "sections[0].width_m",
     "expected a positive number"},
    {"negative_block_size", "size_m: [0.1, 0.1, 0.1]", "size_m: [0.1, -0.1, 0.1]", "case.yaml", 19,
     "blocks[0].size_m[1]", "positive edge length"},
    {"zero_time_step", "dt_s: 1.0e-4", "dt_s: 0", "case.yaml", 4, "time.dt_s", "expected a positive number"},
    {"member_between_identical_nodes", "nodes: [a, b]", "nodes: [a, a]", "case.yaml", 17, "members[0].nodes",
     "two different nodes"},
    {"member_between_coincident_nodes", "{id: b, xyz_m: [0, 0, 1]}", "{id: b, xyz_m: [0, 0, 0]}", "case.yaml", 17,
     "members[0].nodes", "same position"},
    {"unknown_section", "section: s50,", "section: s60,", "case.yaml", 17, "members[0].section",
     "no section named 's60'"},
    {"unknown_material", "center_m: [1, 0, 0.05], material: spruce", "center_m: [1, 0, 0.05], material: oak",
     "case.yaml", 19, "blocks[0].material", "no material named 'oak'"},
    {"unknown_node", "nodes: [a, b]", "nodes: [a, c]", "case.yaml", 17, "members[0].nodes[1]",
     "no node named 'c'"},
    {"unknown_schema_version", "framequake_case: 1", "framequake_case: 2", "case.yaml", 1, "framequake_case",
     "unknown schema version 2"},
    {"missing_record_file", "file: rec.AT2", "file: missing.AT2", "case.yaml", 22, "ground_motion.components[0].file",
     "record file not found"},
    // A folder is not "not found" (a probe's 'dir.AT2' was reported so).
    {"record_file_is_a_folder", "file: rec.AT2", "file: .", "case.yaml", 22, "ground_motion.components[0].file",
     "record file is a folder, not a file"},
    {"empty_case_file", "", "", "case.yaml", 0, "", "the file is empty"},
    {"two_yaml_documents", "", "framequake_case: 1\n---\nname: x\n", "case.yaml", 3, "", "one YAML document"},
    // yaml-cpp 0.7 alone would loop here until memory ran out (fuzz_case_file).
    {"yaml_stray_comma", "", ",\n", "case.yaml", 1, "", "unexpected ','"},
    {"control_byte", "name: cli_errors\n", "name: cli\x01_errors\n", "case.yaml", 2, "", "control byte 0x01"},
    // The same written as YAML escapes: `info` printed them raw (probe).
    {"escaped_control_characters", "name: cli_errors\n", "name: cli_errors\ndescription: \"red \\e[31m \\0 \\x7f\"\n",
     "case.yaml", 3, "description", "control character 0x1B"},
    // Densities no solid has (a typing error or a wrong unit): 1e-300 made
    // every frequency overflow, so the stable-step check saw no limit and
    // the run went on; 1e308 gave an infinite mass.
    {"density_far_too_small", "density_kg_per_m3: 450", "density_kg_per_m3: 1.0e-300", "case.yaml", 8,
     "materials[0].density_kg_per_m3", "is outside 0.1 to 1e+06 kg/m^3"},
    {"density_far_too_large", "density_kg_per_m3: 450", "density_kg_per_m3: 1.0e308", "case.yaml", 8,
     "materials[0].density_kg_per_m3", "is outside 0.1 to 1e+06 kg/m^3"},
    // A stiffness whose modes overflow: no stable step can be estimated, and
    // the run is refused instead of running without a limit (--force or not).
    {"contact_stiffness_overflows", "ground_motion:\n",
     "ground: {level_m: 0}\ncontact: {ground: {normal_stiffness_N_per_m: 1.0e308}}\nground_motion:\n", "case.yaml", 4,
     "time.dt_s", "the stable time step cannot be estimated"},
};

// Faults in the record the case refers to (rec.AT2, read while loading).
const Row kRecordRows[] = {
    {"record_too_few_samples", "", "banner\nevent\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 1, DT= .01 SEC\n.1E-02\n",
     "rec.AT2", 4, "NPTS", "at least 2 samples"},
    {"record_npts_above_data", "NPTS=    6", "NPTS=    7", "rec.AT2", 6, "NPTS",
     "declares NPTS=7 but the file holds 6 values"},
    {"record_npts_below_data", "NPTS=    6", "NPTS=    5", "rec.AT2", 6, "NPTS",
     "declares NPTS=5 but the file holds 6 values"},
    {"record_non_numeric_value", ".2000000E-02", "abc", "rec.AT2", 5, "value", "expected a finite number"},
    {"record_missing_dt", "NPTS=    6, DT=   .0100 SEC", "NPTS=    6", "rec.AT2", 4, "DT", "DT="},
    {"record_in_velocity_units", "IN UNITS OF G", "IN UNITS OF CM/SEC", "rec.AT2", 3, "header", "UNITS OF G"},
    {"record_header_cut_short", "", "PEER NGA STRONG MOTION DATABASE RECORD\nevent\n", "rec.AT2", 3, "header",
     "expected 4 header lines"},
    {"record_empty", "", "", "rec.AT2", 0, "file", "the file is empty"},
    // A decimal comma or a thousands separator is quoted whole (it was
    // quoted as its part before the comma, "got '0'").
    {"record_dt_decimal_comma", "DT=   .0100 SEC", "DT=   0,0100 SEC", "rec.AT2", 4, "DT",
     "expected a time step in s with a decimal point, got '0,0100' (a decimal comma?"},
    // A value far beyond 20 g is quoted in g as written (1e308 g overflowed
    // to inf in m/s^2 and read "got inf g").
    {"record_huge_value", ".2000000E-02", "1e308", "rec.AT2", 5, "value", "expected at most 20 g in magnitude "
     "(the largest ground acceleration ever recorded is about 4 g), got 1e+308 g"},
    {"record_npts_thousands_separator", "NPTS=    6,", "NPTS= 5,372,", "rec.AT2", 4, "NPTS",
     "expected the number of samples, got '5,372' (a thousands separator?"},
};

// Binary garbage: no line to expect (any byte may end up on any line), but
// the file must still be named and the run refused.
const std::string kGarbage = std::string("\x7f" "ELF\x02\x01\x01\x00\x00\x00\xff\xfe\n\x01\x02\x03", 16) +
                             std::string("\x00\x89PNG\r\n\x1a\n", 9);

struct Outcome {
  fq_test::AppResult app;
  bool out_folder_exists = false;
};

// Writes case.yaml and rec.AT2 into a fresh folder and runs
// `framequake run case.yaml --out <dir>/out --quiet`.
Outcome run_case(const std::string& case_text, const std::string& record_text) {
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml", std::ios::binary) << case_text;
  std::ofstream(dir.path() / "rec.AT2", std::ios::binary) << record_text;
  const fs::path out = dir.path() / "out";
  Outcome o;
  o.app = run_app({"run", (dir.path() / "case.yaml").string(), "--out", out.string(), "--quiet"}, dir.path());
  o.out_folder_exists = fs::exists(out);
  return o;
}

void check_row(const Row& row, const Outcome& o) {
  SCOPED_TRACE(row.name);
  EXPECT_EQ(o.app.code, 2) << o.app.err;
  EXPECT_FALSE(o.out_folder_exists) << "an output folder was created for bad input";
  // file:line: field 'path': message (input_error.h); line 0 prints no line.
  // Appended piece by piece: gcc 12 at -O3 warns falsely
  // (-Wstringop-overflow) about the inlined concatenation of temporaries.
  std::string where = row.file;
  if (row.line > 0) {
    where += ':';
    where += std::to_string(row.line);
  }
  where += ": ";
  EXPECT_NE(o.app.err.find(where), std::string::npos) << "expected '" << where << "' in: " << o.app.err;
  if (*row.field) {
    const std::string field = "field '" + std::string(row.field) + "'";
    EXPECT_NE(o.app.err.find(field), std::string::npos) << "expected " << field << " in: " << o.app.err;
  }
  EXPECT_NE(o.app.err.find(row.message), std::string::npos) << "expected '" << row.message << "' in: " << o.app.err;
  EXPECT_EQ(o.app.err.find("internal error"), std::string::npos) << o.app.err;
}

TEST(CliErrors, TheBaseCaseIsValid) {
  // Without this the rows would prove nothing: the unbroken files load.
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml") << kBaseCase;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const auto r = run_app({"info", (dir.path() / "case.yaml").string()}, dir.path());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("ABOVE THE STABLE LIMIT"), std::string::npos) << r.out;
}

// A run shorter than one time step is refused, not "completed" after no
// step: a ground-motion window that short (the run lasts the window when
// duration_s is not given). Named at dt_s's own line (4) with the window's
// line beside it: either may be the mistake (a probe's dt_s of 10 s was
// blamed on the window, at the time section's line 3).
TEST(CliErrors, WindowShorterThanOneStepIsRefused) {
  std::string text = kBaseCase;
  const std::string duration = "  duration_s: 0.01\n", motion = "ground_motion:\n";
  ASSERT_NE(text.find(duration), std::string::npos);
  text.erase(text.find(duration), duration.size());
  text.replace(text.find(motion), motion.size(), "ground_motion:\n  window_length_s: 1.0e-9\n");
  const auto window_line = 1 + std::count(text.begin(), text.begin() + long(text.find("  window_length_s")), '\n');
  const Outcome o = run_case(text, kBaseRecord);
  EXPECT_EQ(o.app.code, 2) << o.app.err;
  EXPECT_FALSE(o.out_folder_exists);
  EXPECT_NE(o.app.err.find("case.yaml:4: field 'time.dt_s'"), std::string::npos) << o.app.err;
  EXPECT_NE(o.app.err.find("dt_s = 0.0001 s is longer than the run"), std::string::npos) << o.app.err;
  EXPECT_NE(o.app.err.find("(ground_motion.window_length_s, line " + std::to_string(window_line) + ","),
            std::string::npos)
      << o.app.err;
}

// Without window_length_s the window runs from window_start_s to the
// record's end (0.05 s): started 0.01 s before it, it is shorter than a
// 0.02 s step, and the message names window_start_s's line, not the absent
// window_length_s (review probe).
TEST(CliErrors, AWindowCutByTheRecordsEndIsNamedByItsStart) {
  std::string text = kBaseCase;
  const std::string duration = "  duration_s: 0.01\n", motion = "ground_motion:\n", step = "  dt_s: 1.0e-4\n";
  text.erase(text.find(duration), duration.size());
  text.replace(text.find(step), step.size(), "  dt_s: 0.02\n");
  text.replace(text.find(motion), motion.size(), "ground_motion:\n  window_start_s: 0.04\n");
  const auto start_line = 1 + std::count(text.begin(), text.begin() + long(text.find("  window_start_s")), '\n');
  const Outcome o = run_case(text, kBaseRecord);
  EXPECT_EQ(o.app.code, 2) << o.app.err;
  EXPECT_FALSE(o.out_folder_exists);
  EXPECT_NE(o.app.err.find("case.yaml:4: field 'time.dt_s'"), std::string::npos) << o.app.err;
  EXPECT_NE(o.app.err.find("(from ground_motion.window_start_s, line " + std::to_string(start_line) +
                           " to the record's end, times time_scale)"),
            std::string::npos)
      << o.app.err;
  EXPECT_EQ(o.app.err.find("window_length_s"), std::string::npos) << o.app.err;
}

// Text of the user's that is not UTF-8 (typed in Latin-1: "D\xFCzce") is
// shown with U+FFFD where it is quoted in an error or printed by info; the
// raw byte reached the terminal (review probe). U+FFFD is EF BF BD.
TEST(CliErrors, TextThatIsNotUtf8IsShownWithReplacementCharacters) {
  const std::string fffd = "\xEF\xBF\xBD";
  std::string text = kBaseCase;
  const std::string name = "name: cli_errors\n";
  ASSERT_NE(text.find(name), std::string::npos);
  text.replace(text.find(name), name.size(), "name: d\xFCzce\n");
  const Outcome o = run_case(text, kBaseRecord);
  EXPECT_EQ(o.app.code, 2) << o.app.err;
  EXPECT_NE(o.app.err.find("field 'name'"), std::string::npos) << o.app.err;
  EXPECT_NE(o.app.err.find("d" + fffd + "zce"), std::string::npos) << o.app.err;
  EXPECT_EQ(o.app.err.find("\xFC"), std::string::npos) << o.app.err;

  TempDir dir;
  std::string described = kBaseCase;
  described.replace(described.find(name), name.size(), name + "description: shaken at D\xFCzce\n");
  std::ofstream(dir.path() / "case.yaml") << described;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const auto r = run_app({"info", (dir.path() / "case.yaml").string()}, dir.path());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("shaken at D" + fffd + "zce"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("\xFC"), std::string::npos) << r.out;
}

// info prints a ground-motion direction as the unit vector it is: axis -z
// is (0 0 -1), without the negative zeros the sign flip leaves in x and y.
TEST(CliInfo, NegativeAxisPrintsWithoutNegativeZeros) {
  TempDir dir;
  std::string text = kBaseCase;
  const std::string axis = "axis: x}";
  ASSERT_NE(text.find(axis), std::string::npos);
  text.replace(text.find(axis), axis.size(), "axis: -z}");
  std::ofstream(dir.path() / "case.yaml") << text;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const auto r = run_app({"info", (dir.path() / "case.yaml").string()}, dir.path());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("along ( 0  0 -1)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("(-0 "), std::string::npos) << r.out;
}

// `info` printed a description's YAML escapes "\e", "\0", "\x7f" as the
// raw ESC, NUL and DEL bytes (black-box probe): the case is refused as one
// with the raw bytes is, and no such byte reaches the terminal. A tab and
// line breaks are text, and stay allowed.
TEST(CliInfo, ControlCharactersWrittenAsEscapesAreRefused) {
  TempDir dir;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  std::ofstream(dir.path() / "bad.yaml") << std::string(kBaseCase) + "description: \"red \\e[31m \\0 \\x7f\"\n";
  std::ofstream(dir.path() / "good.yaml") << std::string(kBaseCase) + "description: \"one\\ttwo\\nthree\"\n";
  const auto bad = run_app({"info", (dir.path() / "bad.yaml").string()}, dir.path());
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("bad.yaml:23: field 'description': control character 0x1B"), std::string::npos) << bad.err;
  for (const char c : {'\x1b', '\0', '\x7f'}) {
    EXPECT_EQ(bad.out.find(c), std::string::npos) << int(c);
    EXPECT_EQ(bad.err.find(c), std::string::npos) << int(c);
  }
  const auto good = run_app({"info", (dir.path() / "good.yaml").string()}, dir.path());
  EXPECT_EQ(good.code, 0) << good.err;
  EXPECT_NE(good.out.find("one\ttwo\nthree"), std::string::npos) << good.out;
}

// An output interval not shorter than the run leaves its file with the
// start and the end only (steps 0 and 100 of the base case's 100 steps of
// 1e-4 s): run says so before it starts (a probe's history interval of 2 s
// on a 1 s run passed without a word); half the run gets no note.
TEST(CliErrors, AnOutputIntervalAsLongAsTheRunIsNoted) {
  TempDir dir;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  std::ofstream(dir.path() / "long.yaml")
      << std::string(kBaseCase) + "output: {frame_interval_s: 5, history_interval_s: 0.01}\n";
  std::ofstream(dir.path() / "half.yaml")
      << std::string(kBaseCase) + "output: {frame_interval_s: 0.005, history_interval_s: 0.005}\n";
  // 30 steps of 1e-5 s end at 3.0000000000000003e-4 s: an interval typed as
  // 0.0003 s is the run's own length, used as it is (no "used as" clause).
  {
    std::string text = kBaseCase;
    text.replace(text.find("  dt_s: 1.0e-4\n  duration_s: 0.01\n"), 34, "  dt_s: 1.0e-5\n  duration_s: 0.0003\n");
    std::ofstream(dir.path() / "thirty.yaml") << text + "output: {frame_interval_s: 0.0003, history_interval_s: 1e-5}\n";
  }
  // 0.00996 s is 99.6 steps, used as 100: the whole run, though shorter than it.
  std::ofstream(dir.path() / "rounded.yaml")
      << std::string(kBaseCase) + "output: {frame_interval_s: 0.005, history_interval_s: 0.00996}\n";
  const fs::path out = dir.path() / "out";
  const auto run = run_app({"run", (dir.path() / "long.yaml").string(), "--out", out.string(), "--quiet"}, dir.path());
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.err.find("framequake: note: output.frame_interval_s = 5 s is not shorter than the run (0.01 s): "
                         "frames are written at the start and the end only"),
            std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("framequake: note: output.history_interval_s = 0.01 s is not shorter than the run (0.01 s): "
                         "history.csv has rows at the start and the end only"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "frames"), fs::directory_iterator()), 2);
  std::ifstream history(out / "history.csv");
  int lines = 0;
  for (std::string line; std::getline(history, line);) ++lines;
  EXPECT_EQ(lines, 1 + 2);
  const auto half =
      run_app({"run", (dir.path() / "half.yaml").string(), "--out", (dir.path() / "half").string(), "--quiet"},
              dir.path());
  ASSERT_EQ(half.code, 0) << half.err;
  EXPECT_EQ(half.err.find("not shorter than the run"), std::string::npos) << half.err;
  const auto rounded =
      run_app({"run", (dir.path() / "rounded.yaml").string(), "--out", (dir.path() / "rounded").string(), "--quiet"},
              dir.path());
  ASSERT_EQ(rounded.code, 0) << rounded.err;
  const auto thirty =
      run_app({"run", (dir.path() / "thirty.yaml").string(), "--out", (dir.path() / "thirty").string(), "--quiet"},
              dir.path());
  ASSERT_EQ(thirty.code, 0) << thirty.err;
  EXPECT_NE(thirty.err.find("framequake: note: output.frame_interval_s = 0.0003 s is not shorter than the run (0.0003 "
                            "s): frames are written at the start and the end only"),
            std::string::npos)
      << thirty.err;
  EXPECT_NE(rounded.err.find("framequake: note: output.history_interval_s = 0.00996 s, used as 100 steps (0.01 s), is "
                             "not shorter than the run (0.01 s): history.csv has rows at the start and the end only"),
            std::string::npos)
      << rounded.err;
}

// Output intervals are whole numbers of steps (io/run_output.h). info
// counts the frames and rows run will write, and says, as run does, when
// an interval was rounded; the run's own files are the reference. Base
// case: 100 steps of 1e-4 s. Frames asked every 2.5 steps: every 3 (the
// nearest, rounding half away from zero), steps 0, 3, ..., 99 and the last
// state, step 100: 35. Rows asked every 0.1 step: every step, 101.
TEST(CliInfo, InfoCountsTheFramesAndRowsRunWritesAndBothSayWhenAnIntervalWasRounded) {
  TempDir dir;
  const std::string text =
      std::string(kBaseCase) + "output: {frame_interval_s: 0.00025, history_interval_s: 0.00001}\n";
  std::ofstream(dir.path() / "case.yaml") << text;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const auto info = run_app({"info", (dir.path() / "case.yaml").string()}, dir.path());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find(": 35 frames every 0.0003 s, 101 history rows every 0.0001 s"), std::string::npos)
      << info.out;
  EXPECT_NE(info.out.find("note        output.frame_interval_s = 0.00025 s is not a whole number of time steps"),
            std::string::npos)
      << info.out;
  EXPECT_NE(info.out.find("output.history_interval_s = 1e-05 s is shorter than one time step"), std::string::npos)
      << info.out;
  const fs::path out = dir.path() / "out";
  const auto run = run_app({"run", (dir.path() / "case.yaml").string(), "--out", out.string(), "--quiet"}, dir.path());
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.err.find("framequake: note: output.frame_interval_s = 0.00025 s"), std::string::npos) << run.err;
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "frames"), fs::directory_iterator()), 35);
  std::ifstream history(out / "history.csv");
  int lines = 0;
  for (std::string line; std::getline(history, line);) ++lines;
  EXPECT_EQ(lines, 1 + 101);
  // A checkpoint interval shorter than a step is refused (a checkpoint at
  // every step made a probe's 0.04 s run take 5.5 s).
  const auto every_step = run_app({"run", (dir.path() / "case.yaml").string(), "--out", (dir.path() / "cp").string(),
                                   "--quiet", "--checkpoint-every", "1e-9"},
                                  dir.path());
  EXPECT_EQ(every_step.code, 2);
  EXPECT_NE(every_step.err.find("'--checkpoint-every': expected at least one time step"), std::string::npos)
      << every_step.err;
  EXPECT_FALSE(fs::exists(dir.path() / "cp"));
}

// A run longer than its ground motion goes on with the ground still; info
// and run say when the motion ends (the base record: 6 samples 0.01 s
// apart, 0.05 s), and say nothing when the run ends first.
TEST(CliInfo, ARunLongerThanItsGroundMotionIsToldWhenTheMotionEnds) {
  TempDir dir;
  std::string text = kBaseCase;
  const std::string duration = "  duration_s: 0.01\n";
  ASSERT_NE(text.find(duration), std::string::npos);
  std::ofstream(dir.path() / "short.yaml") << text;
  text.replace(text.find(duration), duration.size(), "  duration_s: 0.1\n");
  std::ofstream(dir.path() / "long.yaml") << text;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const auto longer = run_app({"info", (dir.path() / "long.yaml").string()}, dir.path());
  ASSERT_EQ(longer.code, 0) << longer.err;
  EXPECT_NE(longer.out.find("note        the ground motion ends at t = 0.05 s; from there to the run's end at 0.1 s"),
            std::string::npos)
      << longer.out;
  const auto shorter = run_app({"info", (dir.path() / "short.yaml").string()}, dir.path());
  ASSERT_EQ(shorter.code, 0) << shorter.err;
  EXPECT_EQ(shorter.out.find("ground motion ends"), std::string::npos) << shorter.out;
  const auto run = run_app({"run", (dir.path() / "long.yaml").string(), "--out", (dir.path() / "out").string(),
                            "--quiet"},
                           dir.path());
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.err.find("framequake: note: the ground motion ends at t = 0.05 s"), std::string::npos) << run.err;
}

// Record time counts from a record's first sample: a two-column file whose
// times start at 5 s is shifted by -5 s, so window_start_s = 0.02 s plays
// its line at t = 5.02 s (cases/README.md, ground_motion). What history.csv
// shows at t = 0 is that line's value (the file's values differ line by
// line); info and run say where the window starts in the file's own times
// (a probe's window on such a file played another time than it expected,
// and nothing said so). A file starting at 0 gets no such note.
TEST(CliInfo, AWindowOnARecordStartingAfterZeroIsPlacedInTheFilesOwnTimes) {
  TempDir dir;
  std::string text = kBaseCase;
  const std::string gm = "ground_motion:\n  components:\n    - {file: rec.AT2, format: peer_at2, axis: x}\n";
  ASSERT_NE(text.find(gm), std::string::npos);
  text.replace(text.find(gm), gm.size(),
               "ground_motion:\n  window_start_s: 0.02\n  components:\n"
               "    - {file: late.txt, format: two_column, unit: m/s2, axis: x}\n");
  std::ofstream(dir.path() / "late.yaml") << text;
  std::ofstream(dir.path() / "late.txt") << "5.00 0.10\n5.01 0.20\n5.02 0.30\n5.03 0.40\n5.04 0.50\n5.05 0.60\n";
  const std::string said = "the times in " + (dir.path() / "late.txt").string() +
                           " start at 5 s; record time counts from that first sample, so window_start_s = 0.02 s is "
                           "t = 5.02 s in the file";
  const auto info = run_app({"info", (dir.path() / "late.yaml").string()}, dir.path());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("window from 0.02 s (" + said + ")"), std::string::npos) << info.out;
  const fs::path out = dir.path() / "out";
  const auto run = run_app({"run", (dir.path() / "late.yaml").string(), "--out", out.string(), "--quiet"}, dir.path());
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.err.find("framequake: note: " + said), std::string::npos) << run.err;
  // The first history row (t = 0): the ground acceleration of the line at 5.02 s.
  std::ifstream history(out / "history.csv");
  std::string header, first;
  ASSERT_TRUE(std::getline(history, header) && std::getline(history, first));
  std::vector<std::string> names, values;
  for (std::stringstream h(header); std::getline(h, names.emplace_back(), ',');) {
  }
  for (std::stringstream v(first); std::getline(v, values.emplace_back(), ',');) {
  }
  const auto column = std::find(names.begin(), names.end(), "ground_accel_x_mps2");
  ASSERT_NE(column, names.end()) << header;
  const std::size_t k = std::size_t(column - names.begin());
  ASSERT_LT(k, values.size());
  EXPECT_NEAR(std::stod(values[k]), 0.30, 1e-9) << first;
  // A window past the record's end is refused in the file's own times too.
  std::string past = text;
  past.replace(past.find("window_start_s: 0.02"), 20, "window_start_s: 0.06");
  std::ofstream(dir.path() / "past.yaml") << past;
  const auto refused = run_app({"info", (dir.path() / "past.yaml").string()}, dir.path());
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("(which ends at 0.05 s; record time counts from the record's first sample, t = 5 s in "
                             "the file, so its end is at t = 5.05 s in the file)"),
            std::string::npos)
      << refused.err;
  // The base record's times start at 0: nothing to say.
  std::ofstream(dir.path() / "base.yaml") << kBaseCase;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const auto base = run_app({"info", (dir.path() / "base.yaml").string()}, dir.path());
  ASSERT_EQ(base.code, 0) << base.err;
  EXPECT_EQ(base.out.find("record time counts from"), std::string::npos) << base.out;
}

TEST(CliErrors, MalformedCaseFiles) {
  for (const Row& row : kCaseRows) check_row(row, run_case(substitute(kBaseCase, row), kBaseRecord));
}

TEST(CliErrors, MalformedRecords) {
  for (const Row& row : kRecordRows) check_row(row, run_case(kBaseCase, substitute(kBaseRecord, row)));
}

TEST(CliErrors, BinaryGarbageIsRefusedNamingTheFile) {
  for (const bool in_record : {false, true}) {
    SCOPED_TRACE(in_record ? "record" : "case file");
    const Outcome o = in_record ? run_case(kBaseCase, kGarbage) : run_case(kGarbage, kBaseRecord);
    EXPECT_EQ(o.app.code, 2) << o.app.err;
    EXPECT_FALSE(o.out_folder_exists);
    EXPECT_NE(o.app.err.find(in_record ? "rec.AT2:" : "case.yaml:"), std::string::npos) << o.app.err;
    EXPECT_NE(o.app.err.find("expected"), std::string::npos) << o.app.err;
  }
}

TEST(CliErrors, ACaseFileThatIsAFolderIsCalledSo) {
  TempDir dir;
  fs::create_directories(dir.path() / "case.yaml");
  const fs::path out = dir.path() / "out";
  const auto r = run_app({"run", (dir.path() / "case.yaml").string(), "--out", out.string()}, dir.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("case file is a folder, not a file"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliErrors, MissingCaseFile) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const auto r = run_app({"run", (dir.path() / "nope.yaml").string(), "--out", out.string()}, dir.path());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("nope.yaml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not found"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// A time step above the stable estimate is refused (exit 2, nothing
// written); with --force the run goes ahead, exits 0, and says on stderr
// and in summary.json that it was forced (io/case_runner.h, kWarn*). The
// case is forced_cube_case.h; the factor printed is dt over the engine's
// own estimate (tests/io/test_run_warnings.cpp checks what the warnings
// say against physics).
TEST(CliErrors, TimeStepAboveTheLimitIsRefusedAndWhenForcedRunsWithAWarning) {
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml", std::ios::binary) << fq_test::kForcedCubeCase;
  const fs::path out = dir.path() / "out";
  const std::vector<std::string> args = {"run", (dir.path() / "case.yaml").string(), "--out", out.string(), "--quiet"};
  // info says so before any run (and still describes the case: exit 0).
  const auto info = run_app({"info", (dir.path() / "case.yaml").string()}, dir.path());
  EXPECT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("ABOVE THE STABLE LIMIT: run refuses this time step unless --force is given"),
            std::string::npos)
      << info.out;
  const auto refused = run_app(args, dir.path());
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("case.yaml:3: field 'time.dt_s'"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("exceeds the stable time step"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(out));

  std::vector<std::string> forced_args = args;
  forced_args.push_back("--force");
  const auto forced = run_app(forced_args, dir.path());
  EXPECT_EQ(forced.code, 0) << forced.err;
  EXPECT_NE(forced.err.find("framequake: warning: dt_s = 0.001 s is 4.2"), std::string::npos) << forced.err;
  EXPECT_NE(forced.err.find("the run was forced"), std::string::npos) << forced.err;
  const std::string summary = fq_test::read_text(out / "summary.json");
  EXPECT_NE(summary.find("\"warnings\": [\"dt_s = 0.001 s is 4.2"), std::string::npos) << summary;
}

// An integrator that cannot serve the scene's force providers (rk4 and
// gsl_rk8pd evaluate trial states; the cube's contacts keep history
// between evaluations, dem_core/simulation.h) is refused by run and by info
// alike, exit 2, nothing written, whatever --force says. The message names
// where the choice was made: the case file's `integrator` key with its
// line, or the command-line option without a file line. Forward Euler,
// whose stable limit (2 zeta / omega on each damped mode, none on an
// undamped one) the engine does not estimate, is refused naming the
// integrator, not the time step, and without calling the damped contact
// modes unstable at every dt (a probe ran them stably at 1e-4 s).
TEST(CliErrors, IntegratorTheSceneCannotUseIsRefusedWhereItWasChosen) {
  TempDir dir;
  std::string block_time = fq_test::kForcedCubeCase;
  const std::string flow = "time: {dt_s: 1.0e-3, duration_s: 0.05}\n";
  ASSERT_NE(block_time.find(flow), std::string::npos);
  // Lines 3-6: time, dt_s, duration_s, integrator.
  block_time.replace(block_time.find(flow), flow.size(),
                     "time:\n  dt_s: 1.0e-4\n  duration_s: 0.05\n  integrator: rk4\n");
  std::ofstream(dir.path() / "rk4.yaml", std::ios::binary) << block_time;
  std::ofstream(dir.path() / "cube.yaml", std::ios::binary) << fq_test::kForcedCubeCase;
  const fs::path out = dir.path() / "out";
  const std::string rk4_case = (dir.path() / "rk4.yaml").string();
  const std::string cube_case = (dir.path() / "cube.yaml").string();

  const auto refused = run_app({"run", rk4_case, "--out", out.string(), "--quiet", "--force"}, dir.path());
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("rk4.yaml:6: field 'time.integrator'"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("evaluates forces at trial states"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(out));
  // info describes the case all the same (exit 0, as for a dt above the
  // limit) and says on one line that run would refuse, and why, in run's
  // words (it exited 2 with the refusal alone).
  const auto described = run_app({"info", rk4_case}, dir.path());
  EXPECT_EQ(described.code, 0) << described.err;
  EXPECT_NE(described.out.find("bodies "), std::string::npos) << described.out;
  EXPECT_NE(described.out.find("output "), std::string::npos) << described.out;
  EXPECT_NE(described.out.find("RUN WOULD REFUSE THIS INTEGRATOR (--force does not override it): " + rk4_case +
                               ":6: field 'time.integrator': integrator rk4 evaluates forces at trial states"),
            std::string::npos)
      << described.out;
  EXPECT_TRUE(described.err.empty()) << described.err;
  const auto option = run_app({"run", cube_case, "--integrator", "gsl_rk8pd", "--out", out.string(), "--quiet"},
                              dir.path());
  EXPECT_EQ(option.code, 2) << option.err;
  EXPECT_NE(option.err.find("error: option '--integrator': integrator gsl_rk8pd"), std::string::npos) << option.err;
  EXPECT_EQ(option.err.find("cube.yaml:"), std::string::npos) << option.err;
  // The refusal says what keeps history, in the case file's words: the
  // contacts here, the trilinear springs of the breaking cantilever's
  // joints there.
  EXPECT_NE(option.err.find("contact shear springs and friction"), std::string::npos) << option.err;
  const auto trilinear = run_app({"run", (fs::path(FQ_SOURCE_DIR) / "cases/demo_breaking_cantilever.yaml").string(),
                                  "--integrator", "rk4", "--out", out.string(), "--quiet"},
                                 dir.path());
  EXPECT_EQ(trilinear.code, 2) << trilinear.err;
  EXPECT_NE(trilinear.err.find("springs of law trilinear"), std::string::npos) << trilinear.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out));

  const auto euler = run_app({"run", cube_case, "--integrator=forward_euler", "--out", out.string(), "--quiet"},
                             dir.path());
  EXPECT_EQ(euler.code, 2) << euler.err;
  EXPECT_NE(euler.err.find("option '--integrator': forward_euler is stable only while dt_s < 2 zeta / omega"),
            std::string::npos)
      << euler.err;
  EXPECT_FALSE(fs::exists(out));
  // info says so too, without a "stable limit" of 0 s that dt_s cannot take.
  std::string euler_case = fq_test::kForcedCubeCase;
  euler_case.replace(euler_case.find(flow), flow.size(), "time: {dt_s: 1.0e-5, duration_s: 0.05, integrator: forward_euler}\n");
  std::ofstream(dir.path() / "euler.yaml", std::ios::binary) << euler_case;
  const auto euler_info = run_app({"info", (dir.path() / "euler.yaml").string()}, dir.path());
  EXPECT_EQ(euler_info.code, 0) << euler_info.err;
  EXPECT_NE(euler_info.out.find("no stable time step with forward_euler"), std::string::npos) << euler_info.out;
  EXPECT_NE(euler_info.out.find("NO ESTIMATED STABLE STEP"), std::string::npos) << euler_info.out;
  EXPECT_EQ(euler_info.out.find("grows at every dt"), std::string::npos) << euler_info.out;
  EXPECT_EQ(euler_info.out.find("stable limit 0"), std::string::npos) << euler_info.out;
}

// info takes --integrator as run does, to preview another integrator's
// stable limit and whether run would take it (it was an unknown option).
// Every reason run would refuse is a line of the description, exit 0; the
// integrator's own refusal is named as the option, not the case file.
TEST(CliInfo, IntegratorOptionPreviewsWhatRunWouldDoWithIt) {
  TempDir dir;
  std::ofstream(dir.path() / "cube.yaml", std::ios::binary) << fq_test::kForcedCubeCase;
  const std::string cube_case = (dir.path() / "cube.yaml").string();
  const auto plain = run_app({"info", cube_case}, dir.path());
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(plain.out.find("NO ESTIMATED STABLE STEP"), std::string::npos) << plain.out;
  EXPECT_EQ(plain.out.find("from --integrator"), std::string::npos) << plain.out;

  const auto euler = run_app({"info", cube_case, "--integrator", "forward_euler"}, dir.path());
  EXPECT_EQ(euler.code, 0) << euler.err;
  EXPECT_NE(euler.out.find("(forward_euler, from --integrator)"), std::string::npos) << euler.out;
  EXPECT_NE(euler.out.find("NO ESTIMATED STABLE STEP: run refuses this integrator here unless --force is given"),
            std::string::npos)
      << euler.out;

  // The cube's contacts keep history: rk4 is refused, whatever --force says;
  // its dt is also above the limit (forced_cube_case.h): two lines.
  const auto rk4 = run_app({"info", cube_case, "--integrator=rk4"}, dir.path());
  EXPECT_EQ(rk4.code, 0) << rk4.err;
  EXPECT_NE(rk4.out.find("(rk4, from --integrator)"), std::string::npos) << rk4.out;
  EXPECT_NE(rk4.out.find("ABOVE THE STABLE LIMIT: run refuses this time step unless --force is given"),
            std::string::npos)
      << rk4.out;
  EXPECT_NE(rk4.out.find("RUN WOULD REFUSE THIS INTEGRATOR (--force does not override it): option '--integrator': "
                         "integrator rk4 evaluates forces at trial states"),
            std::string::npos)
      << rk4.out;
  EXPECT_NE(rk4.out.find("contact shear springs and friction"), std::string::npos) << rk4.out;
  EXPECT_EQ(rk4.out.find("cube.yaml:"), std::string::npos) << rk4.out;

  // The trilinear springs of the breaking cantilever, as run names them.
  const auto trilinear = run_app(
      {"info", (fs::path(FQ_SOURCE_DIR) / "cases/demo_breaking_cantilever.yaml").string(), "--integrator", "rk4"},
      dir.path());
  EXPECT_EQ(trilinear.code, 0) << trilinear.err;
  EXPECT_NE(trilinear.out.find("RUN WOULD REFUSE THIS INTEGRATOR"), std::string::npos) << trilinear.out;
  EXPECT_NE(trilinear.out.find("springs of law trilinear"), std::string::npos) << trilinear.out;

  const auto bad = run_app({"info", cube_case, "--integrator", "leapfrog"}, dir.path());
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("--integrator expects one of"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("Usage: framequake info"), std::string::npos) << bad.err;
  EXPECT_EQ(bad.err.find("did you mean"), std::string::npos) << bad.err;
  const auto upper = run_app({"info", cube_case, "--integrator", "RK4"}, dir.path());
  EXPECT_EQ(upper.code, 2) << upper.err;
  EXPECT_NE(upper.err.find("got 'RK4' (did you mean 'rk4'?)"), std::string::npos) << upper.err;
}

// info --joints ends with one line per joint (id, name, node, members,
// type): the breaking cantilever's joints from its case file's ids, the
// column-arm joint at node top (planned first) and the support at base.
// Without it, a pointer to the option; run does not take it.
TEST(CliInfo, JointsOptionListsTheJoints) {
  TempDir dir;
  const std::string cantilever = (fs::path(FQ_SOURCE_DIR) / "cases/demo_breaking_cantilever.yaml").string();
  const auto listed = run_app({"info", cantilever, "--joints"}, dir.path());
  EXPECT_EQ(listed.code, 0) << listed.err;
  EXPECT_NE(listed.out.find(" 0  top:column-arm      node top: column column - beam arm (type weak_tenon)"),
            std::string::npos)
      << listed.out;
  EXPECT_NE(listed.out.find(" 1  base:ground-column  support base: ground - column column (type stiff_support)"),
            std::string::npos)
      << listed.out;
  const auto plain = run_app({"info", cantilever}, dir.path());
  EXPECT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(plain.out.find("top:column-arm"), std::string::npos) << plain.out;
  const auto run = run_app({"run", cantilever, "--joints"}, dir.path());
  EXPECT_EQ(run.code, 2) << run.err;
  EXPECT_NE(run.err.find("unknown option '--joints'"), std::string::npos) << run.err;
}

// The test's working folder moved to `p` while it lives: the program
// inherits it, so relative names given to it resolve there.
struct WorkIn {
  fs::path before = fs::current_path();
  explicit WorkIn(const fs::path& p) { fs::current_path(p); }
  ~WorkIn() { fs::current_path(before); }
  WorkIn(const WorkIn&) = delete;
  WorkIn& operator=(const WorkIn&) = delete;
};

// Every option also takes the form --option=value (a value may contain
// '='); the run then goes where --out= says.
TEST(CliUsage, OptionEqualsValueIsTheOptionFollowedByTheValue) {
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml", std::ios::binary) << fq_test::kForcedCubeCase;
  const fs::path out = dir.path() / "a=b";
  const auto r = run_app({"run", (dir.path() / "case.yaml").string(), "--out=" + out.string(), "--quiet", "--force",
                          "--integrator=velocity_verlet"},
                         dir.path());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(fq_test::read_text(out / "summary.json").find("\"integrator\": \"velocity_verlet\""), std::string::npos);
  const auto empty = run_app({"run", (dir.path() / "case.yaml").string(), "--out="}, dir.path());
  EXPECT_EQ(empty.code, 2) << empty.err;
  EXPECT_NE(empty.err.find("--out needs a value, got an empty one"), std::string::npos) << empty.err;
  // A flag given a value is named as such (it read as a stray argument).
  const auto flag = run_app({"run", (dir.path() / "case.yaml").string(), "--quiet=1"}, dir.path());
  EXPECT_EQ(flag.code, 2) << flag.err;
  EXPECT_NE(flag.err.find("option --quiet takes no value, got '--quiet=1'"), std::string::npos) << flag.err;
  // ... followed by run's usage, as every other run option error is (it
  // printed the top-level usage); each command's own.
  EXPECT_NE(flag.err.find("Usage: framequake run CASE [options]"), std::string::npos) << flag.err;
  EXPECT_EQ(flag.err.find("framequake --help               this text"), std::string::npos) << flag.err;
  const auto resume = run_app({"resume", dir.path().string(), "--quiet=yes"}, dir.path());
  EXPECT_EQ(resume.code, 2) << resume.err;
  EXPECT_NE(resume.err.find("Usage: framequake resume DIR"), std::string::npos) << resume.err;
  const auto compare = run_app({"compare", (dir.path() / "case.yaml").string(), "--no-figure=1"}, dir.path());
  EXPECT_EQ(compare.code, 2) << compare.err;
  EXPECT_NE(compare.err.find("Usage: framequake compare CASE..."), std::string::npos) << compare.err;
  // info's flag too (review probe: "unexpected argument 'yes' (one case file per run)").
  const auto info = run_app({"info", (dir.path() / "case.yaml").string(), "--joints=yes"}, dir.path());
  EXPECT_EQ(info.code, 2) << info.err;
  EXPECT_NE(info.err.find("option --joints takes no value, got '--joints=yes'"), std::string::npos) << info.err;
  // A value that looks like an option is a value in this form: the run goes
  // into the folder "--odd" (as ./--odd; "--out --odd" is refused instead).
  {
    const WorkIn work_in(dir.path());
    const auto odd = run_app({"run", "case.yaml", "--out=--odd", "--quiet", "--force"}, dir.path());
    EXPECT_EQ(odd.code, 0) << odd.err;
  }
  EXPECT_TRUE(fs::is_regular_file(dir.path() / "--odd" / "summary.json"));
}

// "--" ends the options: a case file whose name starts with '-' is given
// after it (it was "unknown option '--'"). Without "--" such a name reads
// as an option, as in every command line tool.
TEST(CliUsage, DoubleDashEndsTheOptions) {
  TempDir dir;
  std::ofstream(dir.path() / "-cube.yaml", std::ios::binary) << fq_test::kForcedCubeCase;
  // The name relative to the working folder, as a user types it.
  const WorkIn work_in(dir.path());
  const auto info = run_app({"info", "--", "-cube.yaml"}, dir.path());
  EXPECT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("-cube.yaml"), std::string::npos) << info.out;
  const auto run = run_app({"run", "--quiet", "--force", "--out", "o", "--", "-cube.yaml"}, dir.path());
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_TRUE(fs::exists(dir.path() / "o" / "summary.json"));
  const auto without = run_app({"info", "-cube.yaml"}, dir.path());
  EXPECT_EQ(without.code, 2) << without.err;
  EXPECT_NE(without.err.find("unknown option '-cube.yaml'"), std::string::npos) << without.err;
}

// FRAMEQUAKE_SIMD chooses the SIMD form of the lane kernels
// (dem_core/lane_isa.h): auto, sse2, avx2 or avx512vl. A bad value is bad input: exit
// 2, the variable and the accepted values named, no output folder. sse2 is
// available everywhere and runs the same case to the end.
TEST(CliErrors, BadSimdFormIsRefusedNamingTheVariable) {
  ::setenv("FRAMEQUAKE_SIMD", "avx9", 1);
  const Outcome bad = run_case(kBaseCase, kBaseRecord);
  ::setenv("FRAMEQUAKE_SIMD", "sse2", 1);
  const Outcome baseline = run_case(kBaseCase, kBaseRecord);
  ::unsetenv("FRAMEQUAKE_SIMD");
  EXPECT_EQ(bad.app.code, 2) << bad.app.err;
  EXPECT_FALSE(bad.out_folder_exists);
  EXPECT_NE(bad.app.err.find("FRAMEQUAKE_SIMD='avx9'"), std::string::npos) << bad.app.err;
  EXPECT_NE(bad.app.err.find("expected auto, sse2, avx2 or avx512vl"), std::string::npos) << bad.app.err;
  EXPECT_EQ(baseline.app.code, 0) << baseline.app.err;
  EXPECT_TRUE(baseline.out_folder_exists);
}

// OMP_NUM_THREADS that is not a positive whole number is bad input (libgomp
// only warns and goes on with its default); far more threads than cores is
// warned about, and runs (CLI probe: 1000 threads made a run 6x slower).
TEST(CliErrors, BadOmpNumThreadsIsRefusedAndTooManyWarned) {
  ::setenv("OMP_NUM_THREADS", "abc", 1);
  const Outcome bad = run_case(kBaseCase, kBaseRecord);
  const std::string too_many = std::to_string(8 * std::max(1u, std::thread::hardware_concurrency()));
  ::setenv("OMP_NUM_THREADS", too_many.c_str(), 1);
  const Outcome many = run_case(kBaseCase, kBaseRecord);
  ::setenv("OMP_NUM_THREADS", "1", 1);
  const Outcome one = run_case(kBaseCase, kBaseRecord);
  ::unsetenv("OMP_NUM_THREADS");
  EXPECT_EQ(bad.app.code, 2) << bad.app.err;
  EXPECT_FALSE(bad.out_folder_exists);
  EXPECT_NE(bad.app.err.find("OMP_NUM_THREADS='abc' is not a positive whole number"), std::string::npos)
      << bad.app.err;
  EXPECT_EQ(many.app.code, 0) << many.app.err;
  EXPECT_NE(many.app.err.find("OMP_NUM_THREADS=" + too_many + " is far more than the"), std::string::npos)
      << many.app.err;
  EXPECT_EQ(one.app.code, 0) << one.app.err;
  EXPECT_EQ(one.app.err.find("OMP_NUM_THREADS"), std::string::npos) << one.app.err;
  // --threads the same (it was silent at any count; docs probe).
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml") << kBaseCase;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const auto option = run_app({"run", (dir.path() / "case.yaml").string(), "--out", (dir.path() / "out").string(),
                               "--quiet", "--threads", too_many},
                              dir.path());
  EXPECT_EQ(option.code, 0) << option.err;
  EXPECT_NE(option.err.find("warning: --threads " + too_many + " is far more than the"), std::string::npos)
      << option.err;
}

// ---- usage -------------------------------------------------------------------

TEST(CliUsage, HelpForEveryCommandExitsZeroWithUsage) {
  TempDir dir;
  const std::vector<std::vector<std::string>> calls = {
      {"--help"}, {"-h"}, {"help"}, {"run", "--help"}, {"info", "--help"}};
  for (const auto& args : calls) {
    SCOPED_TRACE(args.size() > 1 ? args[0] + " " + args[1] : args[0]);
    const auto r = run_app(args, dir.path());
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;
  }
  const auto run_help = run_app({"run", "--help"}, dir.path());
  EXPECT_NE(run_help.out.find("--out DIR"), std::string::npos);
  EXPECT_NE(run_help.out.find("Exit codes"), std::string::npos);
  // "help COMMAND" gives that command's help, as "COMMAND --help" does.
  // So do "--help COMMAND" and "-h COMMAND" (they printed the top-level help).
  for (const std::string command : {"run", "info", "resume", "compare", "sweep"}) {
    const auto direct = run_app({command, "--help"}, dir.path());
    for (const std::string asking : {"help", "--help", "-h"}) {
      const auto asked = run_app({asking, command}, dir.path());
      EXPECT_EQ(asked.code, 0) << asking << " " << command << ": " << asked.err;
      EXPECT_EQ(asked.out, direct.out) << asking << " " << command;
    }
  }
  const auto version = run_app({"--version"}, dir.path());
  EXPECT_EQ(version.code, 0);
  EXPECT_EQ(version.out.rfind("framequake ", 0), 0u) << version.out;
}

TEST(CliUsage, UsageErrorsExitTwoWithUsageOnStderr) {
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml") << kBaseCase;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const std::string c = (dir.path() / "case.yaml").string();
  struct UsageRow {
    std::vector<std::string> args;
    const char* message;
  };
  const UsageRow rows[] = {
      {{}, "missing command"},
      {{"frobnicate"}, "unknown command 'frobnicate'"},
      {{"run"}, "missing CASE"},
      {{"info"}, "missing CASE"},
      {{"run", c, "--bogus"}, "unknown option '--bogus'"},
      {{"info", c, "--out", "x"}, "unknown option '--out'"},
      {{"run", c, "--out"}, "--out needs a value"},
      {{"run", c, "--out", ""}, "--out needs a value, got an empty one"},
      {{"compare", c, "--out", ""}, "--out needs a value, got an empty one"},
      {{"run", c, "--threads", "0"}, "--threads expects a whole number"},
      {{"run", c, "--threads", "two"}, "--threads expects a whole number"},
      {{"run", c, c}, "unexpected argument"},
      // Which of two values was meant is not guessed (the last won silently).
      {{"run", c, "--integrator", "rk4", "--integrator", "velocity_verlet"}, "--integrator is given twice"},
      {{"run", c, "--out", "a", "--out", "b"}, "--out is given twice"},
      // compare and sweep as run (they kept the last value; CLI probe).
      {{"compare", c, "--out", "a", "--out", "b"}, "--out is given twice"},
      {{"compare", c, "--jobs", "1", "--jobs", "2"}, "--jobs is given twice"},
      {{"sweep", c, "--scales", "1", "--scales", "2"}, "--scales is given twice"},
      {{"sweep", c, "--window-length", "1", "--window-length", "0.5"}, "--window-length is given twice"},
      // An unknown option names the command's option it probably meant
      // (io/name_hint.h, nearest_option): a misspelling, a longer word than
      // the option, a beginning of it; nothing when no option is near.
      {{"run", c, "--output", "x"}, "unknown option '--output' (did you mean '--out'?)"},
      {{"run", c, "--thread", "2"}, "unknown option '--thread' (did you mean '--threads'?)"},
      {{"run", c, "--integ", "rk4"}, "unknown option '--integ' (did you mean '--integrator'?)"},
      {{"sweep", c, "--scale", "1"}, "unknown option '--scale' (did you mean '--scales'?)"},
      {{"compare", c, "--window", "1"}, "unknown option '--window' (did you mean '--window-length'?)"},
      {{"compare", c, "--no_figure"}, "unknown option '--no_figure' (did you mean '--no-figure'?)"},
      {{"resume", dir.path().string(), "--quite"}, "unknown option '--quite' (did you mean '--quiet'?)"},
      {{"run", c, "--bogus"}, "unknown option '--bogus'\n"},
      {{"info", c, "--out", "x"}, "unknown option '--out'\n"},
      {{"render"}, "missing OUT_DIR"},
      {{"render", dir.path().string(), "--fsp", "3"}, "unknown option '--fsp' (did you mean '--fps'?)"},
      // Words after --version or a help request are named, not ignored with
      // exit 0 (CLI probe: "--version extra", "--help run x y").
      {{"--version", "extra"}, "unexpected argument 'extra' after --version"},
      {{"--version", "--bogus"}, "unexpected argument '--bogus' after --version"},
      {{"--help", "run", "x", "y"}, "unexpected argument 'x' after --help run"},
      {{"help", "run", "x"}, "unexpected argument 'x' after help run"},
      {{"-h", "--bogus"}, "unexpected argument '--bogus' after -h"},
      {{"help", "frobnicate"}, "unknown command 'frobnicate'"},
      // Numbers are decimal, as in the case file (which refuses 0x10):
      // strtod read "--scales 0x1" as hexadecimal and ran a folder "..._x1"
      // (black-box probe); strtol took leading spaces and '+'.
      {{"sweep", c, "--scales", "0x1"}, "--scales expects a positive number, got '0x1'"},
      {{"sweep", c, "--scales", "1,0x2"}, "--scales expects a positive number, got '0x2'"},
      {{"sweep", c, "--window-length", "0x1p-1"}, "--window-length expects a positive number, got '0x1p-1'"},
      {{"compare", c, "--window-length", " 1"}, "--window-length expects a positive number, got ' 1'"},
      {{"run", c, "--checkpoint-every", "0x1"}, "--checkpoint-every expects a positive number of simulated seconds, got '0x1'"},
      {{"run", c, "--threads", " 2"}, "--threads expects a whole number from 1 to 1024, got ' 2'"},
      {{"compare", c, "--jobs", "+2"}, "--jobs expects a whole number from 1 to 256, got '+2'"},
      {{"resume", dir.path().string(), "--threads", "0x2"}, "--threads expects a whole number from 1 to 1024, got '0x2'"},
      {{"render", dir.path().string(), "--fps", " 5"}, "--fps expects a whole number from 1 to 100, got ' 5'"},
      // An option where a value belongs: the value is missing (studies
      // probe: "compare --out --no-figure" wrote into a folder named
      // "--no-figure"; "sweep --record --scales 1" read --scales as a record).
      {{"compare", c, "--out", "--no-figure"}, "--out needs a value, got the option '--no-figure' (a file or folder "
                                               "whose name starts with '--' is written ./--no-figure)"},
      {{"sweep", c, "--record", "--scales", "1"}, "--record needs a value, got the option '--scales'"},
      {{"run", c, "--out", "--quiet"}, "--out needs a value, got the option '--quiet'"},
      {{"run", c, "--integrator", "--force"}, "--integrator needs a value, got the option '--force'"},
      {{"resume", dir.path().string(), "--case", "--quiet"}, "--case needs a value, got the option '--quiet'"},
      {{"resume", dir.path().string(), "--threads", "--quiet"}, "--threads needs a value, got the option '--quiet'"},
      {{"render", dir.path().string(), "--to", "--png"}, "--to needs a value, got the option '--png'"},
  };
  for (const UsageRow& row : rows) {
    std::string shown;
    for (const auto& a : row.args) shown += a + " ";
    SCOPED_TRACE(shown);
    const auto r = run_app(row.args, dir.path());
    EXPECT_EQ(r.code, 2) << r.err;
    // Worded as every other error is ("framequake: error: ..."), then the usage.
    EXPECT_NE(r.err.find(std::string("framequake: error: ") + row.message), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("Usage"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

// What a command prints must reach its reader: with standard output on a
// full device, `info` and `--help` end with exit 3 and say so (they ended
// with 0 and nothing written; CLI probe). Run through the shell for the
// redirection.
TEST(CliErrors, AFullStandardOutputIsAnOutputFailure) {
  TempDir dir;
  const std::string app = FQ_APP_PATH;
  const std::string err = (dir.path() / "err.txt").string();
  const std::string case_file = (fs::path(FQ_SOURCE_DIR) / "cases/demo_falling_block.yaml").string();
  for (const std::string& args : {"info '" + case_file + "'", std::string("--help")}) {
    SCOPED_TRACE(args);
    const int status = std::system(("'" + app + "' " + args + " > /dev/full 2> '" + err + "'").c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 3);
    EXPECT_NE(fq_test::read_text(err).find("cannot write to standard output"), std::string::npos)
        << fq_test::read_text(err);
  }
  const int ok = std::system(("'" + app + "' info '" + case_file + "' > /dev/null 2> '" + err + "'").c_str());
  EXPECT_EQ(WEXITSTATUS(ok), 0);
}

// A file system that reports a failed write only when history.csv or
// events.csv is closed (EIO at close, made by the preloaded
// fail_close_shim) fails the run as one at a frame or the summary does:
// exit 3, a message naming the file and the reason, and summary.json
// saying output_failed. It ended with exit 0 and status "completed".
TEST(CliErrors, AFileThatFailsToCloseIsAnOutputFailure) {
#ifndef FQ_FAIL_CLOSE_SHIM
  GTEST_SKIP() << "no close-failing library in a sanitizer build (tests/apps/CMakeLists.txt)";
#else
  TempDir dir;
  const fs::path case_file = dir.path() / "block.yaml";
  std::ofstream(case_file) << "framequake_case: 1\n"
                              "name: block\n"
                              "time: {dt_s: 1.0e-4, duration_s: 0.01}\n"
                              "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
                              "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: spruce}]\n";
  for (const char* name : {"history.csv", "events.csv"}) {
    SCOPED_TRACE(name);
    const fs::path out = dir.path() / (std::string("out_") + name);
    ::setenv("LD_PRELOAD", FQ_FAIL_CLOSE_SHIM, 1);
    ::setenv("FQ_FAIL_CLOSE_SUFFIX", (out / name).c_str(), 1);
    const auto r = run_app({"run", case_file.string(), "--out", out.string(), "--quiet"}, dir.path());
    ::unsetenv("LD_PRELOAD");
    ::unsetenv("FQ_FAIL_CLOSE_SUFFIX");
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("cannot close '" + (out / name).string() + "': Input/output error"), std::string::npos)
        << r.err;
    const std::string summary = fq_test::read_text(out / "summary.json");
    EXPECT_NE(summary.find("\"status\": \"output_failed\""), std::string::npos) << summary;
  }
  // The same run without the failure completes (the case is sound).
  const auto ok = run_app({"run", case_file.string(), "--out", (dir.path() / "out_ok").string(), "--quiet"},
                          dir.path());
  EXPECT_EQ(ok.code, 0) << ok.err;
#endif
}

}  // namespace

namespace {

// info lists what a run's verdicts rest on: the joints and the storeys
// (frame B: 24 four-corner joints of 12 springs, two storeys of 0.29 m on
// four columns each, cases/frame_B.yaml), and warns of a node inside a
// member, as run does (io/case_runner.h, nodes_inside_members_warning).
// A link_system joint type without shear_link has no stiffness against
// shear along its t2 axis (joints/joint_layout.h: K_t2 = 4 k_s sin^2 theta);
// info (and run) note it for each such type in use, and not for the same
// type with shear links or for the shipped frames (four-corner joints).
// Names a file system cannot hold, and scales no earthquake reaches, are
// refused before anything runs (error probe, 2026-11-27: an output folder
// name over 255 bytes ended the run with the library's bare "File name too
// long", exit 3; an amplitude_scale of 100, a percentage, ran a record at
// 83 g to the end). The base record peaks at 0.003 g.
TEST(CliErrors, AnOutputFolderNameTooLongOrASweepScalePast20gIsRefusedBeforeAnyRun) {
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml") << kBaseCase;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const fs::path c = dir.path() / "case.yaml";
  const std::string long_name(300, 'o');
  const auto run = run_app({"run", c.string(), "--out", (dir.path() / long_name).string(), "--quiet"}, dir.path());
  EXPECT_EQ(run.code, 3) << run.err;
  EXPECT_NE(run.err.find("is 300 bytes long, more than the 255 a file name may have"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("File name too long"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir.path() / long_name.substr(0, 255)));
  // 0.003 g x 5000 = 15 g passes; x 7000 = 21 g does not.
  const fs::path out = dir.path() / "sweep";
  const auto sweep = run_app({"sweep", c.string(), "--scales", "5000,7000", "--out", out.string(), "--no-figure"},
                             dir.path());
  EXPECT_EQ(sweep.code, 2) << sweep.err;
  EXPECT_NE(sweep.err.find("option '--scales': 'cli_errors' with rec.AT2: amplitude scale 7000 takes the record's "
                           "peak of 0.003 g to 21 g, more than 20 g"),
            std::string::npos)
      << sweep.err;
  EXPECT_FALSE(fs::exists(out / "cli_errors_rec_x5000"));
}

// A member copied and not edited: two boxes between the same two nodes.
TEST(CliInfo, AMemberBetweenTheSameNodesAsAnotherIsWarnedOf) {
  std::string text = kBaseCase;
  const std::string col = "  - {id: col, kind: column, nodes: [a, b], section: s50, material: spruce}\n";
  ASSERT_NE(text.find(col), std::string::npos);
  text.insert(text.find(col) + col.size(), "  - {id: twin, kind: column, nodes: [b, a], section: s50, material: spruce}\n");
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml") << text;
  std::ofstream(dir.path() / "rec.AT2") << kBaseRecord;
  const auto info = run_app({"info", (dir.path() / "case.yaml").string()}, dir.path());
  EXPECT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("1 member runs between the same two nodes as another ('twin' (line 18) and 'col' (line "
                          "17) between nodes 'b' and 'a'): two boxes in one place double"),
            std::string::npos)
      << info.out;
  // The base case has no such pair.
  std::ofstream(dir.path() / "case.yaml") << kBaseCase;
  const auto base = run_app({"info", (dir.path() / "case.yaml").string()}, dir.path());
  EXPECT_EQ(base.out.find("same two nodes"), std::string::npos) << base.out;
}

TEST(CliErrors, InfoNotesAPlanarLinkSystem) {
  TempDir dir;
  auto info_of = [&](const std::string& shear_link) {
    std::ofstream(dir.path() / "links.yaml", std::ios::binary)
        << "framequake_case: 1\n"
           "time: {dt_s: 1.0e-5, duration_s: 0.01}\n"
           "materials: [{name: wood, density_kg_per_m3: 500}]\n"
           "sections: [{name: sec, width_m: 0.02, depth_m: 0.04}]\n"
           "nodes: [{id: base, xyz_m: [0, 0, 0]}, {id: top, xyz_m: [0, 0, 0.2]}]\n"
           "members: [{id: col, kind: column, nodes: [base, top], section: sec, material: wood}]\n"
           "joint_types:\n"
           "  - name: links\n"
           "    layout: link_system\n"
           "    gap_m: 0.01\n"
           "    axial: {law: linear, stiffness_N_per_m: 1.0e4}\n"
           "    diagonal: {law: linear, stiffness_N_per_m: 2.0e4}\n"
        << shear_link << "supports: [{node: base, joint_type: links}]\n";
    const auto r = run_app({"info", (dir.path() / "links.yaml").string()}, dir.path());
    EXPECT_EQ(r.code, 0) << r.err;
    return r.out;
  };
  const std::string planar = info_of("");
  EXPECT_NE(planar.find("note        joint type 'links' is a link_system without shear_link"), std::string::npos)
      << planar;
  const std::string spatial = info_of("    shear_link: {law: linear, stiffness_N_per_m: 1.0e4}\n");
  EXPECT_EQ(spatial.find("without shear_link"), std::string::npos) << spatial;
  for (const char* name : {"frame_A.yaml", "frame_B.yaml", "frame_C.yaml"}) {
    const auto r = run_app({"info", (fs::path(FQ_SOURCE_DIR) / "cases" / name).string()}, dir.path());
    EXPECT_EQ(r.out.find("without shear_link"), std::string::npos) << name;
  }
}

TEST(CliErrors, InfoListsJointsAndStoreysAndWarnsOfANodeInsideAMember) {
  TempDir dir;
  const fs::path frame_b = fs::path(FQ_SOURCE_DIR) / "cases" / "frame_B.yaml";
  const auto info = run_app({"info", frame_b.string()}, dir.path());
  EXPECT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("joints      24 (288 springs)"), std::string::npos) << info.out;
  // The joints by type (frame B's 24 are all tenon_new: default and
  // support type, cases/frame_B.yaml) and frame C's braces beside them, so
  // a retrofit shows; and the drift limits the verdicts will use (the
  // defaults, 1/30 and 1/10 rad).
  EXPECT_NE(info.out.find("            by type: tenon_new 24\n"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("            verdicts: damaged above 0.0333333 rad, collapsed from 0.1 rad"), std::string::npos)
      << info.out;
  const auto info_c = run_app({"info", (fs::path(FQ_SOURCE_DIR) / "cases" / "frame_C.yaml").string()}, dir.path());
  EXPECT_NE(info_c.out.find("            by type: tenon_new 24, brace_end 4\n"), std::string::npos) << info_c.out;
  EXPECT_NE(info.out.find("storeys     2\n"
                          "            1 from z = 0 to 0.29 m, 4 columns: column1_se, column1_ne, column1_sw, column1_nw\n"
                          "            2 from z = 0.29 to 0.58 m, 4 columns: column2_se, column2_ne, column2_sw, column2_nw\n"
                          "            verdicts:"),
            std::string::npos)
      << info.out;
  EXPECT_EQ(info.out.find("warning"), std::string::npos) << info.out;
  std::ofstream(dir.path() / "through.yaml", std::ios::binary)
      << "framequake_case: 1\n"
         "time: {dt_s: 1.0e-5, duration_s: 0.001}\n"
         "materials: [{name: wood, density_kg_per_m3: 450}]\n"
         "sections: [{name: s, width_m: 0.010, depth_m: 0.010}]\n"
         "nodes:\n"
         "  - {id: m0, xyz_m: [0, 0, 0]}\n"
         "  - {id: m1, xyz_m: [0, 0, 0.3]}\n"
         "  - {id: m2, xyz_m: [0, 0, 0.6]}\n"
         "  - {id: far, xyz_m: [0.5, 0, 0.3]}\n"
         "members:\n"
         "  - {id: col, kind: column, nodes: [m0, m2], section: s, material: wood}\n"
         "  - {id: beam, kind: beam, nodes: [m1, far], section: s, material: wood}\n";
  const auto through = run_app({"info", (dir.path() / "through.yaml").string()}, dir.path());
  EXPECT_EQ(through.code, 0) << through.err;
  EXPECT_NE(through.out.find("warning     "), std::string::npos) << through.out;
  EXPECT_NE(through.out.find("node 'm1' (line 7) inside or on member 'col' (line 11)"), std::string::npos) << through.out;
}

}  // namespace
