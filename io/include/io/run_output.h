// Everything a run writes to its output folder (DESIGN.md "Output a user can open"):
//
//   OUT/case.pvd            ParaView collection: one DataSet per frame, timestep = physical time (s)
//   OUT/frames/frame_NNNNNN.vtu   one grid per frame (vtk_frame_writer.h)
//   OUT/history.csv         one row per history sample (history_writer.h)
//   OUT/events.csv          one row per fq::Event
//   OUT/summary.json        written by finish(): status, steps, timing, energy ledger, event counts
//
// Crash safety: frames, case.pvd and summary.json are written under a
// temporary name and renamed, so each exists only when complete, and case.pvd
// is rewritten after each frame to list only frames already on disk (an
// empty, valid case.pvd is written by the constructor). history.csv and
// events.csv are flushed at every frame, so a crash loses at most one frame
// interval of rows.
//
// Extension hooks for later issues (register before attach()):
//   add_cell_block("springs", fn)      more cells in every frame (VtkCellBlock)
//   add_history_column("drift_storey1_x_m", fn)   more history.csv columns
//   add_summary_field("peak_drift", json)         more summary.json fields (any time before finish())
//
// Lifetime: attach() registers observers owned by this object with the
// simulation; it must outlive the simulation's run() (moving the RunOutput is
// safe: the observers sit behind a stable pointer).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dem_core/simulation.h"
#include "io/history_writer.h"
#include "io/output_def.h"
#include "io/vtk_frame_writer.h"

namespace fq {

class StateWriter;  // dem_core/state_io.h
class StateReader;

// The output folder could not be prepared or written (exit code 3 of the
// command line). A frame or history row that cannot be written during the
// run ends it with this error (see RunOutput::abandon).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Steps between frames or rows for an interval: round(interval / dt), at
// least 1 (the interval actually used is that many steps), and at most
// kEveryStepCap, which no run reaches: an interval longer than the run
// samples its start and its end only.
inline constexpr std::int64_t kEveryStepCap = std::int64_t(1) << 62;
std::int64_t steps_per_interval(double interval_s, double dt_s);
// Frames or rows a run of `total_steps` writes sampling every `every` steps
// (>= 1): steps 0, every, 2 every, ..., and the last state once more when
// it is off that grid.
std::int64_t samples_written(std::int64_t total_steps, std::int64_t every);
// A note when that rounding changes the interval (by more than 1e-9 of
// it), naming `field` and the interval used; "" when it does not.
std::string interval_rounding_note(const char* field, double interval_s, double dt_s);

// Whether RunOutput would accept `folder`, without touching it: false when
// it does not exist or is empty, true when it holds a previous run (which
// would be replaced); throws std::runtime_error naming the folder when it
// would be refused (not a folder, or not empty and holding no run). Lets a
// study check every run's folder before the first run starts.
bool check_output_folder(const std::filesystem::path& folder);

// Where a run in `folder` keeps its summary, its history and its frame
// number `index` (frames/frame_NNNNNN.vtu): the names RunOutput writes,
// for code that reads a run's files back.
std::filesystem::path summary_path(const std::filesystem::path& folder);
std::filesystem::path history_path(const std::filesystem::path& folder);
std::filesystem::path frame_path(const std::filesystem::path& folder, std::size_t index);

class RunOutput {
 public:
  // Prepares `def.folder` (creates it and frames/). If the folder exists and
  // holds a previous framequake run (it has case.pvd or summary.json), that
  // run's output files are removed (case.pvd, summary.json, history.csv,
  // events.csv, frames/frame_*.vtu and temporaries; nothing else). If it
  // exists and holds anything else, throws std::runtime_error naming the
  // folder and leaves it untouched. Throws std::invalid_argument on a
  // non-positive interval or an empty folder path. `on_folder_locked`, when
  // given, is called once this process holds the folder's lock and before
  // anything in it is removed: what the folder held can be told then
  // without a run still writing it (a note read before the lock told a
  // user that a live run's folder held a killed one, review probe).
  RunOutput(const OutputDef& def, std::string case_name,
            const std::function<void()>& on_folder_locked = {});
  ~RunOutput();
  RunOutput(RunOutput&&) noexcept;
  RunOutput& operator=(RunOutput&&) noexcept;

  // Registers observers on the simulation: history rows every
  // max(1, round(history_interval_s / dt)) steps, frames every
  // max(1, round(frame_interval_s / dt)) steps, both at the start and at the
  // last state of the run. Opens history.csv and events.csv. Call once.
  //
  // A RunOutput made by resume() instead cuts history.csv and events.csv
  // back to their length at the checkpoint and appends to them, deletes
  // frames written after the checkpoint and summary.json, and rewrites
  // case.pvd with the frames up to the checkpoint. `initial_position_m`
  // (used only then) are the bodies' positions at t = 0, the reference of
  // max_displacement_m (default: the current positions).
  void attach(Simulation& sim, const std::vector<Vec3>* initial_position_m = nullptr);

  // Checkpoints (io/checkpoint.h): writes the events not yet written,
  // flushes history.csv and events.csv, and saves what the folder holds:
  // the frames listed in case.pvd, the files' byte lengths and row counts.
  void save_state(const Simulation& sim, StateWriter& out);
  // An output continuing a run from its checkpoint in `def.folder`. Reads
  // the "output" section of `in` and checks that history.csv, events.csv
  // and the listed frames are still there; touches nothing (attach() does).
  // Throws CheckpointError (io/checkpoint.h) naming what is wrong.
  static RunOutput resume(const OutputDef& def, std::string case_name, StateReader& in);

  void add_cell_block(std::string name, VtkCellBlock block);
  void add_history_column(std::string header, HistoryColumn value);
  // The joints' node ids and names by joint id, for events.csv's node and
  // joint_name columns (before attach(); without it they stay empty).
  void set_joint_names(std::vector<std::string> nodes, std::vector<std::string> names);
  // Extra summary field; `json_value` is an already formatted JSON value
  // (checked). Keys must not repeat built-in ones; a repeated extra key
  // replaces the earlier value.
  void add_summary_field(std::string key, std::string json_value);

  // Writes the events not yet written, closes history.csv and events.csv and
  // writes summary.json. Call once after run(), also after an unstable or
  // stopped run (the frames and rows up to the last good state are kept).
  // A file that fails to flush or close throws OutputError naming it, with
  // summary.json (where the disk takes it) saying "output_failed".
  void finish(const Simulation& sim, const RunResult& result);
  // Instead of finish() when writing failed during the run (an OutputError
  // from a frame, a history row or a checkpoint: a full disk, a folder made
  // read-only): cuts history.csv and events.csv back to their last complete
  // rows, keeps case.pvd (it lists only frames on disk) and tries to write
  // summary.json with status "output_failed", `why`, and the step and time
  // reached, so that nothing in the folder claims a completed run. Best
  // effort on a disk that may refuse everything; never throws. Returns true
  // when summary.json was written.
  bool abandon(const Simulation& sim, const std::string& why) noexcept;

  const std::filesystem::path& folder() const;
  // Not empty when the folder's file system has no locks and the run goes
  // on unprotected against a second process (io/folder_lock.h): a warning
  // for the run to give.
  const std::string& folder_lock_warning() const;
  std::int64_t frame_every_steps() const;    // 0 before attach()
  std::int64_t history_every_steps() const;  // 0 before attach()
  std::size_t frames_written() const;
  std::int64_t history_rows() const;
  // History rows this process wrote (a resumed run: since the checkpoint)
  // and their mean length (bytes).
  std::int64_t history_rows_this_process() const;
  double history_mean_row_bytes() const;
  // An upper bound on the size of the latest frame this process wrote and of
  // later frames with as many cells (VtkFrameWriter::last_frame_bound_bytes);
  // 0 before this process has written a frame.
  double frame_bytes_bound() const;

 private:
  struct Impl;
  explicit RunOutput(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace fq
