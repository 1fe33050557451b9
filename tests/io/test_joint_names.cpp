// How the outputs name a joint (retrofit probe: joint numbers change from
// case to case, the frames carried only joint_id, events.csv no node, the
// summary no joint id, and the frames showed every spring of a broken joint
// as deleted). The case is cases/demo_breaking_cantilever.yaml: a column
// from node `base` to node `top` on a support at `base`, and an arm from
// `top` to `tip` on a weak any_spring_deleted joint that breaks under
// gravity. From the case file's own ids, its joints are the column-arm
// joint at `top` (the column is the hub, side a) and the support joint at
// `base` (ground on side a): names "top:column-arm" and
// "base:ground-column", nodes "top" and "base".
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io_test_util.h"

namespace fq {
namespace {

using test::TempDir;

const std::filesystem::path kCase = std::filesystem::path(FQ_SOURCE_DIR) / "cases/demo_breaking_cantilever.yaml";

// The joints the case file describes, by the bodies they join (names of
// body_a and body_b): node and name.
const std::map<std::string, std::pair<std::string, std::string>> kExpected = {
    {"column|arm", {"top", "top:column-arm"}},
    {"ground|column", {"base", "base:ground-column"}},
};

std::vector<std::string> split_csv(const std::string& line) {
  // The case's ids need no quoting.
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// One run of the cantilever shared by the tests below.
struct CantileverRun {
  TempDir dir;
  std::filesystem::path out;
  CantileverRun() {
    CaseRunOptions options;
    out = dir.path() / "out";
    options.output_folder = out;
    const CaseRunReport report = run_case(load_case_file(kCase), options);
    EXPECT_EQ(report.result.status, RunStatus::Completed);
  }
};

const CantileverRun& cantilever() {
  static const CantileverRun run;
  return run;
}

struct EventRow {
  std::map<std::string, std::string> field;
};

std::vector<EventRow> read_events(const std::filesystem::path& file, std::vector<std::string>* header_out) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split_csv(line);
  if (header_out) *header_out = header;
  std::vector<EventRow> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = split_csv(line);
    EXPECT_EQ(f.size(), header.size()) << line;
    EventRow r;
    for (std::size_t k = 0; k < std::min(f.size(), header.size()); ++k) r.field[header[k]] = f[k];
    rows.push_back(r);
  }
  return rows;
}

TEST(JointNames, EventsCsvEndsWithTheJointsNodeAndName) {
  std::vector<std::string> header;
  const std::vector<EventRow> rows = read_events(cantilever().out / "events.csv", &header);
  // The columns before are those README documents, in their places.
  const std::vector<std::string> documented = {"time_s", "step",   "kind", "joint_id", "body_a", "body_b",
                                               "spring_index", "mode", "force_N", "x_m", "y_m", "z_m",
                                               "body_a_name", "body_b_name", "node", "joint_name"};
  EXPECT_EQ(header, documented);
  int broken = 0;
  for (const EventRow& r : rows) {
    const auto it = kExpected.find(r.field.at("body_a_name") + "|" + r.field.at("body_b_name"));
    ASSERT_NE(it, kExpected.end()) << r.field.at("body_a_name") << " - " << r.field.at("body_b_name");
    EXPECT_EQ(r.field.at("node"), it->second.first);
    EXPECT_EQ(r.field.at("joint_name"), it->second.second);
    if (r.field.at("kind") == "joint_broken") ++broken;
  }
  EXPECT_EQ(broken, 1);  // the arm's joint: rows to check above
}

TEST(JointNames, SummaryGivesTheFirstFailedJointsIdAndName) {
  const std::string summary = read_text(cantilever().out / "summary.json");
  const std::vector<EventRow> rows = read_events(cantilever().out / "events.csv", nullptr);
  std::string first_id;
  for (const EventRow& r : rows)
    if (r.field.at("kind") == "spring_deleted" || r.field.at("kind") == "joint_broken") {
      first_id = r.field.at("joint_id");
      break;
    }
  ASSERT_FALSE(first_id.empty());
  EXPECT_NE(summary.find("\"first_joint_failure_joint_id\": " + first_id + ","), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"first_joint_failure_joint_name\": \"top:column-arm\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"first_joint_failure\": \"node top: column column - beam arm (type weak_tenon)\""),
            std::string::npos)
      << summary;
}

TEST(JointNames, SummaryFieldsAreNullWithoutAFailure) {
  // The same case for 1 ms: the arm's joint does not fail that soon.
  TempDir dir;
  std::string text = read_text(kCase);
  const std::string from = "duration_s: 0.25", to = "duration_s: 0.001";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), to);
  CaseRunOptions options;
  options.output_folder = dir.path() / "out";
  run_case(load_case_file(dir.write("short.yaml", text)), options);
  const std::string summary = read_text(dir.path() / "out/summary.json");
  EXPECT_NE(summary.find("\"first_joint_failure\": null"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"first_joint_failure_joint_id\": null"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"first_joint_failure_joint_name\": null"), std::string::npos) << summary;
}

vtkStringArray* string_field(vtkUnstructuredGrid* grid, const char* name) {
  return vtkStringArray::SafeDownCast(grid->GetFieldData()->GetAbstractArray(name));
}

TEST(JointNames, FramesNameEveryJointIdAndTellBrokenFromDeletedSprings) {
  // The last frame, read by VTK's own reader.
  std::filesystem::path last;
  for (const auto& e : std::filesystem::directory_iterator(cantilever().out / "frames"))
    if (e.path().extension() == ".vtu" && (last.empty() || e.path() > last)) last = e.path();
  ASSERT_FALSE(last.empty());
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(last.c_str());
  reader->Update();
  ASSERT_EQ(reader->GetErrorCode(), 0);
  vtkUnstructuredGrid* grid = reader->GetOutput();
  vtkStringArray* names = string_field(grid, "joint_names");
  vtkStringArray* nodes = string_field(grid, "joint_nodes");
  ASSERT_NE(names, nullptr);
  ASSERT_NE(nodes, nullptr);
  ASSERT_EQ(names->GetNumberOfValues(), 2);
  ASSERT_EQ(nodes->GetNumberOfValues(), 2);
  // Each joint_id's name and node are those of the bodies its springs join.
  vtkStringArray* bodies = string_field(grid, "body_names");
  ASSERT_NE(bodies, nullptr);
  const std::vector<EventRow> rows = read_events(cantilever().out / "events.csv", nullptr);
  std::map<int, int> deleted;  // spring_deleted rows per joint id
  std::map<int, std::string> pair_of;
  for (const EventRow& r : rows) {
    const int j = std::atoi(r.field.at("joint_id").c_str());
    pair_of[j] = r.field.at("body_a_name") + "|" + r.field.at("body_b_name");
    if (r.field.at("kind") == "spring_deleted") ++deleted[j];
  }
  for (const auto& [j, pair] : pair_of) {
    EXPECT_EQ(names->GetValue(j), kExpected.at(pair).second) << "joint " << j;
    EXPECT_EQ(nodes->GetValue(j), kExpected.at(pair).first) << "joint " << j;
  }
  // Spring states: the broken joint's deleted springs 2 (as many as
  // events.csv deleted), its other springs 3 (joint broken); the support's
  // linear springs 0.
  vtkDataArray* block = grid->GetCellData()->GetArray("cell_block");
  vtkDataArray* state = grid->GetCellData()->GetArray("spring_state");
  vtkDataArray* joint = grid->GetCellData()->GetArray("joint_id");
  vtkDataArray* joint_broken = grid->GetCellData()->GetArray("joint_broken");
  ASSERT_TRUE(block && state && joint && joint_broken);
  int broken_joint = -1;
  for (const auto& [j, pair] : pair_of)
    if (pair == "column|arm") broken_joint = j;
  ASSERT_GE(broken_joint, 0);
  std::map<int, std::map<int, int>> states;  // joint id -> state -> springs
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    if (block->GetTuple1(c) != 1) continue;
    const int j = int(joint->GetTuple1(c));
    ++states[j][int(state->GetTuple1(c))];
    EXPECT_EQ(joint_broken->GetTuple1(c), j == broken_joint ? 1.0 : 0.0) << "cell " << c;
  }
  const int springs = states[broken_joint][2] + states[broken_joint][3];
  EXPECT_EQ(springs, 12);  // four_corner: four points of one normal and two shear springs
  EXPECT_GT(deleted[broken_joint], 0);
  EXPECT_EQ(states[broken_joint][2], deleted[broken_joint]);
  EXPECT_EQ(states[broken_joint][3], 12 - deleted[broken_joint]);
  const int support = 1 - broken_joint;
  EXPECT_EQ(states[support][0], 12);
}

TEST(JointNames, InfoListsTheJointsOnRequest) {
  std::ostringstream plain, listed;
  describe_case(load_case_file(kCase), plain);
  describe_case(load_case_file(kCase), listed, std::nullopt, true);
  EXPECT_EQ(plain.str().find("top:column-arm"), std::string::npos) << plain.str();
  EXPECT_NE(plain.str().find("--joints lists them"), std::string::npos) << plain.str();
  const std::string text = listed.str();
  // Node joints come first (the column at `top` is the hub), then supports.
  EXPECT_NE(text.find("             0  top:column-arm      node top: column column - beam arm (type weak_tenon)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("             1  base:ground-column  support base: ground - column column (type stiff_support)\n"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace fq
