// The notes under the comparison table (apps/comparison_notes.h): the order
// in which each case's storeys collapsed, each run's warnings, and the cases'
// contact models, on made-up
// reports (the expected text follows from the reports given, by the
// definition in the header).
#include <gtest/gtest.h>

#include <cmath>

#include <string>
#include <vector>

#include "comparison_notes.h"

namespace {

fq::StoreyOutcome storey(int number, double collapse_time_s) {
  fq::StoreyOutcome s;
  s.number = number;
  s.drift.collapse_time_s = collapse_time_s;
  return s;
}

// A retrofit probe's case: first-storey braces moved the collapse up, the
// second storey falling first (2.596 s), the first after it (2.740 s);
// the original frame's first storey fell first (3.170 s, then 3.716 s).
TEST(ComparisonNotes, StoreysAreListedInTheOrderTheyCollapsed) {
  fq::CaseRunReport original, braced, standing;
  original.storeys = {storey(1, 3.170), storey(2, 3.716)};
  braced.storeys = {storey(1, 2.740), storey(2, 2.596)};
  standing.storeys = {storey(1, -1.0), storey(2, -1.0)};
  const std::string note = fq_app::collapse_order_note(
      {{"frame_A", &original}, {"A_braced", &braced}, {"frame_C", &standing}, {"failed", nullptr}});
  EXPECT_NE(note.find("- frame_A: storey 1 at 3.170 s, storey 2 at 3.716 s\n"), std::string::npos) << note;
  EXPECT_NE(note.find("- A_braced: storey 2 at 2.596 s, storey 1 at 2.740 s\n"), std::string::npos) << note;
  EXPECT_EQ(note.find("frame_C"), std::string::npos) << note;
  EXPECT_EQ(note.find("failed"), std::string::npos) << note;
  EXPECT_EQ(fq_app::collapse_order_note({{"frame_C", &standing}}), "");
}

// A run that became unstable is not assessed (the table's verdict), so its
// drifts past the collapse limit are no collapse (a probe's forced run was
// listed as "unstable: storey 1 at 0.004 s").
TEST(ComparisonNotes, AnUnstableRunIsNotListedAsCollapsed) {
  fq::CaseRunReport blown, fallen;
  blown.result.status = fq::RunStatus::Unstable;
  blown.storeys = {storey(1, 0.004)};
  fallen.result.status = fq::RunStatus::Completed;
  fallen.storeys = {storey(1, 3.170)};
  EXPECT_EQ(fq_app::collapse_order_note({{"unstable", &blown}}), "");
  const std::string note = fq_app::collapse_order_note({{"unstable", &blown}, {"frame_A", &fallen}});
  EXPECT_NE(note.find("- frame_A: storey 1 at 3.170 s\n"), std::string::npos) << note;
  EXPECT_EQ(note.find("unstable"), std::string::npos) << note;
}

TEST(ComparisonNotes, EveryWarningOfEveryRunIsListedUnderItsCase) {
  fq::CaseRunReport a, b;
  a.warnings = {"storey 1 twists: column 'column1_sw' alone drifted 0.113 rad", "second warning"};
  const std::string note = fq_app::warnings_note({{"A_one_face", &a}, {"frame_B", &b}, {"failed", nullptr}});
  EXPECT_NE(note.find("- A_one_face: storey 1 twists: column 'column1_sw' alone drifted 0.113 rad\n"),
            std::string::npos)
      << note;
  EXPECT_NE(note.find("- A_one_face: second warning\n"), std::string::npos) << note;
  EXPECT_EQ(note.find("frame_B"), std::string::npos) << note;
  EXPECT_EQ(fq_app::warnings_note({{"frame_B", &b}}), "");
}

// A comparison of one frame under two contact models reads the same as
// one of two frames unless the model is named: it is, as soon as one case
// leaves the default (touch), for every case; cases without contacts say so.
TEST(ComparisonNotes, ContactModelsAreNamedWhenAnyCaseLeavesTheDefault) {
  const std::string note = fq_app::contact_model_note(
      {{"frame_B", "touch"}, {"frame_B_seed", "none"}, {"blocks", ""}});
  EXPECT_NE(note.find("- frame_B: touch\n"), std::string::npos) << note;
  EXPECT_NE(note.find("- frame_B_seed: none\n"), std::string::npos) << note;
  EXPECT_NE(note.find("- blocks: no contacts\n"), std::string::npos) << note;
  EXPECT_EQ(fq_app::contact_model_note({{"frame_A", "touch"}, {"frame_B", "touch"}, {"blocks", ""}}), "");
}

// Cases run with different integrators or steps say so under the table,
// each with its own; cases that share both say nothing.
TEST(ComparisonNotes, IntegratorsAndStepsAreNamedWhenTheCasesDiffer) {
  const std::string note = fq_app::time_integration_note(
      {{"portal", "central_difference", 1e-5}, {"portal_rk4", "rk4", 1e-5}, {"portal_vv", "velocity_verlet", 2e-5}});
  EXPECT_NE(note.find("- portal: central_difference, dt_s = 1e-05 s\n"), std::string::npos) << note;
  EXPECT_NE(note.find("- portal_rk4: rk4, dt_s = 1e-05 s\n"), std::string::npos) << note;
  EXPECT_NE(note.find("- portal_vv: velocity_verlet, dt_s = 2e-05 s\n"), std::string::npos) << note;
  EXPECT_NE(fq_app::time_integration_note({{"a", "central_difference", 1e-5}, {"b", "central_difference", 2e-5}}),
            "");
  // The integrator alone, and steps that differ in the last bit, each
  // printed as it reads back.
  EXPECT_NE(fq_app::time_integration_note({{"a", "central_difference", 1e-5}, {"b", "rk4", 1e-5}}), "");
  const std::string close =
      fq_app::time_integration_note({{"a", "rk4", 1e-5}, {"b", "rk4", std::nextafter(1e-5, 1.0)}});
  EXPECT_NE(close.find("- a: rk4, dt_s = 1e-05 s\n"), std::string::npos) << close;
  EXPECT_NE(close.find("- b: rk4, dt_s = 1.00000000000000"), std::string::npos) << close;
  EXPECT_EQ(fq_app::time_integration_note(
                {{"frame_A", "central_difference", 1e-5}, {"frame_B", "central_difference", 1e-5}}),
            "");
}

}  // namespace

// The ground motion is always named: one line when every case ran under the
// same one (its peak from a case that completed; 9.80665 m/s² is 1 g), a line
// per case when they differ, with "none" for a case without ground motion,
// no peak for a case that did not run, and a vertical-only motion said to
// have no horizontal acceleration (its horizontal PGA is 0).
TEST(ComparisonNotes, TheGroundMotionIsNamedOnceWhenSharedAndPerCaseWhenNot) {
  const double not_run = std::nan("");
  const std::string kobe = "KJM000.AT2 along x, record seconds 0 to 20 at time scale 0.3162";
  const std::string kobe_path = "/r/" + kobe, up = "KJM-UP.AT2 along z, record seconds 0 to 20";
  EXPECT_EQ(fq_app::ground_motion_note(
                {{"A", kobe, kobe_path, not_run}, {"B", kobe, kobe_path, 9.80665}, {"C", kobe, kobe_path, 9.80665}}),
            "\nGround motion (every case): " + kobe + "; horizontal PGA 9.81 m/s² (1 g)\n");
  // Two records of one name in different folders are two motions.
  EXPECT_EQ(fq_app::ground_motion_note({{"A", kobe, kobe_path, 9.80665}, {"B", kobe, "/s/" + kobe, 4.903325}}),
            "\nGround motion of each case (they differ: the verdicts compare the frames under different shaking):\n"
            "- A: " + kobe + "; horizontal PGA 9.81 m/s² (1 g)\n"
            "- B: " + kobe + "; horizontal PGA 4.9 m/s² (0.5 g)\n");
  EXPECT_EQ(fq_app::ground_motion_note({{"A", kobe, kobe_path, 4.903325}, {"up", up, "/r/" + up, 0.0},
                                        {"still", "", "", 0.0}, {"D", kobe, kobe_path, not_run}}),
            "\nGround motion of each case (they differ: the verdicts compare the frames under different shaking):\n"
            "- A: " + kobe + "; horizontal PGA 4.9 m/s² (0.5 g)\n"
            "- up: KJM-UP.AT2 along z, record seconds 0 to 20; no horizontal acceleration\n"
            "- still: none; no horizontal acceleration\n"
            "- D: " + kobe + "\n");
  EXPECT_EQ(fq_app::ground_motion_note({}), "");
}
