#include "io/run_output.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

#include "io/atomic_file.h"
#include "dem_core/lane_isa.h"
#include "dem_core/state_io.h"
#include "io/checkpoint.h"
#include "io/folder_lock.h"
#include "event_csv_writer.h"
#include "fq_config.h"
#include "io/json_writer.h"
#include "pvd_collection.h"

namespace fq {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPvdName = "case.pvd";
constexpr const char* kSummaryName = "summary.json";
constexpr const char* kHistoryName = "history.csv";
constexpr const char* kEventsName = "events.csv";
constexpr const char* kFramesDir = "frames";

// Top-level keys summary.json writes itself; extra fields may not reuse them.
constexpr const char* kBuiltinSummaryKeys[] = {
    "program",          "program_version", "case",           "status",           "message",
    "steps",            "dt_s",            "duration_s",     "simulated_time_s", "wall_time_s",
    "steps_per_second", "body_count",      "energy",         "event_counts",     "stage_seconds",
    "provider_seconds", "frames_written",  "history_rows",   "event_rows",       "output",
    "simd_form"};

bool is_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// frame_NNNNNN.vtu (6 or more digits) or its temporary .frame_NNNNNN.vtu.tmp.
bool is_frame_file_name(std::string_view name) {
  if (name.starts_with(".") && name.ends_with(".tmp")) name = name.substr(1, name.size() - 5);
  if (!name.starts_with("frame_") || !name.ends_with(".vtu")) return false;
  const std::string_view digits = name.substr(6, name.size() - 10);
  return digits.size() >= 6 && is_digits(digits);
}

std::string frame_file_name(std::size_t index) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%06zu.vtu", index);
  return buf;
}

void remove_file_if_present(const fs::path& p) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(p, ec))) return;
  if (!fs::remove(p, ec) && ec)
    throw std::runtime_error("cannot remove old output file '" + p.string() + "': " + ec.message());
}

}  // namespace

namespace {
// The first 4 KiB of `file` ("" when it cannot be read).
std::string file_head(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return "";  // a pipe would block the open
  std::ifstream in(file, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(std::size_t(std::max<std::streamsize>(0, in.gcount())));
  return head;
}

// A run of ours, by its files' content and not their names alone (a user's
// own summary.json once let a run replace the history.csv beside it): a
// summary.json written by framequake, or a case.pvd collection whose
// frames (if any yet) are ours.
bool holds_framequake_run(const fs::path& folder) {
  if (file_head(folder / kSummaryName).find("\"program\": \"framequake\"") != std::string::npos) return true;
  const std::string pvd = file_head(folder / kPvdName);
  if (pvd.find("<VTKFile type=\"Collection\"") == std::string::npos) return false;
  const std::size_t file_attr = pvd.find("file=\"");
  constexpr std::string_view ours = "file=\"frames/frame_";
  return file_attr == std::string::npos || pvd.compare(file_attr, ours.size(), ours) == 0;
}
}  // namespace

fs::path summary_path(const fs::path& folder) { return folder / kSummaryName; }
fs::path history_path(const fs::path& folder) { return folder / kHistoryName; }
fs::path frame_path(const fs::path& folder, std::size_t index) { return folder / kFramesDir / frame_file_name(index); }

bool check_output_folder(const fs::path& folder) {
  // A file system limits each name in a path to 255 bytes (NAME_MAX); a
  // longer one failed later with the library's bare "File name too long".
  for (const fs::path& part : folder)
    if (part.native().size() > 255)
      throw std::runtime_error("output folder '" + folder.string() + "': its part '" + part.native().substr(0, 40) +
                               "...' is " + std::to_string(part.native().size()) +
                               " bytes long, more than the 255 a file name may have; choose a shorter folder (or "
                               "case or record name)");
  std::error_code ec;
  const fs::file_status st = fs::status(folder, ec);
  if (!fs::exists(st)) {
    // A symbolic link whose target is missing: creating the folder would
    // fail with a bare "File exists" (CLI probe).
    if (fs::is_symlink(fs::symlink_status(folder, ec)))
      throw std::runtime_error("output folder '" + folder.string() + "' is a symbolic link to '" +
                               fs::read_symlink(folder, ec).string() + "', which does not exist");
    return false;
  }
  if (!fs::is_directory(st))
    throw std::runtime_error("output folder '" + folder.string() + "' exists and is not a folder");
  // Empty, or holding only an empty frames/ (a run stopped between making
  // the folders and writing case.pvd): nothing to protect.
  bool empty = true;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
    const bool empty_frames_dir = e.path().filename() == kFramesDir && e.is_directory() && fs::is_empty(e.path());
    if (!empty_frames_dir) empty = false;
  }
  if (ec) throw std::runtime_error("cannot read output folder '" + folder.string() + "': " + ec.message());
  if (empty) return false;
  if (!holds_framequake_run(folder))
    throw std::runtime_error("output folder '" + folder.string() +
                             "' is not empty and holds no previous framequake run (no case.pvd or "
                             "summary.json written by framequake); refusing to write into it: choose another folder "
                             "or empty it");
  return true;
}

namespace {

// See the constructor's contract in run_output.h. Only files this class
// writes are ever removed.
void prepare_folder(const fs::path& folder) {
  std::error_code ec;
  if (check_output_folder(folder)) {
    for (const char* name : {kPvdName, kSummaryName, kHistoryName, kEventsName, kCheckpointFileName}) {
      remove_file_if_present(folder / name);
      remove_file_if_present(detail::temporary_path_for(folder / name));
    }
    const fs::path frames = folder / kFramesDir;
    if (fs::is_directory(fs::symlink_status(frames, ec))) {
      std::vector<fs::path> old;
      for (const fs::directory_entry& e : fs::directory_iterator(frames))
        if (is_frame_file_name(e.path().filename().string())) old.push_back(e.path());
      for (const fs::path& p : old) remove_file_if_present(p);
    }
  }
  fs::create_directories(folder / kFramesDir, ec);
  if (ec || !fs::is_directory(folder / kFramesDir))
    throw std::runtime_error("cannot create output folder '" + (folder / kFramesDir).string() + "': " + ec.message());
}

}  // namespace

std::int64_t steps_per_interval(double interval_s, double dt_s) {
  // An interval longer than any run (1e300 s, or 1e15 s at dt = 1e-5 s)
  // means the start and the end only; llround of a quotient past 2^63 is
  // undefined (it gave "every step": 20 001 frames for 1e300 s, CLI probe).
  const double steps = interval_s / dt_s;
  if (!(steps < double(kEveryStepCap))) return kEveryStepCap;
  return std::max<std::int64_t>(1, std::llround(steps));
}

std::int64_t samples_written(std::int64_t total_steps, std::int64_t every) {
  return total_steps / every + 1 + (total_steps % every != 0 ? 1 : 0);
}

std::string interval_rounding_note(const char* field, double interval_s, double dt_s) {
  const std::int64_t every = steps_per_interval(interval_s, dt_s);
  if (every == kEveryStepCap) return "";  // the start and the end only
  const double used_s = double(every) * dt_s;
  if (std::fabs(used_s - interval_s) <= 1e-9 * interval_s) return "";
  std::ostringstream note;
  note << std::setprecision(6) << field << " = " << interval_s << " s is "
       << (interval_s < dt_s ? "shorter than one time step" : "not a whole number of time steps") << " of " << dt_s
       << " s: written every " << every << (every == 1 ? " step" : " steps") << " (" << used_s << " s)";
  return note.str();
}

struct RunOutput::Impl {
  // Observers the simulation calls; they forward to Impl, whose address is
  // stable behind RunOutput's unique_ptr.
  // A write that fails in the step loop (std::runtime_error from a writer)
  // becomes an OutputError, which ends the run: the command line reports
  // it as an output failure (exit 3), not as an internal error.
  // One type for both: `frames` picks what it writes.
  struct WritingObserver final : StepObserver {
    WritingObserver(Impl* o, bool writes_frames) : owner(o), frames(writes_frames) {}
    void on_sample(const Simulation& sim) override {
      try {
        if (frames)
          owner->write_frame(sim);
        else
          owner->sample_history(sim);
      } catch (const OutputError&) {
        throw;
      } catch (const std::runtime_error& e) {
        throw OutputError(e.what());
      }
    }
    Impl* owner;
    bool frames;
  };

  Impl(const OutputDef& d, std::string name)
      : def(d), case_name(std::move(name)), pvd(def.folder / kPvdName) {}

  void sample_history(const Simulation& sim) {
    if (sim.steps_done() == last_history_step) return;  // this state is already in the file
    last_history_step = sim.steps_done();
    history.write_row(sim);
    events.write_new(sim.events());
  }

  void write_frame(const Simulation& sim) {
    if (sim.steps_done() == last_frame_step) return;
    last_frame_step = sim.steps_done();
    const std::string name = frame_file_name(pvd.size());
    frames.write(sim, def.folder / kFramesDir / name, def.vtk_binary);
    pvd.add(sim.time_s(), std::string(kFramesDir) + "/" + name);
    // Rows up to this frame's time are on disk as well.
    history.flush();
    events.write_new(sim.events());
    events.flush();
  }

  // `status_override`, when given, replaces the run status's name (abandon()).
  void write_summary(const Simulation& sim, const RunResult& result, const char* status_override = nullptr) const;

  FolderLock lock;  // first, so released last: held while this output exists (io/folder_lock.h)
  OutputDef def;
  std::string case_name;
  VtkFrameWriter frames;
  HistoryWriter history;
  detail::EventCsvWriter events;
  detail::PvdCollection pvd;
  std::vector<std::pair<std::string, std::string>> extra_fields;
  WritingObserver history_observer{this, false};
  WritingObserver frame_observer{this, true};
  std::int64_t frame_every = 0;
  std::int64_t history_every = 0;
  std::int64_t last_frame_step = -1;
  std::int64_t last_history_step = -1;
  bool attached = false;
  bool finished = false;
  // Set by resume(): where the folder stood at the checkpoint.
  struct Resume {
    std::string pvd_entries;
    std::uint64_t pvd_count = 0;
    std::uint64_t history_bytes = 0;
    std::int64_t history_rows = 0;
    std::uint64_t event_bytes = 0;
    std::uint64_t events_written = 0;
    std::int64_t event_rows = 0;
    std::int64_t frame_every = 0;
    std::int64_t history_every = 0;
  };
  std::optional<Resume> resume;
};

RunOutput::RunOutput(const OutputDef& def, std::string case_name, const std::function<void()>& on_folder_locked) {
  if (def.folder.empty()) throw std::invalid_argument("output folder path is empty");
  if (!(def.frame_interval_s > 0.0) || !std::isfinite(def.frame_interval_s))
    throw std::invalid_argument("frame_interval_s must be a positive number of seconds");
  if (!(def.history_interval_s > 0.0) || !std::isfinite(def.history_interval_s))
    throw std::invalid_argument("history_interval_s must be a positive number of seconds");
  // The folder, then its lock, then its contents: a second process waits
  // for nothing and changes nothing while the first holds it.
  std::error_code ec;
  (void)check_output_folder(def.folder);  // a file, or a broken link, in its place: refused with its reason
  if (!fs::exists(def.folder, ec)) {
    fs::create_directories(def.folder, ec);
    if (ec && !fs::is_directory(def.folder))
      throw std::runtime_error("cannot create output folder '" + def.folder.string() + "': " + ec.message());
  }
  if (!fs::is_directory(def.folder, ec))
    throw std::runtime_error("output folder '" + def.folder.string() + "' exists and is not a folder");
  FolderLock lock(def.folder);
  if (on_folder_locked) on_folder_locked();
  prepare_folder(def.folder);
  impl_ = std::make_unique<Impl>(def, std::move(case_name));
  impl_->lock = std::move(lock);
  // From now on the folder is recognisably a framequake run, and case.pvd
  // is valid at every instant.
  impl_->pvd.write();
}

RunOutput::RunOutput(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

RunOutput::~RunOutput() = default;
RunOutput::RunOutput(RunOutput&&) noexcept = default;
RunOutput& RunOutput::operator=(RunOutput&&) noexcept = default;

void RunOutput::attach(Simulation& sim, const std::vector<Vec3>* initial_position_m) {
  Impl& o = *impl_;
  if (o.attached) throw std::logic_error("RunOutput::attach called twice");
  const double dt = sim.settings().dt_s;
  o.history_every = steps_per_interval(o.def.history_interval_s, dt);
  o.frame_every = steps_per_interval(o.def.frame_interval_s, dt);
  {
    std::vector<std::string> names;
    for (const BodyInfo& info : sim.bodies().info) names.push_back(info.name);
    o.events.set_body_names(std::move(names));
  }
  if (o.resume) {
    const Impl::Resume& r = *o.resume;
    if (r.frame_every != o.frame_every || r.history_every != o.history_every)
      throw std::runtime_error("the output intervals differ from those of the checkpointed run");
    // Frames written after the checkpoint go: the resumed run writes them again.
    const fs::path frames = o.def.folder / kFramesDir;
    std::error_code ec;
    std::vector<fs::path> later;
    for (const fs::directory_entry& e : fs::directory_iterator(frames, ec)) {
      const std::string name = e.path().filename().string();
      if (!is_frame_file_name(name)) continue;
      if (name.starts_with(".") || std::stoull(name.substr(6, name.size() - 10)) >= r.pvd_count) later.push_back(e.path());
    }
    if (ec) throw std::runtime_error("cannot read '" + frames.string() + "': " + ec.message());
    for (const fs::path& p : later) remove_file_if_present(p);
    remove_file_if_present(o.def.folder / kSummaryName);
    o.pvd.restore(r.pvd_entries, std::size_t(r.pvd_count));
    o.pvd.write();
    o.history.reopen(o.def.folder / kHistoryName, initial_position_m ? *initial_position_m : sim.bodies().position_m,
                     r.history_bytes, r.history_rows);
    o.events.reopen(o.def.folder / kEventsName, r.event_bytes, std::size_t(r.events_written), r.event_rows);
    // The checkpoint was written after the samples of its step.
    o.last_history_step = sim.steps_done();
    o.last_frame_step = sim.steps_done();
  } else {
    o.history.open(o.def.folder / kHistoryName, sim);
    o.events.open(o.def.folder / kEventsName);
  }
  // History first: at a step where both are due the row is written before
  // the frame flushes the file.
  sim.add_observer(&o.history_observer, o.history_every);
  sim.add_observer(&o.frame_observer, o.frame_every);
  o.attached = true;
}

void RunOutput::save_state(const Simulation& sim, StateWriter& out) {
  Impl& o = *impl_;
  if (!o.attached) throw std::logic_error("RunOutput::save_state before attach");
  o.history.flush();
  o.events.write_new(sim.events());
  o.events.flush();
  out.section("output");
  out.str(o.pvd.entries());
  out.u64(o.pvd.size());
  out.u64(o.history.bytes_written());
  out.i64(o.history.rows());
  out.u64(o.events.bytes_written());
  out.u64(o.events.written());
  out.i64(o.events.rows());
  out.i64(o.frame_every);
  out.i64(o.history_every);
}

RunOutput RunOutput::resume(const OutputDef& def, std::string case_name, StateReader& in) {
  FolderLock lock(def.folder);  // before anything of the folder is read or cut
  auto impl = std::make_unique<Impl>(def, std::move(case_name));
  impl->lock = std::move(lock);
  Impl::Resume r;
  in.section("output");
  r.pvd_entries = in.str("case.pvd entries");
  r.pvd_count = in.u64("frame count");
  r.history_bytes = in.u64("history.csv length");
  r.history_rows = in.i64("history.csv rows");
  r.event_bytes = in.u64("events.csv length");
  r.events_written = in.u64("events written");
  r.event_rows = in.i64("events.csv rows");
  r.frame_every = in.i64("frame interval");
  r.history_every = in.i64("history interval");
  // The folder must still hold what the checkpoint describes.
  std::error_code ec;
  for (const auto& [name, bytes] : {std::pair{kHistoryName, r.history_bytes}, std::pair{kEventsName, r.event_bytes}}) {
    const fs::path p = def.folder / name;
    const std::uintmax_t size = fs::file_size(p, ec);
    if (ec || size < bytes)
      throw CheckpointError("'" + p.string() + "' is missing or shorter than when the checkpoint was written (" +
                            std::to_string(bytes) + " bytes); the output folder was changed since, cannot resume");
  }
  for (std::uint64_t k = 0; k < r.pvd_count; ++k) {
    const fs::path p = def.folder / kFramesDir / frame_file_name(std::size_t(k));
    if (!fs::is_regular_file(p, ec))
      throw CheckpointError("frame '" + p.string() + "', listed at the checkpoint, is missing; cannot resume");
  }
  impl->resume = std::move(r);
  return RunOutput(std::move(impl));
}

void RunOutput::add_cell_block(std::string name, VtkCellBlock block) {
  impl_->frames.add_cell_block(std::move(name), std::move(block));
}

void RunOutput::set_joint_names(std::vector<std::string> nodes, std::vector<std::string> names) {
  impl_->events.set_joint_names(std::move(nodes), std::move(names));
}

void RunOutput::add_history_column(std::string header, HistoryColumn value) {
  impl_->history.add_column(std::move(header), std::move(value));
}

void RunOutput::add_summary_field(std::string key, std::string json_value) {
  for (const char* k : kBuiltinSummaryKeys)
    if (key == k) throw std::invalid_argument("summary field '" + key + "' is written by RunOutput itself");
  if (!json_is_valid(json_value))
    throw std::invalid_argument("summary field '" + key + "': not a valid JSON value: " + json_value.substr(0, 80));
  for (auto& [k, v] : impl_->extra_fields) {
    if (k == key) {
      v = std::move(json_value);
      return;
    }
  }
  impl_->extra_fields.emplace_back(std::move(key), std::move(json_value));
}

void RunOutput::finish(const Simulation& sim, const RunResult& result) {
  Impl& o = *impl_;
  if (o.finished) throw std::logic_error("RunOutput::finish called twice");
  o.finished = true;
  // An unstable run ends without a final sample: its Instability event is
  // only in the log. Both files are closed whatever the other's fate.
  std::string failure;
  try {
    o.events.write_new(sim.events());
    o.events.close();
  } catch (const std::runtime_error& e) {
    failure = e.what();
  }
  try {
    o.history.close();
  } catch (const std::runtime_error& e) {
    if (failure.empty()) failure = e.what();
  }
  if (!failure.empty()) {
    // As abandon(): whole rows only where a flush failed, and a summary
    // that does not claim the run's output complete.
    o.history.abandon();
    o.events.abandon();
    RunResult reached = result;
    reached.message = "the output could not be written: " + failure;
    bool summary_written = true;
    try {
      o.write_summary(sim, reached, "output_failed");
    } catch (const std::exception&) {
      summary_written = false;
    }
    throw OutputError(failure + (summary_written ? " (summary.json says output_failed)"
                                                 : "; summary.json could not be written either"));
  }
  o.write_summary(sim, result);
}

bool RunOutput::abandon(const Simulation& sim, const std::string& why) noexcept {
  Impl& o = *impl_;
  if (o.finished) return false;
  o.finished = true;
  o.history.abandon();
  o.events.abandon();
  try {
    RunResult reached;
    reached.status = RunStatus::Stopped;
    reached.steps = sim.steps_done();
    reached.steps_this_call = sim.steps_this_run();
    reached.simulated_s = sim.time_s();
    // The wall time the run had taken (it was written as 0, and
    // steps_per_second as null, after seconds of running; review probe).
    reached.wall_s = sim.wall_seconds();
    reached.message = "the output could not be written: " + why;
    o.write_summary(sim, reached, "output_failed");
    return true;
  } catch (...) {
    // The disk refuses the summary too: the folder then has no summary.json,
    // which no reader takes for a completed run.
    return false;
  }
}

void RunOutput::Impl::write_summary(const Simulation& sim, const RunResult& result, const char* status_override) const {
  JsonWriter w;
  w.begin_object();
  w.key("program").value("framequake");
  w.key("program_version").value(FQ_VERSION_STRING);
  w.key("case").value(case_name);
  w.key("status").value(status_override ? status_override : run_status_name(result.status));
  w.key("message").value(result.message);
  w.key("steps").value(result.steps);
  w.key("dt_s").value(sim.settings().dt_s);
  w.key("duration_s").value(sim.settings().duration_s);
  w.key("simulated_time_s").value(result.simulated_s);
  w.key("wall_time_s").value(result.wall_s);
  // Non-finite (null) when the run was too short for the clock to see. The
  // steps this process took over its own wall time: a resumed run counts
  // from its checkpoint.
  w.key("steps_per_second").value(result.wall_s > 0.0 ? double(result.steps_this_call) / result.wall_s : HUGE_VAL);
  w.key("body_count").value(sim.bodies().size());
  // Which SIMD form of the lane kernels ran (dem_core/lane_isa.h): the
  // results are the same in every form, the wall time is not.
  w.key("simd_form").value(lane_isa_name(active_lane_isa()));

  const EnergyLedger& e = sim.ledger();
  w.key("energy").begin_object();
  w.key("kinetic_J").value(e.kinetic_J);
  w.key("kinetic_rotational_J").value(e.kinetic_rotational_J);
  w.key("gravity_potential_J").value(e.gravity_potential_J);
  w.key("elastic_J").value(e.elastic_J);
  w.key("dissipated_viscous_J").value(e.dissipated_viscous_J);
  w.key("dissipated_plastic_J").value(e.dissipated_plastic_J);
  w.key("dissipated_friction_J").value(e.dissipated_friction_J);
  w.key("work_ground_motion_J").value(e.work_ground_motion_J);
  w.key("work_external_J").value(e.work_external_J);
  w.key("initial_stored_J").value(e.initial_stored_J);
  w.key("scale_J").value(e.scale_J);
  w.key("stored_J").value(e.stored_J());
  w.key("dissipated_J").value(e.dissipated_J());
  w.key("input_J").value(e.input_J());
  w.key("balance_error_J").value(e.balance_error_J());
  w.key("balance_error_relative").value(e.balance_error_relative());
  w.end_object();

  // Every kind the engine knows, zero counts included. EventKind has a fixed
  // uint8 underlying type, so scanning its range picks up kinds added later.
  w.key("event_counts").begin_object();
  for (int k = 0; k < 256; ++k) {
    const auto kind = static_cast<EventKind>(k);
    const std::string name = event_kind_name(kind);
    if (name == "unknown") continue;
    w.key(name).value(sim.events().count(kind));
  }
  w.end_object();

  // Estimated from one step in settings.profile_every_steps (simulation.h).
  const StageProfile& p = sim.profile();
  w.key("stage_seconds").begin_object();
  for (int s = 0; s < static_cast<int>(Stage::Count); ++s) w.key(stage_name(static_cast<Stage>(s))).value(p.seconds[s]);
  w.end_object();
  // Keyed by provider name; a repeated name gets "#2", "#3", ...
  w.key("provider_seconds").begin_object();
  std::vector<std::string> used;
  for (std::size_t i = 0; i < sim.providers().size() && i < p.provider_seconds.size(); ++i) {
    std::string name = sim.providers()[i]->name();
    const std::string base = name;
    for (int n = 2; std::find(used.begin(), used.end(), name) != used.end(); ++n) name = base + "#" + std::to_string(n);
    used.push_back(name);
    w.key(name).value(p.provider_seconds[i]);
  }
  w.end_object();

  w.key("frames_written").value(pvd.size());
  w.key("history_rows").value(history.rows());
  w.key("event_rows").value(events.rows());
  w.key("output").begin_object();
  // The intervals used (whole steps), and those the case asked for.
  w.key("frame_interval_s").value(double(frame_every) * sim.settings().dt_s);
  w.key("frame_interval_requested_s").value(def.frame_interval_s);
  w.key("frame_every_steps").value(frame_every);
  w.key("history_interval_s").value(double(history_every) * sim.settings().dt_s);
  w.key("history_interval_requested_s").value(def.history_interval_s);
  w.key("history_every_steps").value(history_every);
  w.key("vtk_binary").value(def.vtk_binary);
  w.end_object();

  for (const auto& [key, json] : extra_fields) w.key(key).raw(json);
  w.end_object();
  std::string doc = w.str();
  doc.push_back('\n');
  detail::write_file_atomically(def.folder / kSummaryName, doc);
}

const fs::path& RunOutput::folder() const { return impl_->def.folder; }
const std::string& RunOutput::folder_lock_warning() const { return impl_->lock.warning(); }
std::int64_t RunOutput::frame_every_steps() const { return impl_->frame_every; }
std::int64_t RunOutput::history_every_steps() const { return impl_->history_every; }
std::size_t RunOutput::frames_written() const { return impl_->pvd.size(); }
std::int64_t RunOutput::history_rows() const { return impl_->history.rows(); }
std::int64_t RunOutput::history_rows_this_process() const { return impl_->history.rows_this_process(); }
double RunOutput::history_mean_row_bytes() const { return impl_->history.mean_row_bytes(); }
double RunOutput::frame_bytes_bound() const { return double(impl_->frames.last_frame_bound_bytes()); }

}  // namespace fq
