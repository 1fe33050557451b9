// Run output (case.pvd, frames/*.vtu, history.csv, events.csv, summary.json)
// read back by independent readers: VTK's own XML reader and XML parser in
// C++, and python3-vtk9 plus Python's csv/json modules in a separate process
// (tests/io/read_vtu_with_vtk.py).
//
// The scene: a fixed ground slab and three free boxes under gravity and a
// constant ground acceleration, with no springs or contacts. Each free body
// then has the constant acceleration a = g - a_g, for which central
// difference is exact (dem_core/simulation.h "Starting"): x(t) = x0 + v0 t +
// a t^2/2, and the stored mid-step velocity after the step that reaches t is
// v(t - dt/2) = v0 + a (t - dt/2). These closed forms are the expected
// values of positions, velocities and displacements below. A box keeps its
// volume 8 hx hy hz under any rotation (rigid motion), the expected hexahedron
// volume. Frame and row counts follow from the intervals: samples at every
// k-th step from 0 to N, plus the last state N when k does not divide N.
#include <gtest/gtest.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "dem_core/address_sanitizer.h"
#include "dem_core/simulation.h"
#include "io/case_file.h"
#include "io/case_runner.h"
#include "io/folder_lock.h"
#include "io/vtk_frame_writer.h"
#include "io/atomic_file.h"
#include "io/history_writer.h"
#include "io/json_writer.h"
#include "io/run_output.h"
#include "checkpoint_case.h"
#include "io_test_util.h"

namespace fs = std::filesystem;

namespace {

constexpr double kDt_s = 1e-3;
constexpr double kGroundAccelX_mps2 = 1.5;  // constant ground acceleration along x
constexpr double kGravity_mps2 = fq::kStandardGravity_mps2;

struct BodySpec {
  const char* name;
  fq::MemberKind kind;
  fq::Vec3 size_m;
  fq::Vec3 position_m;
  fq::Quat orientation;
  fq::Vec3 velocity_mps;
  fq::Vec3 angular_velocity_radps;
  bool fixed;
};

std::vector<BodySpec> scene_bodies() {
  const fq::Quat tilted(Eigen::AngleAxisd(0.3, fq::Vec3(1, 2, 3).normalized()));
  const fq::Quat tumbling(Eigen::AngleAxisd(1.1, fq::Vec3(-2, 1, 0.5).normalized()));
  return {
      {"ground", fq::MemberKind::Ground, fq::Vec3(2.0, 2.0, 0.1), fq::Vec3(0, 0, -0.05), fq::Quat::Identity(),
       fq::Vec3::Zero(), fq::Vec3::Zero(), true},
      {"column", fq::MemberKind::Column, fq::Vec3(0.01, 0.02, 0.29), fq::Vec3(0.1, 0.0, 0.5), tilted,
       fq::Vec3(0.1, 0.0, 0.5), fq::Vec3::Zero(), false},
      // Spins about its body z axis, a principal axis: torque-free, the spin stays (0, 0, 5) rad/s.
      {"beam", fq::MemberKind::Beam, fq::Vec3(0.49, 0.01, 0.01), fq::Vec3(-0.2, 0.3, 0.8), fq::Quat::Identity(),
       fq::Vec3::Zero(), fq::Vec3(0.0, 0.0, 5.0), false},
      {"block", fq::MemberKind::Block, fq::Vec3(0.05, 0.07, 0.03), fq::Vec3(0.4, -0.1, 0.3), tumbling,
       fq::Vec3(-0.3, 0.2, 0.0), fq::Vec3(3.0, -2.0, 7.0), false},
  };
}

// Acceleration of every free body: gravity plus the inertia force of the ground motion.
fq::Vec3 free_body_acceleration() { return fq::Vec3(-kGroundAccelX_mps2, 0.0, -kGravity_mps2); }

fq::Vec3 expected_position(const BodySpec& b, double t) {
  if (b.fixed) return b.position_m;
  return b.position_m + b.velocity_mps * t + 0.5 * free_body_acceleration() * t * t;
}

std::unique_ptr<fq::Simulation> make_simulation(double duration_s) {
  fq::BodyStore store;
  for (const BodySpec& s : scene_bodies()) {
    fq::BoxBodyDef d;
    d.name = s.name;
    d.kind = s.kind;
    d.size_m = s.size_m;
    d.density_kg_per_m3 = 500.0;  // softwood
    d.position_m = s.position_m;
    d.orientation = s.orientation;
    d.velocity_mps = s.velocity_mps;
    d.angular_velocity_radps = s.angular_velocity_radps;
    d.fixed = s.fixed;
    store.add_box(d);
  }
  fq::SimulationSettings settings;
  settings.dt_s = kDt_s;
  settings.duration_s = duration_s;
  // A constant record (1 s of samples) along x: a_g(t) = 1.5 m/s^2 for the whole run.
  fq::GroundMotionComponent c;
  c.record.dt_s = 0.01;
  c.record.acceleration_mps2.assign(101, kGroundAccelX_mps2);
  c.direction = fq::Vec3::UnitX();
  fq::GroundMotion gm;
  gm.add_component(c);
  return std::make_unique<fq::Simulation>(std::move(store), settings, std::move(gm));
}

fs::path output_root() { return fs::path(FQ_BINARY_DIR) / "test_output" / "run_output"; }

// A fresh folder for one test. CTest runs each test of this program in its
// own process, several at once, so the folder carries the process id: two
// tests sharing main_run() must not remove each other's output.
fs::path fresh_folder(const std::string& name) {
  const fs::path p = output_root() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p.parent_path());
  return p;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> read_lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) out.push_back(cur);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

std::set<std::string> folder_listing(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir)) names.insert(fs::relative(e.path(), dir).string());
  return names;
}

// Samples at steps 0, k, 2k, ... <= n, plus n itself when k does not divide n.
std::vector<std::int64_t> sample_steps(std::int64_t k, std::int64_t n) {
  std::vector<std::int64_t> s;
  for (std::int64_t i = 0; i <= n; i += k) s.push_back(i);
  if (n % k != 0) s.push_back(n);
  return s;
}

struct PvdEntry {
  double time_s;
  std::string file;
};

// Parses case.pvd with VTK's XML parser (expat), independent of our writer.
std::vector<PvdEntry> parse_pvd(const fs::path& pvd, bool* ok) {
  std::vector<PvdEntry> out;
  *ok = false;
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(pvd.c_str());
  if (!parser->Parse()) return out;
  vtkXMLDataElement* root = parser->GetRootElement();
  if (!root || std::string(root->GetName()) != "VTKFile" || !root->GetAttribute("type") ||
      std::string(root->GetAttribute("type")) != "Collection")
    return out;
  vtkXMLDataElement* coll = root->FindNestedElementWithName("Collection");
  if (!coll) return out;
  for (int i = 0; i < coll->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = coll->GetNestedElement(i);
    if (std::string(e->GetName()) != "DataSet" || !e->GetAttribute("timestep") || !e->GetAttribute("file")) return out;
    out.push_back({std::strtod(e->GetAttribute("timestep"), nullptr), e->GetAttribute("file")});
  }
  *ok = true;
  return out;
}

// Counts VTK error events of a reader (VTK reports read failures that way).
class ErrorCounter : public vtkCommand {
 public:
  static ErrorCounter* New() { return new ErrorCounter; }
  void Execute(vtkObject*, unsigned long, void*) override { ++errors; }
  int errors = 0;
};

struct ReadFrame {
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  int errors = 0;
};

ReadFrame read_vtu(const fs::path& file) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  vtkNew<ErrorCounter> counter;
  reader->AddObserver(vtkCommand::ErrorEvent, counter);
  reader->SetFileName(file.c_str());
  reader->Update();
  ReadFrame r;
  r.grid = reader->GetOutput();
  r.errors = counter->errors + (reader->GetErrorCode() != 0 ? 1 : 0);
  return r;
}

// Volume of a parallelepiped hexahedron in VTK order from the edges at
// vertex 0: (p1 - p0) . ((p3 - p0) x (p4 - p0)); positive when the bottom face
// 0-1-2-3 turns counter-clockwise seen from the top face (VTK's convention).
double hex_volume(vtkUnstructuredGrid* grid, vtkIdType cell) {
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  grid->GetCellPoints(cell, n, ids);
  fq::Vec3 p[8];
  for (int k = 0; k < 8; ++k) grid->GetPoint(ids[k], p[k].data());
  return (p[1] - p[0]).dot((p[3] - p[0]).cross(p[4] - p[0]));
}

fq::Vec3 hex_centroid(vtkUnstructuredGrid* grid, vtkIdType cell) {
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  grid->GetCellPoints(cell, n, ids);
  fq::Vec3 c = fq::Vec3::Zero();
  for (vtkIdType k = 0; k < n; ++k) {
    fq::Vec3 p;
    grid->GetPoint(ids[k], p.data());
    c += p;
  }
  return c / double(n);
}

fq::Vec3 tuple3(vtkDataArray* a, vtkIdType i) {
  double v[3];
  a->GetTuple(i, v);
  return fq::Vec3(v[0], v[1], v[2]);
}

bool python_with_vtk_available() {
  return std::system("/usr/bin/python3 -c 'import vtk' > /dev/null 2>&1") == 0;
}
bool python_available() { return std::system("/usr/bin/python3 -c 'import json' > /dev/null 2>&1") == 0; }

std::string run_command(const std::string& cmd, int* status) {
  std::string out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) {
    *status = -1;
    return out;
  }
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  *status = pclose(pipe);
  return out;
}

// The value after "key": in a flat JSON object printed by Python's json.dumps.
std::string json_field(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\": ";
  const auto at = json.find(tag);
  if (at == std::string::npos) return "";
  std::size_t begin = at + tag.size(), end = begin;
  if (json[begin] == '[') {
    end = json.find(']', begin) + 1;
  } else if (json[begin] == '"') {
    end = json.find('"', begin + 1) + 1;
  } else {
    while (end < json.size() && json[end] != ',' && json[end] != '}') ++end;
  }
  return json.substr(begin, end - begin);
}

std::vector<double> json_number_list(const std::string& list) {
  std::vector<double> out;
  if (list.size() < 2) return out;
  for (const std::string& item : split(list.substr(1, list.size() - 2), ','))
    if (!item.empty()) out.push_back(std::strtod(item.c_str(), nullptr));
  return out;
}

const std::vector<std::string> kStandardHeader = {
    "time_s",          "kinetic_J",           "kinetic_rotational_J",  "gravity_potential_J",
    "elastic_J",       "dissipated_viscous_J", "dissipated_plastic_J", "dissipated_friction_J",
    "work_ground_motion_J", "energy_balance_error_J", "ground_accel_x_mps2", "ground_accel_y_mps2",
    "ground_accel_z_mps2",  "max_displacement_m"};

// The main scenario, run once for the read-back tests: 103 steps of 1 ms,
// frames every 20 steps, history every 5.
constexpr double kMainDuration_s = 0.103;
constexpr std::int64_t kMainSteps = 103;
constexpr std::int64_t kFrameEvery = 20;
constexpr std::int64_t kHistoryEvery = 5;

struct MainRun {
  fs::path folder;
  fq::RunResult result;
};

const MainRun& main_run() {
  static const MainRun run = [] {
    MainRun r;
    r.folder = fresh_folder("main");
    auto sim = make_simulation(kMainDuration_s);
    fq::OutputDef def;
    def.folder = r.folder;
    def.frame_interval_s = 0.02;
    def.history_interval_s = 0.005;
    fq::RunOutput out(def, "unit \"test\" case");
    out.attach(*sim);
    out.add_summary_field("peak_drift", "{\"storey1_x_ratio\": 0.0125, \"verdict\": [\"stands\"]}");
    r.result = sim->run();
    out.finish(*sim, r.result);
    return r;
  }();
  return run;
}

}  // namespace

// An interval longer than any run means the start and the end only. The
// quotient used to be rounded with llround, undefined past 2^63: 1e300 s
// gave "every step", 20 001 frames for a 0.2 s run (CLI probe).
TEST(RunOutput, AnIntervalLongerThanTheRunSamplesTheStartAndTheEnd) {
  EXPECT_EQ(fq::steps_per_interval(1e300, 1e-5), fq::kEveryStepCap);
  EXPECT_EQ(fq::steps_per_interval(std::numeric_limits<double>::infinity(), 1e-5), fq::kEveryStepCap);
  EXPECT_EQ(fq::steps_per_interval(1e15, 1e-5), fq::kEveryStepCap);  // 1e20 steps
  EXPECT_EQ(fq::steps_per_interval(1e10, 1e-5), std::int64_t(1e15));  // within range: rounded as before
  EXPECT_EQ(fq::samples_written(20000, fq::kEveryStepCap), 2);
  EXPECT_EQ(fq::steps_per_interval(0.01, 1e-3), 10);  // ordinary intervals as before
  const fs::path folder = fresh_folder("long_interval");
  fq::OutputDef def;
  def.folder = folder;
  def.frame_interval_s = 1e300;
  def.history_interval_s = 1e300;
  auto sim = make_simulation(0.05);
  fq::RunOutput out(def, "long interval");
  out.attach(*sim);
  out.finish(*sim, sim->run());
  bool ok = false;
  EXPECT_EQ(parse_pvd(folder / "case.pvd", &ok).size(), 2u);
  std::size_t lines = 0;
  for (const char c : read_text(folder / "history.csv")) lines += c == '\n';
  EXPECT_EQ(lines, 3u);  // header, start, end
}

TEST(RunOutput, IntervalsAreRoundedToWholeSteps) {
  auto sim = make_simulation(0.01);
  fq::OutputDef def;
  def.folder = fresh_folder("intervals");
  def.frame_interval_s = 0.0204;   // 20.4 steps -> 20
  def.history_interval_s = 0.0001;  // 0.1 step -> at least 1
  fq::RunOutput out(def, "intervals");
  out.attach(*sim);
  EXPECT_EQ(out.frame_every_steps(), 20);
  EXPECT_EQ(out.history_every_steps(), 1);
  // The rounding is said (run prints it as a note, info too), and the
  // summary gives the interval used beside the one asked for.
  const std::string frame_note = fq::interval_rounding_note("output.frame_interval_s", 0.0204, kDt_s);
  EXPECT_NE(frame_note.find("not a whole number of time steps"), std::string::npos) << frame_note;
  EXPECT_NE(frame_note.find("every 20 steps (0.02 s)"), std::string::npos) << frame_note;
  const std::string row_note = fq::interval_rounding_note("output.history_interval_s", 0.0001, kDt_s);
  EXPECT_NE(row_note.find("shorter than one time step"), std::string::npos) << row_note;
  EXPECT_NE(row_note.find("every 1 step (0.001 s)"), std::string::npos) << row_note;
  EXPECT_EQ(fq::interval_rounding_note("output.frame_interval_s", 0.02, kDt_s), "");  // whole steps: no note
  sim->run();
  out.finish(*sim, fq::RunResult{});
  const std::string summary = read_text(def.folder / "summary.json");
  const auto number = [&](const char* key) { return std::strtod(json_field(summary, key).c_str(), nullptr); };
  EXPECT_DOUBLE_EQ(number("frame_interval_s"), 20 * kDt_s) << summary;
  EXPECT_DOUBLE_EQ(number("frame_interval_requested_s"), 0.0204) << summary;
  EXPECT_DOUBLE_EQ(number("history_interval_s"), kDt_s) << summary;
  EXPECT_DOUBLE_EQ(number("history_interval_requested_s"), 0.0001) << summary;
}

TEST(RunOutput, FolderLayoutAndNoTemporariesLeft) {
  const MainRun& run = main_run();
  ASSERT_EQ(run.result.status, fq::RunStatus::Completed);
  ASSERT_EQ(run.result.steps, kMainSteps);
  for (const char* f : {"case.pvd", "history.csv", "events.csv", "summary.json"})
    EXPECT_TRUE(fs::is_regular_file(run.folder / f)) << f;
  EXPECT_TRUE(fs::is_directory(run.folder / "frames"));
  for (const std::string& name : folder_listing(run.folder))
    EXPECT_EQ(name.find("/."), std::string::npos) << "temporary left behind: " << name;
}

TEST(RunOutput, PvdListsEveryFrameAtItsPhysicalTime) {
  const MainRun& run = main_run();
  bool ok = false;
  const std::vector<PvdEntry> entries = parse_pvd(run.folder / "case.pvd", &ok);
  ASSERT_TRUE(ok) << "case.pvd is not a VTK collection";
  const std::vector<std::int64_t> steps = sample_steps(kFrameEvery, kMainSteps);
  ASSERT_EQ(entries.size(), steps.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    EXPECT_NEAR(entries[k].time_s, double(steps[k]) * kDt_s, 1e-12) << "frame " << k;
    char expected_file[64];
    std::snprintf(expected_file, sizeof expected_file, "frames/frame_%06zu.vtu", k);
    EXPECT_EQ(entries[k].file, expected_file);
  }
  // Only listed frames exist.
  std::size_t frame_files = 0;
  for (const auto& e : fs::directory_iterator(run.folder / "frames")) frame_files += e.path().extension() == ".vtu";
  EXPECT_EQ(frame_files, entries.size());
}

TEST(RunOutput, FramesReadBackWithVtkReader) {
  const MainRun& run = main_run();
  const std::vector<BodySpec> bodies = scene_bodies();
  bool ok = false;
  const std::vector<PvdEntry> entries = parse_pvd(run.folder / "case.pvd", &ok);
  ASSERT_TRUE(ok);
  ASSERT_FALSE(entries.empty());
  for (const PvdEntry& entry : entries) {
    SCOPED_TRACE(entry.file);
    const double t = entry.time_s;
    ReadFrame f = read_vtu(run.folder / entry.file);
    ASSERT_EQ(f.errors, 0);
    vtkUnstructuredGrid* g = f.grid;
    ASSERT_EQ(g->GetNumberOfCells(), vtkIdType(bodies.size()));
    ASSERT_EQ(g->GetNumberOfPoints(), vtkIdType(8 * bodies.size()));

    // The frame's own time is bitwise the .pvd's (both written shortest round-trip or binary).
    vtkDataArray* time = g->GetFieldData()->GetArray("TimeValue");
    ASSERT_NE(time, nullptr);
    EXPECT_EQ(time->GetTuple1(0), t);

    vtkCellData* cd = g->GetCellData();
    struct Expect {
      const char* name;
      int components;
      bool is_int;
    };
    for (const Expect& e : {Expect{"body_id", 1, true}, Expect{"member_kind", 1, true}, Expect{"velocity_mps", 3, false},
                            Expect{"angular_velocity_radps", 3, false}, Expect{"state", 1, true},
                            Expect{"cell_block", 1, true}}) {
      vtkDataArray* a = cd->GetArray(e.name);
      ASSERT_NE(a, nullptr) << e.name;
      EXPECT_EQ(a->GetNumberOfComponents(), e.components) << e.name;
      EXPECT_EQ(a->GetNumberOfTuples(), g->GetNumberOfCells()) << e.name;
      if (e.is_int)
        EXPECT_NE(vtkIntArray::SafeDownCast(a), nullptr) << e.name << " should be an int array";
      else
        EXPECT_NE(vtkDoubleArray::SafeDownCast(a), nullptr) << e.name << " should be a double array";
    }
    auto* kind_names = vtkStringArray::SafeDownCast(g->GetFieldData()->GetAbstractArray("member_kind_names"));
    ASSERT_NE(kind_names, nullptr);
    // Enum values of fq::MemberKind (body_store.h): Column = 0, ..., Ground = 4.
    EXPECT_EQ(kind_names->GetValue(0), "column");
    EXPECT_EQ(kind_names->GetValue(4), "ground");

    const fq::Vec3 a = free_body_acceleration();
    for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
      const BodySpec& b = bodies[std::size_t(c)];
      SCOPED_TRACE(b.name);
      EXPECT_EQ(g->GetCellType(c), VTK_HEXAHEDRON);
      EXPECT_EQ(cd->GetArray("body_id")->GetTuple1(c), double(c));
      EXPECT_EQ(cd->GetArray("member_kind")->GetTuple1(c), double(static_cast<int>(b.kind)));
      EXPECT_EQ(cd->GetArray("state")->GetTuple1(c), b.fixed ? 1.0 : 0.0);
      EXPECT_EQ(cd->GetArray("cell_block")->GetTuple1(c), 0.0);
      // Rigid motion keeps the box volume (and a proper rotation its sign).
      const double v = hex_volume(g, c);
      const double v_expected = b.size_m.prod();
      EXPECT_GT(v, 0.0);
      EXPECT_NEAR(v, v_expected, 1e-12 * v_expected);
      EXPECT_LT((hex_centroid(g, c) - expected_position(b, t)).norm(), 1e-12);
      const fq::Vec3 v_mid = b.fixed ? fq::Vec3::Zero() : fq::Vec3(b.velocity_mps + a * (t - 0.5 * kDt_s));
      EXPECT_LT((tuple3(cd->GetArray("velocity_mps"), c) - v_mid).norm(), 1e-12);
      if (std::string(b.name) == "beam") {
        EXPECT_LT((tuple3(cd->GetArray("angular_velocity_radps"), c) - b.angular_velocity_radps).norm(), 1e-9);
      }
    }
  }
}

TEST(RunOutput, HistoryHasUnitsAndOneRowPerSample) {
  const MainRun& run = main_run();
  const std::vector<std::string> lines = read_lines(run.folder / "history.csv");
  ASSERT_FALSE(lines.empty());
  const std::vector<std::string> header = split(lines[0], ',');
  EXPECT_EQ(header, kStandardHeader);
  const std::vector<std::int64_t> steps = sample_steps(kHistoryEvery, kMainSteps);
  ASSERT_EQ(lines.size() - 1, steps.size());
  const std::vector<BodySpec> bodies = scene_bodies();
  for (std::size_t r = 0; r < steps.size(); ++r) {
    SCOPED_TRACE("row " + std::to_string(r));
    const std::vector<std::string> cells = split(lines[r + 1], ',');
    ASSERT_EQ(cells.size(), header.size());
    std::vector<double> v;
    for (const std::string& s : cells) v.push_back(std::strtod(s.c_str(), nullptr));
    const double t = double(steps[r]) * kDt_s;
    EXPECT_NEAR(v[0], t, 1e-12);
    EXPECT_EQ(v[10], kGroundAccelX_mps2);  // the record's constant value
    EXPECT_EQ(v[11], 0.0);
    EXPECT_EQ(v[12], 0.0);
    double max_disp = 0.0;
    for (const BodySpec& b : bodies) max_disp = std::max(max_disp, (expected_position(b, t) - b.position_m).norm());
    EXPECT_NEAR(v[13], max_disp, 1e-12);
    // Only gravity and the ground motion act; the ledger books their work on
    // the translation exactly (energy_ledger.h), and they exert no torque.
    // So the balance error is exactly the drift of the rotational kinetic
    // energy, which a torque-free body conserves physically but the
    // discrete rotation update does not quite (tumbling block). Energies are
    // below 0.1 J: 103 steps x a few additions x 1.1e-16 x 0.1 J < 1e-14 J.
    const double first_rotational_J = std::strtod(split(lines[1], ',')[2].c_str(), nullptr);
    EXPECT_NEAR(v[9], v[2] - first_rotational_J, 1e-14);
    EXPECT_GE(v[1], v[2]);  // kinetic includes its rotational part
  }
}

TEST(RunOutput, EventsFileHasHeaderAndNoRowsWithoutEvents) {
  const MainRun& run = main_run();
  const std::vector<std::string> lines = read_lines(run.folder / "events.csv");
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "time_s,step,kind,joint_id,body_a,body_b,spring_index,mode,force_N,x_m,y_m,z_m,body_a_name,body_b_name,node,joint_name");
}

TEST(RunOutput, SummaryIsValidJsonWithStatusAndExtraFields) {
  const MainRun& run = main_run();
  const std::string text = read_text(run.folder / "summary.json");
  EXPECT_TRUE(fq::json_is_valid(text));
  EXPECT_NE(text.find("\"status\": \"completed\""), std::string::npos);
  EXPECT_NE(text.find("\"case\": \"unit \\\"test\\\" case\""), std::string::npos);
  if (!python_available()) GTEST_SKIP() << "/usr/bin/python3 not available for the independent JSON check";
  // Python's json module is the independent parser; it checks the values a
  // reader needs against the run's definition (103 steps of 1 ms, 4 bodies,
  // frames at steps 0, 20, ..., 100 and 103 = 7) and the ledger identities
  // of energy_ledger.h (stored = kinetic + gravity + elastic; balance error
  // = stored - initial + dissipated - input), to round-off of 0.06 J values.
  const std::string script =
      "import json,sys; d=json.load(open(sys.argv[1])); "
      "e=d['energy']; "
      "ok = d['status']=='completed' and d['steps']==103 and d['body_count']==4 and d['frames_written']==7 "
      "and d['history_rows']==22 and abs(d['dt_s']-1e-3)<1e-18 and abs(d['simulated_time_s']-0.103)<1e-12 "
      "and d['case']=='unit \"test\" case' and d['peak_drift']['verdict']==['stands'] "
      "and set(d['event_counts'])=={'spring_yielded','spring_deleted','joint_broken','instability'} "
      "and set(d['stage_seconds'])=={'external_forces','providers','integrate','finish_step','observe'} "
      "and all(k in e for k in ['kinetic_J','balance_error_J','balance_error_relative','work_ground_motion_J']) "
      "and abs(e['stored_J']-e['initial_stored_J']+e['dissipated_J']-e['input_J']-e['balance_error_J'])<1e-15 "
      "and abs(e['kinetic_J']+e['gravity_potential_J']+e['elastic_J']-e['stored_J'])<1e-15; "
      "sys.exit(0 if ok else 1)";
  const std::string cmd = "/usr/bin/python3 -c \"" + std::string([&] {
                            std::string s;
                            for (char c : script) {
                              if (c == '"' || c == '\\' || c == '$' || c == '`') s.push_back('\\');
                              s.push_back(c);
                            }
                            return s;
                          }()) +
                          "\" '" + (run.folder / "summary.json").string() + "'";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << read_text(run.folder / "summary.json");
}

TEST(RunOutput, IndependentReadBackWithPythonVtk) {
  const MainRun& run = main_run();
  if (!python_with_vtk_available()) GTEST_SKIP() << "/usr/bin/python3 cannot import vtk (python3-vtk9 missing)";
  int status = 0;
  const std::string out = run_command("/usr/bin/python3 '" + std::string(FQ_SOURCE_DIR) +
                                          "/tests/io/read_vtu_with_vtk.py' '" + run.folder.string() + "' 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << out;
  ASSERT_TRUE(fq::json_is_valid(out)) << out;
  const std::size_t n_bodies = scene_bodies().size();
  const std::vector<std::int64_t> steps = sample_steps(kFrameEvery, kMainSteps);
  EXPECT_EQ(json_field(out, "frames"), std::to_string(steps.size()));
  EXPECT_EQ(json_field(out, "hexahedra"), std::to_string(steps.size() * n_bodies));
  EXPECT_EQ(json_field(out, "lines"), "0");
  EXPECT_EQ(json_field(out, "vertices"), "0");
  EXPECT_EQ(json_field(out, "other_cells"), "0");
  for (double c : json_number_list(json_field(out, "cells"))) EXPECT_EQ(c, double(n_bodies));
  for (double p : json_number_list(json_field(out, "points"))) EXPECT_EQ(p, double(8 * n_bodies));
  const std::vector<double> pvd_times = json_number_list(json_field(out, "pvd_times"));
  const std::vector<double> frame_times = json_number_list(json_field(out, "frame_times"));
  ASSERT_EQ(pvd_times.size(), steps.size());
  ASSERT_EQ(frame_times.size(), steps.size());
  for (std::size_t k = 0; k < steps.size(); ++k) {
    EXPECT_NEAR(pvd_times[k], double(steps[k]) * kDt_s, 1e-12);
    EXPECT_EQ(frame_times[k], pvd_times[k]);
  }
  // vtkCellSizeFilter's volumes: every box keeps 8 hx hy hz in every frame.
  EXPECT_GT(std::strtod(json_field(out, "hex_volume_min_m3").c_str(), nullptr), 0.0);
  const std::vector<double> volumes = json_number_list(json_field(out, "hex_volumes_m3"));
  ASSERT_EQ(volumes.size(), steps.size() * n_bodies);
  for (std::size_t k = 0; k < volumes.size(); ++k) {
    const double expected = scene_bodies()[k % n_bodies].size_m.prod();
    EXPECT_NEAR(volumes[k], expected, 1e-9 * expected) << "hexahedron " << k;
  }
  EXPECT_EQ(json_field(out, "array_body_id"), "1");
  EXPECT_EQ(json_field(out, "array_member_kind"), "1");
  EXPECT_EQ(json_field(out, "array_velocity_mps"), "3");
  EXPECT_EQ(json_field(out, "array_angular_velocity_radps"), "3");
  EXPECT_EQ(json_field(out, "array_state"), "1");
  EXPECT_EQ(json_field(out, "array_type_body_id"), "\"int\"");
  EXPECT_EQ(json_field(out, "array_type_velocity_mps"), "\"double\"");
  EXPECT_EQ(json_field(out, "history_rows"), std::to_string(sample_steps(kHistoryEvery, kMainSteps).size()));
  std::string header;
  for (const std::string& h : kStandardHeader) header += (header.empty() ? "" : ",") + h;
  EXPECT_EQ(json_field(out, "history_header"), "\"" + header + "\"");
  EXPECT_EQ(json_field(out, "summary_status"), "\"completed\"");
}

TEST(RunOutput, AsciiFramesAreReadableToo) {
  auto sim = make_simulation(0.02);
  fq::OutputDef def;
  def.folder = fresh_folder("ascii");
  def.frame_interval_s = 0.01;
  def.vtk_binary = false;
  fq::RunOutput out(def, "ascii");
  out.attach(*sim);
  const fq::RunResult result = sim->run();
  out.finish(*sim, result);
  bool ok = false;
  const std::vector<PvdEntry> entries = parse_pvd(def.folder / "case.pvd", &ok);
  ASSERT_TRUE(ok);
  ASSERT_EQ(entries.size(), 3u);  // steps 0, 10, 20
  const std::vector<BodySpec> bodies = scene_bodies();
  for (const PvdEntry& e : entries) {
    const std::string text = read_text(def.folder / e.file);
    EXPECT_NE(text.find("format=\"ascii\""), std::string::npos);
    EXPECT_EQ(text.find("<AppendedData"), std::string::npos);
    ReadFrame f = read_vtu(def.folder / e.file);
    ASSERT_EQ(f.errors, 0);
    ASSERT_EQ(f.grid->GetNumberOfCells(), vtkIdType(bodies.size()));
    // ASCII numbers are decimal text: allow the last digits of a double.
    EXPECT_NEAR(f.grid->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), e.time_s, 1e-15);
    for (vtkIdType c = 0; c < f.grid->GetNumberOfCells(); ++c) {
      EXPECT_NEAR(hex_volume(f.grid, c), bodies[std::size_t(c)].size_m.prod(), 1e-9 * bodies[std::size_t(c)].size_m.prod());
      EXPECT_LT((hex_centroid(f.grid, c) - expected_position(bodies[std::size_t(c)], e.time_s)).norm(), 1e-9);
    }
  }
}

TEST(RunOutput, RefusesFolderWithForeignFilesAndLeavesItUntouched) {
  const fs::path folder = fresh_folder("foreign");
  fs::create_directories(folder / "photos");
  { std::ofstream(folder / "notes.txt") << "my thesis, do not delete\n"; }
  { std::ofstream(folder / "photos" / "frame_000000.vtu") << "not ours\n"; }
  const std::set<std::string> before = folder_listing(folder);
  fq::OutputDef def;
  def.folder = folder;
  try {
    fq::RunOutput out(def, "foreign");
    FAIL() << "a folder with foreign files was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(folder.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(folder_listing(folder), before);
  EXPECT_EQ(read_text(folder / "notes.txt"), "my thesis, do not delete\n");
  EXPECT_EQ(read_text(folder / "photos" / "frame_000000.vtu"), "not ours\n");
}

// A folder is taken for an earlier run by its files' content, not their
// names: a user's own summary.json or case.pvd (another program's) does
// not make the run replace the history.csv beside them (a probe's did).
TEST(RunOutput, RefusesAFolderWhoseSummaryOrPvdIsNotFramequakes) {
  const fs::path folder = fresh_folder("foreign_summary");
  fs::create_directories(folder);
  { std::ofstream(folder / "summary.json") << "{\"my\": \"own summary\"}\n"; }
  { std::ofstream(folder / "history.csv") << "my measurements\n"; }
  fq::OutputDef def;
  def.folder = folder;
  EXPECT_THROW(fq::RunOutput(def, "x"), std::runtime_error);
  EXPECT_EQ(read_text(folder / "history.csv"), "my measurements\n");
  fs::remove(folder / "summary.json");
  { std::ofstream(folder / "case.pvd") << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\">\n<Collection>\n"
                                          "<DataSet timestep=\"0\" file=\"scans/scan_0.vtu\"/>\n"; }
  EXPECT_THROW(fq::RunOutput(def, "x"), std::runtime_error);
  EXPECT_EQ(read_text(folder / "history.csv"), "my measurements\n");
  EXPECT_TRUE(fs::exists(folder / "case.pvd"));
}

TEST(RunOutput, AcceptsAnEmptyFolderOrOneWithAnEmptyFramesFolder) {
  for (const bool with_frames : {false, true}) {
    const fs::path folder = fresh_folder(with_frames ? "empty_frames" : "empty");
    fs::create_directories(with_frames ? folder / "frames" : folder);
    fq::OutputDef def;
    def.folder = folder;
    fq::RunOutput out(def, "empty");
    bool ok = false;
    EXPECT_TRUE(parse_pvd(folder / "case.pvd", &ok).empty());
    EXPECT_TRUE(ok);
  }
}

// A run killed before its summary (SIGKILL, a crash, a full disk) leaves
// case.pvd listing its frames and no summary.json: that folder is still
// recognised as a framequake run and replaced by the next run (a CLI probe
// found it refused as "holds no previous framequake run": the check
// compared 20 characters of a 19-character prefix).
TEST(RunOutput, ReplacesARunKilledBeforeItsSummary) {
  const fs::path folder = fresh_folder("killed");
  fq::OutputDef def;
  def.folder = folder;
  def.frame_interval_s = 0.01;
  {
    auto sim = make_simulation(0.05);
    fq::RunOutput out(def, "killed");
    out.attach(*sim);
    out.finish(*sim, sim->run());
  }
  fs::remove(folder / "summary.json");  // as a kill before the end leaves it
  bool ok = false;
  ASSERT_EQ(parse_pvd(folder / "case.pvd", &ok).size(), 6u);
  auto sim = make_simulation(0.015);
  fq::RunOutput out(def, "again");
  EXPECT_NO_THROW(out.attach(*sim));
  out.finish(*sim, sim->run());
  EXPECT_EQ(parse_pvd(folder / "case.pvd", &ok).size(), 3u);
  EXPECT_NE(read_text(folder / "summary.json").find("\"case\": \"again\""), std::string::npos);
}

// Two outputs into one folder at the same time: the second is refused
// while the first exists (its files would interleave with the first's: a
// CLI probe's concurrent runs left a summary saying "completed" over a
// fifth of its history rows), and may go ahead once the first is gone.
TEST(RunOutput, AFolderInUseByAnotherOutputIsRefused) {
  const fs::path folder = fresh_folder("in_use");
  fq::OutputDef def;
  def.folder = folder;
  auto first = std::make_unique<fq::RunOutput>(def, "first");
  try {
    fq::RunOutput second(def, "second");
    ADD_FAILURE() << "the second output was allowed into a folder in use";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is in use by another framequake process"), std::string::npos) << e.what();
  }
  EXPECT_NE(read_text(folder / "case.pvd").find("<VTKFile"), std::string::npos);  // the first's files untouched
  first.reset();
  EXPECT_NO_THROW(fq::RunOutput third(def, "third"));
}

// On a file system without flock (ENOLCK, EOPNOTSUPP or ENOTSUP, ENOSYS:
// some network and FUSE mounts) the output goes on without the lock and
// says so in a warning naming the folder; every run was refused there
// ("cannot lock output folder: No locks available", exit 3; tester's
// probe). Any other lock failure still refuses. The failures are stood in
// for by FQ_TEST_FLOCK_ERRNO (io/folder_lock.h).
TEST(RunOutput, AFileSystemWithoutLocksIsWarnedOfNotRefused) {
  const fs::path folder = fresh_folder("no_locks");
  fq::OutputDef def;
  def.folder = folder;
  for (const int err : {ENOLCK, EOPNOTSUPP, ENOTSUP, ENOSYS}) {
    ::setenv("FQ_TEST_FLOCK_ERRNO", std::to_string(err).c_str(), 1);
    try {
      fq::RunOutput out(def, "unlocked");
      const std::string w = out.folder_lock_warning();
      EXPECT_NE(w.find("'" + folder.string() + "'"), std::string::npos) << w;
      EXPECT_NE(w.find(std::generic_category().message(err)), std::string::npos) << w;
      EXPECT_NE(w.find("going on without the lock"), std::string::npos) << w;
      EXPECT_TRUE(fq::is_folder_lock_warning(w)) << w;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "errno " << err << ": " << e.what();
    }
  }
  ::setenv("FQ_TEST_FLOCK_ERRNO", std::to_string(EIO).c_str(), 1);
  EXPECT_THROW(fq::RunOutput(def, "refused"), fq::OutputError);
  ::unsetenv("FQ_TEST_FLOCK_ERRNO");
  fq::RunOutput locked(def, "locked");
  EXPECT_EQ(locked.folder_lock_warning(), "");
}

// A broken symbolic link as the output folder is named as one (creating
// the folder failed with a bare "File exists"; CLI probe).
TEST(RunOutput, ABrokenSymlinkAsTheFolderIsNamed) {
  const fs::path base = fresh_folder("dangling");
  fs::create_directories(base);
  const fs::path link = base / "out";
  fs::create_symlink(base / "missing_target", link);
  fq::OutputDef def;
  def.folder = link;
  try {
    fq::RunOutput out(def, "x");
    ADD_FAILURE() << "accepted a broken link";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is a symbolic link to"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("which does not exist"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(base / "missing_target"));
}

TEST(RunOutput, ReplacesThePreviousRunButNothingElse) {
  const fs::path folder = fresh_folder("rerun");
  fq::OutputDef def;
  def.folder = folder;
  def.frame_interval_s = 0.01;
  {
    auto sim = make_simulation(0.05);  // frames at steps 0, 10, ..., 50: 6
    fq::RunOutput out(def, "first");
    out.attach(*sim);
    out.finish(*sim, sim->run());
  }
  { std::ofstream(folder / "README.txt") << "notes on the run\n"; }
  {
    auto sim = make_simulation(0.015);  // frames at steps 0, 10, 15: 3
    fq::RunOutput out(def, "second");
    out.attach(*sim);
    out.finish(*sim, sim->run());
  }
  bool ok = false;
  EXPECT_EQ(parse_pvd(folder / "case.pvd", &ok).size(), 3u);
  EXPECT_TRUE(ok);
  std::size_t frame_files = 0;
  for (const auto& e : fs::directory_iterator(folder / "frames")) frame_files += e.path().extension() == ".vtu";
  EXPECT_EQ(frame_files, 3u);
  EXPECT_EQ(read_text(folder / "README.txt"), "notes on the run\n");
  EXPECT_NE(read_text(folder / "summary.json").find("\"case\": \"second\""), std::string::npos);
}

namespace {

// Runs after the RunOutput observers at every frame step: what a viewer or a
// crash would find on disk at that instant.
class DiskInspector : public fq::StepObserver {
 public:
  DiskInspector(fs::path folder, std::size_t bodies, std::int64_t history_every)
      : folder_(std::move(folder)), bodies_(bodies), history_every_(history_every) {}
  void on_sample(const fq::Simulation& sim) override {
    ++visits;
    bool ok = false;
    const std::vector<PvdEntry> entries = parse_pvd(folder_ / "case.pvd", &ok);
    EXPECT_TRUE(ok) << "case.pvd invalid at step " << sim.steps_done();
    EXPECT_EQ(entries.size(), visits) << "at step " << sim.steps_done();
    for (const PvdEntry& e : entries) {
      ReadFrame f = read_vtu(folder_ / e.file);
      EXPECT_EQ(f.errors, 0) << e.file << " listed but not readable";
      EXPECT_EQ(f.grid->GetNumberOfCells(), vtkIdType(bodies_)) << e.file;
    }
    if (!entries.empty()) {
      EXPECT_EQ(entries.back().time_s, sim.time_s());
    }
    for (const auto& d : fs::directory_iterator(folder_ / "frames"))
      EXPECT_NE(d.path().filename().string().front(), '.') << "temporary visible after the frame: " << d.path();
    // Every history row up to now is on disk (flushed with the frame): rows
    // at 0, k, 2k, ... and, at the end of the run only, the last state.
    const std::int64_t s = sim.steps_done();
    const bool extra_last = s == sim.total_steps() && s % history_every_ != 0;
    const std::size_t expected_rows = std::size_t(s / history_every_ + 1 + (extra_last ? 1 : 0));
    EXPECT_EQ(read_lines(folder_ / "history.csv").size(), expected_rows + 1) << "at step " << s;
  }
  std::size_t visits = 0;

 private:
  fs::path folder_;
  std::size_t bodies_;
  std::int64_t history_every_;
};

}  // namespace

TEST(RunOutput, EachListedFrameIsCompleteWhenThePvdNamesIt) {
  auto sim = make_simulation(0.047);
  fq::OutputDef def;
  def.folder = fresh_folder("complete");
  def.frame_interval_s = 0.01;
  def.history_interval_s = 0.003;
  fq::RunOutput out(def, "complete");
  // A valid, empty collection exists before the first frame.
  bool ok = false;
  EXPECT_TRUE(parse_pvd(def.folder / "case.pvd", &ok).empty());
  EXPECT_TRUE(ok);
  out.attach(*sim);
  DiskInspector inspector(def.folder, scene_bodies().size(), out.history_every_steps());
  sim->add_observer(&inspector, out.frame_every_steps());
  const fq::RunResult result = sim->run();
  out.finish(*sim, result);
  EXPECT_EQ(inspector.visits, sample_steps(10, 47).size());  // 0, 10, 20, 30, 40, 47
  EXPECT_EQ(out.frames_written(), inspector.visits);
}

TEST(RunOutput, HooksAddCellBlocksAndHistoryColumns) {
  auto sim = make_simulation(0.01);
  fq::OutputDef def;
  def.folder = fresh_folder("hooks");
  def.frame_interval_s = 0.01;
  def.history_interval_s = 0.005;
  fq::RunOutput out(def, "hooks");
  // A marker vertex at every body centre carrying its height.
  out.add_cell_block("markers", [](const fq::Simulation& s, fq::VtkFrameBuilder& frame) {
    const auto height = frame.cell_array("marker_height_m", fq::VtkArrayType::Float64, 1,
                                         std::numeric_limits<double>::quiet_NaN());
    for (std::size_t i = 0; i < s.bodies().size(); ++i) {
      const auto p = frame.add_point(s.bodies().position_m[i]);
      const auto c = frame.add_cell(fq::VtkCellType::Vertex, {p});
      frame.set(height, c, s.bodies().position_m[i].z());
    }
  });
  out.add_history_column("beam_height_m", [](const fq::Simulation& s) { return s.bodies().position_m[2].z(); });
  EXPECT_THROW(out.add_history_column("nounit", [](const fq::Simulation&) { return 0.0; }), std::invalid_argument);
  EXPECT_THROW(out.add_history_column("bad,name_m", [](const fq::Simulation&) { return 0.0; }), std::invalid_argument);
  EXPECT_THROW(out.add_history_column("time_s", [](const fq::Simulation&) { return 0.0; }), std::invalid_argument);
  EXPECT_THROW(out.add_summary_field("status", "1"), std::invalid_argument);
  EXPECT_THROW(out.add_summary_field("extra", "{oops}"), std::invalid_argument);
  out.attach(*sim);
  EXPECT_THROW(out.add_history_column("late_m", [](const fq::Simulation&) { return 0.0; }), std::logic_error);
  out.finish(*sim, sim->run());

  const std::vector<BodySpec> bodies = scene_bodies();
  const std::size_t n = bodies.size();
  ReadFrame f = read_vtu(def.folder / "frames" / "frame_000001.vtu");  // t = 0.01 s
  ASSERT_EQ(f.errors, 0);
  vtkUnstructuredGrid* g = f.grid;
  ASSERT_EQ(g->GetNumberOfCells(), vtkIdType(2 * n));
  const double t = 0.01;
  auto* block_names = vtkStringArray::SafeDownCast(g->GetFieldData()->GetAbstractArray("cell_block_names"));
  ASSERT_NE(block_names, nullptr);
  ASSERT_EQ(block_names->GetNumberOfValues(), 2);
  EXPECT_EQ(block_names->GetValue(0), "bodies");
  EXPECT_EQ(block_names->GetValue(1), "markers");
  vtkDataArray* height = g->GetCellData()->GetArray("marker_height_m");
  ASSERT_NE(height, nullptr);
  for (vtkIdType c = 0; c < vtkIdType(2 * n); ++c) {
    const bool body_cell = c < vtkIdType(n);
    const BodySpec& b = bodies[std::size_t(body_cell ? c : c - vtkIdType(n))];
    EXPECT_EQ(g->GetCellType(c), body_cell ? VTK_HEXAHEDRON : VTK_VERTEX);
    EXPECT_EQ(g->GetCellData()->GetArray("cell_block")->GetTuple1(c), body_cell ? 0.0 : 1.0);
    if (body_cell) {
      EXPECT_TRUE(std::isnan(height->GetTuple1(c)));  // fill value on cells of other blocks
    } else {
      EXPECT_EQ(g->GetCellData()->GetArray("body_id")->GetTuple1(c), -1.0);  // fill value
      EXPECT_NEAR(height->GetTuple1(c), expected_position(b, t).z(), 1e-12);
    }
  }
  const std::vector<std::string> lines = read_lines(def.folder / "history.csv");
  ASSERT_EQ(lines.size(), 4u);  // header + steps 0, 5, 10
  EXPECT_EQ(split(lines[0], ',').back(), "beam_height_m");
  for (std::size_t r = 1; r < lines.size(); ++r) {
    const double tr = double(5 * (r - 1)) * kDt_s;
    EXPECT_NEAR(std::strtod(split(lines[r], ',').back().c_str(), nullptr), expected_position(bodies[2], tr).z(), 1e-12);
  }
}

namespace {

// Breaks the run: a non-finite force on body 1 at step `bad_step`.
class PoisonProvider : public fq::ForceProvider {
 public:
  explicit PoisonProvider(std::int64_t bad_step) : bad_step_(bad_step) {}
  const char* name() const override { return "poison"; }
  void accumulate_forces(fq::BodyStore& bodies, const fq::StepInfo& step) override {
    if (step.step == bad_step_) bodies.force_N[1].x() = std::numeric_limits<double>::quiet_NaN();
  }

 private:
  std::int64_t bad_step_;
};

}  // namespace

// A 0.1 m block on the ground with ground contact and no joints, run through
// run_case into dir/out: `duration_s`, the block's extra keys, the output's
// extra keys.
void run_block_on_ground(const fq::test::TempDir& dir, const std::string& duration_s, const std::string& block_extra,
                         const std::string& output_extra) {
  const fs::path file = dir.path() / "block.yaml";
  std::ofstream(file) << "framequake_case: 1\n"
                         "time: {dt_s: 1.0e-5, duration_s: " << duration_s << "}\n"
                         "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
                         "ground: {level_m: 0.0}\n"
                         "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.05], material: spruce"
                      << block_extra << "}]\n"
                         "contact: {ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.5, friction_coefficient: 0.4}}\n"
                         "output: {frame_interval_s: 0.001, history_interval_s: 0.001"
                      << output_extra << "}\n";
  fq::CaseRunOptions options;
  options.output_folder = dir.path() / "out";
  ASSERT_EQ(fq::run_case(fq::load_case_file(file), options).result.status, fq::RunStatus::Completed);
}

// docs/paraview.md promises cell_block 0 bodies, 1 springs, 2 contacts, so
// that one ParaView threshold works for every run: a case with contacts but
// no joints (a block resting on the ground) must keep its contact points at
// 2, with an empty springs block before them.
TEST(RunOutput, CellBlocksKeepTheirNumbersInASceneWithoutJoints) {
  fq::test::TempDir dir;
  run_block_on_ground(dir, "0.002", "", "");
  ReadFrame f = read_vtu(dir.path() / "out" / "frames" / "frame_000002.vtu");
  ASSERT_EQ(f.errors, 0);
  vtkUnstructuredGrid* g = f.grid;
  auto* names = vtkStringArray::SafeDownCast(g->GetFieldData()->GetAbstractArray("cell_block_names"));
  ASSERT_NE(names, nullptr);
  ASSERT_EQ(names->GetNumberOfValues(), 3);
  EXPECT_EQ(names->GetValue(0), "bodies");
  EXPECT_EQ(names->GetValue(1), "springs");
  EXPECT_EQ(names->GetValue(2), "contacts");
  // Two bodies (the ground, the block), then the block's four corner contacts.
  ASSERT_EQ(g->GetNumberOfCells(), 6);
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c)
    EXPECT_EQ(g->GetCellData()->GetArray("cell_block")->GetTuple1(c), c < 2 ? 0.0 : 2.0) << c;
}

// ASCII frames of a run with contacts: their cell arrays hold NaN on the
// cells of other blocks, and VTK caches an L2-norm range for such arrays
// that it writes as an information key it cannot read back (an error logged
// by vtkXMLUnstructuredGridReader for every such array). Every frame must
// read without an error.
TEST(RunOutput, AsciiFramesOfARunWithContactsReadWithoutErrors) {
  fq::test::TempDir dir;
  run_block_on_ground(dir, "0.01", ", velocity_mps: [0.3, 0, -0.2], angular_velocity_radps: [0, 2, 0]",
                      ", vtk_binary: false");
  int frames = 0, with_contacts = 0;
  for (const auto& entry : fs::directory_iterator(dir.path() / "out" / "frames")) {
    ReadFrame f = read_vtu(entry.path());
    EXPECT_EQ(f.errors, 0) << entry.path();
    ++frames;
    with_contacts += f.grid->GetNumberOfCells() > 2;
  }
  EXPECT_EQ(frames, 11);
  EXPECT_GT(with_contacts, 0);  // the block lands: contact cells with NaN-filled arrays on the body cells
}

// damage_state colours members by their joints; the ground is no member and
// is left at the array's fill, -1 (it took the states of the support
// joints, so a portal frame's ground read "yielded" and frame A's
// "detached"; output probe). The portal demo for 0.05 s: every joint still
// elastic, so each member is 0, intact.
TEST(RunOutput, TheGroundHasNoDamageState) {
  fq::test::TempDir dir;
  fq::CaseDef def = fq::load_case_file(fs::path(FQ_SOURCE_DIR) / "cases" / "demo_portal_frame.yaml");
  def.time.duration_s = 0.05;
  def.output.folder = dir.path() / "out";
  const fq::CaseRunReport report = fq::run_case(def, {});
  ASSERT_EQ(report.result.status, fq::RunStatus::Completed);
  bool ok = false;
  const std::vector<PvdEntry> entries = parse_pvd(def.output.folder / "case.pvd", &ok);
  ASSERT_TRUE(ok);
  ASSERT_FALSE(entries.empty());
  ReadFrame f = read_vtu(def.output.folder / entries.back().file);
  ASSERT_EQ(f.errors, 0);
  vtkDataArray* damage = f.grid->GetCellData()->GetArray("damage_state");
  vtkDataArray* kind = f.grid->GetCellData()->GetArray("member_kind");
  ASSERT_NE(damage, nullptr);
  ASSERT_NE(kind, nullptr);
  int ground = 0, members = 0;
  for (vtkIdType c = 0; c < f.grid->GetNumberOfCells(); ++c) {
    if (f.grid->GetCellType(c) != VTK_HEXAHEDRON) continue;
    if (kind->GetTuple1(c) == double(int(fq::MemberKind::Ground))) {
      EXPECT_EQ(damage->GetTuple1(c), -1.0) << "cell " << c;
      ++ground;
    } else {
      EXPECT_EQ(damage->GetTuple1(c), 0.0) << "cell " << c;
      ++members;
    }
  }
  EXPECT_EQ(ground, 1);
  EXPECT_GT(members, 0);
}

TEST(RunOutput, UnstableRunKeepsGoodFramesAndWritesSummaryAndEvent) {
  auto sim = make_simulation(0.1);
  sim->add_force_provider(std::make_unique<PoisonProvider>(7));
  fq::OutputDef def;
  def.folder = fresh_folder("unstable");
  def.frame_interval_s = 0.002;    // every 2 steps
  def.history_interval_s = 0.001;  // every step
  fq::RunOutput out(def, "unstable");
  out.attach(*sim);
  const fq::RunResult result = sim->run();
  ASSERT_EQ(result.status, fq::RunStatus::Unstable);
  out.finish(*sim, result);

  // Steps 0..6 completed, so states 0..7 were sampled; step 7 failed.
  bool ok = false;
  const std::vector<PvdEntry> entries = parse_pvd(def.folder / "case.pvd", &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(entries.size(), 4u);  // states 0, 2, 4, 6
  for (const PvdEntry& e : entries) {
    ReadFrame f = read_vtu(def.folder / e.file);
    EXPECT_EQ(f.errors, 0);
    double bounds[6];
    f.grid->GetBounds(bounds);
    for (double b : bounds) EXPECT_TRUE(std::isfinite(b)) << e.file;
  }
  EXPECT_EQ(read_lines(def.folder / "history.csv").size(), 1u + 8u);
  const std::vector<std::string> events = read_lines(def.folder / "events.csv");
  ASSERT_EQ(events.size(), 2u);
  const std::vector<std::string> cols = split(events[1], ',');
  ASSERT_EQ(cols.size(), 16u);
  EXPECT_EQ(cols[1], "7");
  EXPECT_EQ(cols[2], "instability");
  EXPECT_EQ(cols[4], "1");  // the poisoned body
  // Its name from the scene (body 1 is "column"), and none for body_b = -1:
  // a weak point read without the frames (workflow probe).
  EXPECT_EQ(cols[5], "-1");
  EXPECT_EQ(cols[12], "column");
  EXPECT_EQ(cols[13], "");
  // An instability belongs to no joint (joint_id -1): no node, no joint name.
  EXPECT_EQ(cols[3], "-1");
  EXPECT_EQ(cols[14], "");
  EXPECT_EQ(cols[15], "");
  const std::string summary = read_text(def.folder / "summary.json");
  EXPECT_TRUE(fq::json_is_valid(summary));
  EXPECT_NE(summary.find("\"status\": \"unstable\""), std::string::npos);
  EXPECT_NE(summary.find("\"instability\": 1"), std::string::npos);
  EXPECT_NE(summary.find("\"poison\": "), std::string::npos);
  EXPECT_EQ(summary.find("\"message\": \"\""), std::string::npos) << "an unstable run must say why";
  EXPECT_THROW(out.finish(*sim, result), std::logic_error);
}

namespace {

class StopAt : public fq::StepObserver {
 public:
  StopAt(std::int64_t step, std::atomic<bool>* flag) : step_(step), flag_(flag) {}
  void on_sample(const fq::Simulation& sim) override {
    if (sim.steps_done() >= step_) flag_->store(true);
  }

 private:
  std::int64_t step_;
  std::atomic<bool>* flag_;
};

}  // namespace

TEST(RunOutput, StoppedRunEndsWithAFrameOfTheLastState) {
  auto sim = make_simulation(1.0);
  fq::OutputDef def;
  def.folder = fresh_folder("stopped");
  def.frame_interval_s = 0.02;
  def.history_interval_s = 0.005;
  fq::RunOutput out(def, "stopped");
  out.attach(*sim);
  std::atomic<bool> stop{false};
  StopAt stopper(13, &stop);
  sim->add_observer(&stopper, 1);
  const fq::RunResult result = sim->run(&stop);
  ASSERT_EQ(result.status, fq::RunStatus::Stopped);
  ASSERT_EQ(result.steps, 13);
  out.finish(*sim, result);
  bool ok = false;
  const std::vector<PvdEntry> entries = parse_pvd(def.folder / "case.pvd", &ok);
  ASSERT_TRUE(ok);
  ASSERT_EQ(entries.size(), 2u);  // steps 0 and 13 (the stop)
  EXPECT_NEAR(entries.back().time_s, 13 * kDt_s, 1e-12);
  EXPECT_EQ(read_lines(def.folder / "history.csv").size(), 1u + 4u);  // steps 0, 5, 10, 13
  EXPECT_NE(read_text(def.folder / "summary.json").find("\"status\": \"stopped\""), std::string::npos);
}

// A write that fails in the middle of a run (a full disk, a folder made
// read-only or removed) ends the run with an OutputError (exit 3 of the
// command line), not an internal error, and leaves a folder that claims
// nothing it does not hold: history.csv cut back to whole rows, case.pvd
// listing only frames on disk, and summary.json saying output_failed with
// the step reached. The failure is made portably (root ignores file modes):
// after step 2000 (whose frame is written) an observer replaces frames/ by a
// regular file, so the frame due at step 2100 cannot be created.
namespace {
class ReplaceFramesFolderWithAFile : public fq::StepObserver {
 public:
  explicit ReplaceFramesFolderWithAFile(fs::path folder) : folder_(std::move(folder)) {}
  void on_sample(const fq::Simulation& sim) override {
    if (done_ || sim.steps_done() <= 2000) return;
    done_ = true;
    fs::remove_all(folder_ / "frames");
    std::ofstream(folder_ / "frames") << "not a folder\n";
  }

 private:
  fs::path folder_;
  bool done_ = false;
};
}  // namespace

TEST(RunOutput, AWriteFailingMidRunEndsWithAnOutputErrorWholeRowsAndASummarySayingSo) {
  fq::test::TempDir dir;
  const fs::path file = dir.path() / "block.yaml";
  std::ofstream(file) << "framequake_case: 1\n"
                         "time: {dt_s: 1.0e-5, duration_s: 0.05}\n"
                         "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
                         "ground: {level_m: 0.0}\n"
                         "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.05], material: spruce}]\n"
                         "contact: {ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.5}}\n"
                         "output: {frame_interval_s: 0.001, history_interval_s: 0.0001}\n";
  const fs::path out = dir.path() / "out";
  ReplaceFramesFolderWithAFile saboteur(out);
  fq::CaseRunOptions options;
  options.output_folder = out;
  options.progress = &saboteur;  // asked after every step, before the frames
  std::string message;
  try {
    fq::run_case(fq::load_case_file(file), options);
    ADD_FAILURE() << "the run did not report the failed frame";
  } catch (const fq::OutputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("frame_000021.vtu"), std::string::npos) << message;
  EXPECT_NE(message.find("summary.json says output_failed"), std::string::npos) << message;

  const std::string summary = read_text(out / "summary.json");
  EXPECT_EQ(json_field(summary, "status"), "\"output_failed\"") << summary;
  EXPECT_EQ(json_field(summary, "steps"), "2100");  // the frame due at step 2100 failed
  // The rest of a summary as far as the run got (it had the ground motion
  // only, a wall time of 0 and no steps per second; review probe): the
  // warnings, the contacts' press and the state hash, which is that of an
  // undisturbed run of the same 2100 steps.
  EXPECT_EQ(json_field(summary, "warnings").substr(0, 1), "[") << summary;
  EXPECT_NE(json_field(summary, "contact_press_peak"), "") << summary;
  EXPECT_GT(std::stod(json_field(summary, "wall_time_s")), 0.0) << summary;
  EXPECT_GT(std::stod(json_field(summary, "steps_per_second")), 0.0) << summary;
  {
    fq::CaseDef def = fq::load_case_file(file);
    def.time.duration_s = 2100 * 1.0e-5;
    fq::CaseRunOptions undisturbed;
    undisturbed.output_folder = dir.path() / "undisturbed";
    fq::run_case(def, undisturbed);
    const std::string reference = read_text(dir.path() / "undisturbed" / "summary.json");
    EXPECT_EQ(json_field(reference, "steps"), "2100");
    EXPECT_EQ(json_field(summary, "state_hash"), json_field(reference, "state_hash")) << summary;
  }
  // The rows written before the failure (steps 0, 10, ..., 2100) and no
  // part of one; the summary counts what the file holds.
  const std::string history = read_text(out / "history.csv");
  ASSERT_FALSE(history.empty());
  EXPECT_EQ(history.back(), '\n');
  const std::vector<std::string> rows = read_lines(out / "history.csv");
  EXPECT_EQ(rows.size(), 1u + 211u);
  EXPECT_EQ(json_field(summary, "history_rows"), std::to_string(rows.size() - 1));
  // case.pvd lists only frames that existed when it was written (0..20).
  bool ok = false;
  const std::vector<PvdEntry> entries = parse_pvd(out / "case.pvd", &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(entries.size(), 21u);
}

// summary.json's stable_dt_s is the engine's estimate as the shortest text
// that reads back to it, as every number of the summary (it was printed to
// 17 digits, one too many for most values; review probe).
TEST(RunOutput, SummaryGivesTheStableStepAsTheShortestTextOfTheEstimate) {
  fq::test::TempDir dir;
  const fs::path file = dir.path() / "cube.yaml";
  std::ofstream(file) << "framequake_case: 1\n"
                         "time: {dt_s: 1.0e-5, duration_s: 0.001}\n"
                         "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
                         "ground: {level_m: 0.0}\n"
                         "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.05], material: spruce}]\n"
                         "contact: {ground: {normal_stiffness_N_per_m: 8.0e5, restitution: 0.5}}\n";
  fq::CaseRunOptions options;
  options.output_folder = dir.path() / "out";
  const fq::CaseRunReport report = fq::run_case(fq::load_case_file(file), options);
  // (At this stiffness the estimate's shortest text has 16 digits, so 17
  // would differ: 0.0002645405806336698 against 0.00026454058063366979.)
  const double estimate_s = report.stable_time_step.dt_crit_s;
  ASSERT_TRUE(std::isfinite(estimate_s));
  char shortest[32];
  const auto end = std::to_chars(shortest, shortest + sizeof shortest, estimate_s).ptr;
  const std::string text = json_field(read_text(options.output_folder.value() / "summary.json"), "stable_dt_s");
  EXPECT_EQ(text, std::string(shortest, end));
  EXPECT_EQ(std::stod(text), estimate_s);
}

// The cut itself: an appended file that ends in part of a row loses that
// part and nothing else; whole files and files without a line end stay.
TEST(RunOutput, AnAppendedFileIsCutBackToItsLastCompleteRow) {
  fq::test::TempDir dir;
  const fs::path f = dir.path() / "rows.csv";
  std::ofstream(f, std::ios::binary) << "time_s,x_m\n0,1\n0.1,2\n0.2,";
  fq::detail::cut_back_to_last_line_end(f);
  EXPECT_EQ(read_text(f), "time_s,x_m\n0,1\n0.1,2\n");
  EXPECT_EQ(fq::detail::count_line_ends(f), 3);
  fq::detail::cut_back_to_last_line_end(f);  // already whole
  EXPECT_EQ(read_text(f), "time_s,x_m\n0,1\n0.1,2\n");
  // A long row (longer than one read block) after the last line end.
  std::ofstream(f, std::ios::binary | std::ios::app) << std::string(10000, '7');
  fq::detail::cut_back_to_last_line_end(f);
  EXPECT_EQ(read_text(f), "time_s,x_m\n0,1\n0.1,2\n");
  std::ofstream(f, std::ios::binary | std::ios::trunc) << "no line end";
  fq::detail::cut_back_to_last_line_end(f);
  EXPECT_EQ(read_text(f), "no line end");
  EXPECT_EQ(fq::detail::count_line_ends(dir.path() / "missing.csv"), -1);
}

// A spring line's end on a member is where that member is drawn in the same
// frame: a column on a four-corner support joint (points at the section's
// corners on the column's foot plane, which is its box's end face) has, in
// every frame, one end of each spring at a vertex of the column's box to
// round-off. The frames drew the ends of the last force evaluation, a step
// before the bodies (1e-7 m off a column swaying under a record; VTK probe).
TEST(RunOutput, SpringEndsAreOnTheBodiesOfTheSameFrame) {
  fq::test::TempDir dir;
  std::ofstream(dir.path() / "sine.txt") << fq::test::sine_record(0.3);
  const auto file = dir.write("column.yaml",
                              "framequake_case: 1\n"
                              "time: {dt_s: 1.0e-5, duration_s: 0.3}\n"
                              "materials: [{name: wood, density_kg_per_m3: 450}]\n"
                              "sections: [{name: col, width_m: 0.02, depth_m: 0.02}]\n"
                              "nodes: [{id: a, xyz_m: [0, 0, 0]}, {id: b, xyz_m: [0, 0, 0.3]}]\n"
                              "members: [{id: c, kind: column, nodes: [a, b], section: col, material: wood}]\n"
                              "joint_types: [{name: base, layout: four_corner,\n"
                              "               normal: {law: linear, stiffness_N_per_m: 1.0e4},\n"
                              "               shear: {law: linear, stiffness_N_per_m: 1.0e4},\n"
                              "               fracture: {criterion: never}}]\n"
                              "supports: [{node: a, joint_type: base}]\n"
                              "ground_motion: {components: [{file: sine.txt, format: two_column, axis: x}]}\n"
                              "output: {frame_interval_s: 0.1, history_interval_s: 0.01}\n");
  fq::CaseRunOptions options;
  options.output_folder = dir.path() / "out";
  ASSERT_EQ(fq::run_case(fq::load_case_file(file), options).result.status, fq::RunStatus::Completed);
  for (const char* name : {"frame_000001.vtu", "frame_000002.vtu", "frame_000003.vtu"}) {
    ReadFrame f = read_vtu(dir.path() / "out" / "frames" / name);
    ASSERT_EQ(f.errors, 0) << name;
    vtkUnstructuredGrid* g = f.grid;
    vtkDataArray* block = g->GetCellData()->GetArray("cell_block");
    vtkDataArray* body_id = g->GetCellData()->GetArray("body_id");
    ASSERT_NE(block, nullptr);
    ASSERT_NE(body_id, nullptr);
    std::vector<fq::Vec3> column_corners;
    std::vector<std::pair<fq::Vec3, fq::Vec3>> springs;
    for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
      vtkIdType n = 0;
      const vtkIdType* ids = nullptr;
      g->GetCellPoints(c, n, ids);
      if (block->GetTuple1(c) == 0.0 && n == 8 && hex_volume(g, c) < 0.3 * 0.02 * 0.02 * 1.01) {
        for (int k = 0; k < 8; ++k) {
          fq::Vec3 p;
          g->GetPoint(ids[k], p.data());
          column_corners.push_back(p);
        }
      } else if (block->GetTuple1(c) == 1.0 && n == 2) {
        fq::Vec3 a, b;
        g->GetPoint(ids[0], a.data());
        g->GetPoint(ids[1], b.data());
        springs.emplace_back(a, b);
      }
    }
    ASSERT_EQ(column_corners.size(), 8u) << name;
    ASSERT_EQ(springs.size(), 12u) << name;  // four points, a normal and two shear springs each
    for (const auto& [a, b] : springs) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const fq::Vec3& corner : column_corners)
        nearest = std::min({nearest, (a - corner).norm(), (b - corner).norm()});
      EXPECT_LT(nearest, 1e-12) << name;
    }
  }
}

// The output-size check measures a history row by the mean length of the
// rows written (HistoryWriter::mean_row_bytes): exactly what the file grows
// by per row, header excluded, and only the rows of this process after a
// reopen. (The file's size over its rows counted the header in, 67 % too
// much for a stress probe's run; a resumed run's whole file was taken as
// one row, 18 GB announced for 16 MB.)
TEST(RunOutput, HistoryRowSizeIsTheMeanOfTheRowsWritten) {
  fq::test::TempDir dir;
  const auto file = dir.write("block.yaml",
                              "framequake_case: 1\n"
                              "time: {dt_s: 1.0e-3, duration_s: 0.05}\n"
                              "materials: [{name: wood, density_kg_per_m3: 450}]\n"
                              "blocks: [{id: b, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 1], material: wood,\n"
                              "          angular_velocity_radps: [1, 2, 3]}]\n");
  fq::Scene scene = fq::build_scene(fq::load_case_file(file));
  fq::Simulation& sim = *scene.simulation;
  sim.initialize();
  fq::HistoryWriter history;
  const fs::path csv = dir.path() / "history.csv";
  history.open(csv, sim);
  history.flush();
  const auto header_bytes = fs::file_size(csv);
  EXPECT_EQ(history.mean_row_bytes(), 0.0);
  // A step and a row, `count` times, then the rows flushed to the file.
  auto step_and_write = [&](int count) {
    for (int k = 0; k < count; ++k) {
      ASSERT_TRUE(sim.step());
      history.write_row(sim);
    }
    history.flush();
  };
  step_and_write(20);
  EXPECT_EQ(history.rows_this_process(), 20);
  EXPECT_DOUBLE_EQ(history.mean_row_bytes(), double(fs::file_size(csv) - header_bytes) / 20.0);
  // Reopened as a resumed run does: the rows before count no more.
  const auto before = fs::file_size(csv);
  history.close();
  history.reopen(csv, std::vector<fq::Vec3>(sim.bodies().size(), fq::Vec3::Zero()), before, 20);
  EXPECT_EQ(history.rows_this_process(), 0);
  step_and_write(5);
  EXPECT_EQ(history.rows(), 25);
  EXPECT_DOUBLE_EQ(history.mean_row_bytes(), double(fs::file_size(csv) - before) / 5.0);
}

namespace {
std::size_t thread_count_of_this_process() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator("/proc/self/task")) ++n;
  return n;
}
}  // namespace

// Writing frames starts no threads: VTK's SMP backend (TBB on Debian) would
// start a pool of spinning workers for the writer's array ranges, which take
// CPU from the engine and from other runs of `compare --jobs` and gain
// nothing on frames of a few hundred points (vtk_frame_writer.cpp).
TEST(RunOutput, WritingFramesStartsNoThreads) {
  if (std::getenv("VTK_SMP_BACKEND_IN_USE") != nullptr) GTEST_SKIP() << "VTK_SMP_BACKEND_IN_USE is set";
  auto sim = make_simulation(0.01);
  sim->initialize();
  fq::VtkFrameWriter writer;
  const fs::path folder = fresh_folder("no_threads");
  fs::create_directories(folder);
  const std::size_t before = thread_count_of_this_process();
  for (int k = 0; k < 3; ++k) {
    sim->step();
    writer.write(*sim, folder / ("frame_" + std::to_string(k) + ".vtu"), true);
  }
  EXPECT_EQ(thread_count_of_this_process(), before);
}

#if defined(__GLIBC__) && !FQ_ADDRESS_SANITIZER
#if __GLIBC_PREREQ(2, 33)
// Writing a frame, VTK allocates and frees some forty blocks; the frame
// writer keeps glibc from returning the freed top of the heap to the kernel
// after each of them (vtk_frame_writer.cpp: 25 482 brk calls and their page
// faults in a run of frame B before). A 24 MiB block, after a writer
// exists, comes from the heap (glibc's default would map it: its mmap
// threshold starts at 128 KiB and only rises to the size of a mapped block
// freed before) and, freed, stays in it (the default trim threshold is
// 128 KiB, or twice the raised mmap threshold). (Not under AddressSanitizer,
// whose allocator replaces glibc's; mallinfo2 is glibc 2.33's.)
TEST(RunOutput, FrameWriterKeepsFreedHeapForTheNextFrame) {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (std::getenv("MALLOC_TRIM_THRESHOLD_") || std::getenv("MALLOC_MMAP_THRESHOLD_") ||
      (tunables && std::strstr(tunables, "glibc.malloc.") != nullptr))
    GTEST_SKIP() << "the user's own malloc thresholds are set";
  const fq::VtkFrameWriter writer;
  constexpr std::size_t kBlockBytes = std::size_t(24) << 20;
  const struct mallinfo2 before = mallinfo2();
  void* block = std::malloc(kBlockBytes);
  ASSERT_NE(block, nullptr);
  std::memset(block, 1, kBlockBytes);
  const struct mallinfo2 held = mallinfo2();
  std::free(block);
  const struct mallinfo2 after = mallinfo2();
  EXPECT_EQ(held.hblkhd, before.hblkhd) << "the block was mapped, not taken from the heap";
  EXPECT_GE(held.uordblks, before.uordblks + kBlockBytes) << "the block is not counted in the heap's blocks in use";
  EXPECT_EQ(after.arena, held.arena) << "the freed block was returned to the kernel";
}
#endif
#endif
