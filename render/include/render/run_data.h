// What the renderer reads from a run's output folder (io/include/io/run_output.h
// writes it): the frame list of case.pvd, the ground acceleration columns of
// history.csv and the joint breaks of events.csv. Frames themselves (.vtu)
// are read with VTK's XML reader by the renderer, one at a time.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace fq::render {

// A run folder or option the renderer cannot use. The message names the file
// (and line or field) and says what was expected.
class RenderInputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RunFrame {
  double time_s = 0.0;
  std::filesystem::path file;  // absolute or relative to the working folder
};

struct JointBreak {
  double time_s = 0.0;
  int joint_id = -1;
};

struct RunData {
  std::filesystem::path folder;
  std::string label;                  // folder name, shown above the run's view
  std::vector<RunFrame> frames;       // ascending time
  std::vector<double> history_time_s; // history.csv time_s (may be empty)
  // history.csv ground_accel_{x,y,z}_mps2; empty when the columns are absent.
  std::vector<double> ground_accel_mps2[3];
  std::vector<JointBreak> breaks;     // events.csv joint_broken rows (may be empty)
};

// Reads case.pvd (required, at least one frame, every listed .vtu present),
// history.csv and events.csv (optional). Throws RenderInputError.
RunData load_run(const std::filesystem::path& folder);

}  // namespace fq::render
