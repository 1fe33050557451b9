// Crash-safe output: a `framequake run` killed at any moment leaves a folder
// ParaView can open, and SIGINT or SIGTERM stops a run cleanly.
//
// What must hold (apps/main.cpp, io/run_output.h): case.pvd is replaced
// atomically after each frame, so at any instant it is well-formed XML that
// lists only frames already complete on disk; each listed frame opens with
// VTK's own reader and has one hexahedron per body (vtk_frame_writer.cpp,
// add_bodies). SIGINT or SIGTERM: exit code 128 + the signal (130, 143),
// summary.json with status "stopped" and a message saying why,
// and a final frame at the time the run stopped.
//
// The case is N spinning blocks in space (no gravity, no ground, no
// contacts) for a simulated time far longer than the test waits, so every
// kill lands in the middle of the run whatever the machine's speed.
#include <gtest/gtest.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "app_process.h"

namespace {

namespace fs = std::filesystem;
using fq_test::AppProcess;
using fq_test::TempDir;

constexpr int kBlocks = 24;

std::string long_case() {
  std::string s =
      "framequake_case: 1\n"
      "name: crash_safety\n"
      "time:\n"
      "  dt_s: 1.0e-4\n"
      "  duration_s: 10000.0\n"  // 1e8 steps: never reached while the test waits
      "  gravity_mps2: [0, 0, 0]\n"
      "materials:\n"
      "  - {name: spruce, density_kg_per_m3: 450}\n"
      "output:\n"
      "  frame_interval_s: 0.02\n"
      "  history_interval_s: 0.01\n"
      "blocks:\n";
  for (int i = 0; i < kBlocks; ++i)
    s += "  - {id: b" + std::to_string(i) + ", size_m: [0.1, 0.05, 0.2], center_m: [" + std::to_string(i % 6) +
         ", " + std::to_string(i / 6) + ", 1], material: spruce, angular_velocity_radps: [1, 2, 3]}\n";
  return s;
}

struct PvdEntry {
  double time_s = 0.0;
  std::string file;
};

// Parses case.pvd with VTK's XML parser; false if it is not well-formed or
// not a VTK Collection.
bool parse_pvd(const fs::path& pvd, std::vector<PvdEntry>& entries, std::string& why) {
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(pvd.c_str());
  if (!parser->Parse()) {
    why = "not well-formed XML";
    return false;
  }
  vtkXMLDataElement* root = parser->GetRootElement();
  if (!root || std::string(root->GetName()) != "VTKFile" || !root->GetAttribute("type") ||
      std::string(root->GetAttribute("type")) != "Collection") {
    why = "root is not <VTKFile type=\"Collection\">";
    return false;
  }
  vtkXMLDataElement* coll = root->FindNestedElementWithName("Collection");
  if (!coll) {
    why = "no <Collection>";
    return false;
  }
  for (int i = 0; i < coll->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* ds = coll->GetNestedElement(i);
    const char* file = ds->GetAttribute("file");
    double t = 0.0;
    if (std::string(ds->GetName()) != "DataSet" || !file || !ds->GetScalarAttribute("timestep", t)) {
      why = "a DataSet without file or timestep";
      return false;
    }
    entries.push_back({t, file});
  }
  return true;
}

// Every frame case.pvd lists exists, opens with vtkXMLUnstructuredGridReader
// and holds one cell per body.
void check_listed_frames(const fs::path& folder, const std::vector<PvdEntry>& entries) {
  double previous_t = -1.0;
  for (const PvdEntry& e : entries) {
    SCOPED_TRACE(e.file);
    EXPECT_GT(e.time_s, previous_t) << "frame times must increase";
    previous_t = e.time_s;
    const fs::path p = folder / e.file;
    ASSERT_TRUE(fs::is_regular_file(p)) << "case.pvd lists a frame that does not exist";
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(p.c_str());
    ASSERT_TRUE(reader->CanReadFile(p.c_str()));
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    ASSERT_NE(grid, nullptr);
    EXPECT_EQ(grid->GetNumberOfCells(), kBlocks);
    EXPECT_EQ(grid->GetNumberOfPoints(), 8 * kBlocks);
  }
}

// Waits (without a deadline of its own: ctest's timeout bounds it) until the
// run has set up its folder; case.pvd appears after the SIGINT handler is
// installed (apps/main.cpp installs it before run_case).
bool wait_for_file(const fs::path& p) {
  for (int i = 0; i < 60000; ++i) {
    if (fs::exists(p)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

// Kills a run with SIGKILL `wait_ms` after it started (or, for
// after_setup, that long after case.pvd first appeared) and checks what is
// left. Returns the number of frames case.pvd lists (-1: no case.pvd).
int kill_and_check(int wait_ms, bool after_setup) {
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml") << long_case();
  const fs::path out = dir.path() / "out";
  const fs::path pvd = out / "case.pvd";
  AppProcess app({"run", (dir.path() / "case.yaml").string(), "--out", out.string(), "--quiet"}, dir.path());
  if (after_setup) {
    EXPECT_TRUE(wait_for_file(pvd)) << app.err();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
  app.signal(SIGKILL);
  EXPECT_EQ(app.wait(), 128 + SIGKILL) << "the run ended before it was killed: " << app.err();
  // Killed before the folder was set up (possible at 200 ms on a slow,
  // sanitized build): nothing was promised yet.
  if (!fs::exists(pvd)) return -1;
  std::vector<PvdEntry> entries;
  std::string why;
  EXPECT_TRUE(parse_pvd(pvd, entries, why)) << why << ":\n" << fq_test::read_text(pvd);
  check_listed_frames(out, entries);
  return int(entries.size());
}

TEST(CrashSafety, SigkillAtAnyMomentLeavesAReadableFolder) {
  for (const int wait_ms : {200, 500, 1000}) {
    SCOPED_TRACE("SIGKILL " + std::to_string(wait_ms) + " ms after the start");
    kill_and_check(wait_ms, false);
  }
  SCOPED_TRACE("SIGKILL 300 ms after case.pvd appeared");
  // The frame at t = 0 is written when the run starts (simulation.h: every
  // observer samples the initial state), so at least it is listed.
  EXPECT_GE(kill_and_check(300, true), 1);
}

double json_number(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + "\"\\s*:\\s*([-+0-9.eE]+)");
  std::smatch m;
  if (!std::regex_search(json, m, re)) return std::nan("");
  return std::stod(m[1].str());
}

// Ctrl-C (SIGINT) and SIGTERM (kill, timeout, a batch scheduler's time
// limit) both stop the run at the end of a step: exit 128 + the signal.
void stop_with_signal_and_check(int signal_number) {
  TempDir dir;
  std::ofstream(dir.path() / "case.yaml") << long_case();
  const fs::path out = dir.path() / "out";
  AppProcess app({"run", (dir.path() / "case.yaml").string(), "--out", out.string(), "--quiet"}, dir.path());
  ASSERT_TRUE(wait_for_file(out / "case.pvd")) << app.err();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // let it write some frames
  app.signal(signal_number);
  ASSERT_EQ(app.wait(), 128 + signal_number) << app.err();

  const std::string summary = fq_test::read_text(out / "summary.json");
  ASSERT_FALSE(summary.empty()) << "summary.json missing";
  EXPECT_TRUE(std::regex_search(summary, std::regex("\"status\"\\s*:\\s*\"stopped\""))) << summary;
  // The message lists every signal that stops a run (it said "Ctrl-C or
  // SIGTERM" after a SIGHUP: docs probe).
  EXPECT_NE(summary.find("stopped on request (Ctrl-C, SIGTERM or SIGHUP)"), std::string::npos) << summary;
  const double simulated_s = json_number(summary, "simulated_time_s");
  ASSERT_TRUE(std::isfinite(simulated_s)) << summary;
  EXPECT_GT(simulated_s, 0.0);
  EXPECT_LT(simulated_s, 10000.0) << "the run was meant to be stopped, not completed";

  std::vector<PvdEntry> entries;
  std::string why;
  ASSERT_TRUE(parse_pvd(out / "case.pvd", entries, why)) << why;
  ASSERT_FALSE(entries.empty());
  check_listed_frames(out, entries);
  // The final frame is the state the run stopped at (simulation.h: the last
  // state is sampled by every observer once). Both numbers are printed in
  // round-trip form, so they agree to the last bit; 1e-12 relative allows
  // for a writer that prints 17 significant digits instead.
  EXPECT_NEAR(entries.back().time_s, simulated_s, 1e-12 * simulated_s);
  EXPECT_EQ(json_number(summary, "frames_written"), double(entries.size()));

  // The run said near its start how much more it would write: 1e8 steps, a
  // frame every 200 (500 001 with the first) of a few kB and a row every 100
  // (1 000 001), less the few written when it measured them (after its
  // tenth row, io/src/case_runner.cpp, OutputSizeCheck): well above the
  // 1 GB that earns a note.
  std::smatch m;
  const std::string err = app.err();
  ASSERT_TRUE(std::regex_search(err, m,
                                std::regex("framequake: note: this run will write up to about ([0-9.]+) GB more "
                                           "output \\(([0-9]+) frames of up to about ([0-9.]+) kB, their "
                                           "uncompressed size, ([0-9]+) history rows; more if contacts multiply\\)")))
      << err;
  const double frames = std::stod(m[2]), frame_kB = std::stod(m[3]), rows = std::stod(m[4]);
  EXPECT_GE(frames, 500001.0 - 10.0);
  EXPECT_LE(frames, 500001.0 - 1.0);
  EXPECT_GE(rows, 1000001.0 - 20.0);
  EXPECT_LE(rows, 1000001.0 - 10.0);
  // The total is the frames and rows at their measured sizes (3 digits).
  const double row_bytes_max = 400.0;  // 14 columns of at most 25 characters and a comma
  EXPECT_GT(std::stod(m[1]), frames * frame_kB * 1e3 / 1e9 * 0.99);
  EXPECT_LT(std::stod(m[1]), (frames * frame_kB * 1e3 + rows * row_bytes_max) / 1e9 * 1.01);
}

TEST(CrashSafety, SigintStopsCleanlyWithSummaryAndFinalFrame) {
  ASSERT_NO_FATAL_FAILURE(stop_with_signal_and_check(SIGINT));
}

TEST(CrashSafety, SigtermStopsCleanlyWithSummaryAndFinalFrame) {
  ASSERT_NO_FATAL_FAILURE(stop_with_signal_and_check(SIGTERM));
}

// A closed terminal or SSH session (SIGHUP) stops the run the same way; it
// used to end it with no summary and no final frame (CLI probe).
TEST(CrashSafety, SighupStopsCleanlyWithSummaryAndFinalFrame) {
  ASSERT_NO_FATAL_FAILURE(stop_with_signal_and_check(SIGHUP));
}

}  // namespace
