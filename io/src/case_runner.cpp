#include "io/case_runner.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "dem_core/state_io.h"
#include "io/checkpoint.h"
#include "io/input_error.h"
#include "io/joint_builder.h"
#include "io/json_writer.h"
#include "io/model.h"
#include "io/point_grid.h"
#include "io/run_output.h"
#include "io/utf8_text.h"
#include "scene_output.h"

namespace fq {

namespace {

// A stable limit as users read it and copy it into dt_s: six significant
// digits rounded down, so that the printed value itself is accepted (the
// default rounding printed 0.000123704 for 1.237035e-4, which run refused).
std::string limit_text(double dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) {
    std::ostringstream o;
    o << dt_s;
    return o.str();
  }
  const double unit = std::pow(10.0, std::floor(std::log10(dt_s)) - 5.0);
  double shown = std::floor(dt_s / unit) * unit;
  std::ostringstream o;
  o << std::setprecision(6) << shown;
  // The printed decimal must not read back above the limit.
  while (std::stod(o.str()) > dt_s) {
    shown -= unit;
    o.str("");
    o << std::setprecision(6) << shown;
  }
  return o.str();
}

int line_of(const CaseDef& def, const std::string& key) {
  auto it = def.section_line.find(key);
  return it == def.section_line.end() ? 0 : it->second;
}

// The reach of RK4's stability region along the negative real axis: the
// root x > 0 of 1 - x + x^2/2 - x^3/6 + x^4/24 = 1 (its amplification on a
// decay of rate r at step dt, x = r dt), found by bisection.
constexpr double kRk4RealAxisReach = 2.785293563405282;

// joint_names: per joint id, its name as events.csv and `info --joints` give
// it ("node:member_a-member_b"), added to a joint's description: ids change
// from case to case, names do not (stable-step probe).
StableTimeStep estimate_stable_time_step(const Simulation& sim, const std::vector<std::string>& joint_names) {
  // One network of every provider's spring-dashpots acting now (joints and
  // the contacts present at the start: a column held by its support joint
  // and standing on the ground gets both stiffnesses), and each provider's
  // springs that may form later; the stiffest of these sets the limit
  // (dem_core/linearised_network.h). Checked against bisected runs in
  // tests/io/test_scene_stable_step.cpp (joint and contact on one body),
  // tests/contacts/test_contact_stable_step.cpp and
  // tests/joints/test_stable_time_step.cpp.
  StableTimeStep s;
  const BodyStore& bodies = sim.bodies();
  std::vector<LinearisedSpring> rows;
  std::vector<std::size_t> owner_end;  // rows of provider p end at owner_end[p]
  for (const auto& p : sim.providers()) {
    p->linearised_springs(bodies, rows);
    owner_end.push_back(rows.size());
  }
  // The provider that contributed row k.
  auto provider_of = [&](std::size_t k) -> const ForceProvider& {
    return *sim.providers()[std::size_t(std::upper_bound(owner_end.begin(), owner_end.end(), k) - owner_end.begin())];
  };
  double omega_max = 0.0;
  const NetworkStableStep net = network_stable_step(rows, bodies.size());
  // A frequency that is not a finite number (a mass or an inertia of 1e-300,
  // a stiffness of 1e300) makes every comparison with dt false: kept as
  // NaN, so that check_run_start refuses the run instead of letting it pass.
  bool not_finite = !std::isfinite(net.omega_radps);
  if (net.omega_radps > 0.0) {
    omega_max = net.omega_radps;
    const ForceProvider& p = provider_of(net.stiffest);
    s.stiffest_element = p.describe_linearised_spring(bodies, rows[net.stiffest].element);
    const auto element = std::size_t(rows[net.stiffest].element);
    if (std::string_view(p.name()) == "joints" && element < joint_names.size())
      s.stiffest_element += ", named '" + joint_names[element] + "'";
  }
  for (std::size_t k = 0; k < sim.providers().size(); ++k) {
    // A provider without linearised terms (none acting now, or one that
    // only knows its stiffest mode) is asked for that mode whole.
    const ForceProvider& p = *sim.providers()[k];
    const bool has_rows = owner_end[k] > (k == 0 ? 0 : owner_end[k - 1]);
    const StiffestMode mode = has_rows ? p.later_stiffest_mode(bodies) : p.stiffest_mode(bodies);
    not_finite = not_finite || !std::isfinite(mode.omega_radps);
    if (mode.omega_radps > omega_max) {
      omega_max = mode.omega_radps;
      s.stiffest_element = mode.where;
    }
  }
  s.omega_max_radps = not_finite ? std::numeric_limits<double>::quiet_NaN() : omega_max;
  const double factor = integrator_stability_factor(sim.settings().integrator);
  if (not_finite)
    s.dt_crit_s = std::numeric_limits<double>::quiet_NaN();
  else if (omega_max > 0.0 && std::isfinite(factor))
    s.dt_crit_s = factor / omega_max;
  if (sim.settings().integrator == Integrator::RungeKutta4 && std::isfinite(s.dt_crit_s)) {
    // RK4's factor, 2 sqrt 2 times the damped leapfrog network's frequency,
    // holds for light damping, but a heavily overdamped mode decays at a
    // rate up to lambda_max(C~) (a real root s of s^2 + s c + k = 0 in the
    // mode's Rayleigh quotients has |s| <= c), and RK4 is stable on a real
    // decay only while rate x dt <= 2.7853 (its polynomial's reach on the
    // negative real axis). Past a damping ratio of about 5.5 that is the
    // lower limit: at 20 the factor's limit was 1.4 % above the bisected one
    // and a run at it blew up (integrator probe). lambda_max(C~) is the
    // network's top eigenvalue with each dashpot put in the place of a
    // stiffness (its "frequency" squared).
    std::vector<LinearisedSpring> dashpots;
    std::vector<std::size_t> dashpot_row;  // the row of `rows` each came from
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (!(rows[k].c_Nspm > 0.0)) continue;
      dashpots.push_back(rows[k]);
      dashpots.back().k_Npm = rows[k].c_Nspm;
      dashpots.back().c_Nspm = 0.0;
      dashpot_row.push_back(k);
    }
    const NetworkStableStep decay = network_stable_step(dashpots, bodies.size());
    const double rate_per_s = decay.omega_radps * decay.omega_radps;
    if (rate_per_s > 0.0 && std::isfinite(rate_per_s) && kRk4RealAxisReach / rate_per_s < s.dt_crit_s) {
      s.dt_crit_s = kRk4RealAxisReach / rate_per_s;
      s.omega_max_radps = factor / s.dt_crit_s;  // the frequency that would set the same limit
      const std::size_t owner = decay.stiffest < dashpot_row.size() ? dashpot_row[decay.stiffest] : 0;
      std::ostringstream where;
      where << std::setprecision(4) << "the dashpots, most of all that of "
            << provider_of(owner).describe_linearised_spring(bodies, rows[owner].element)
            << " (an overdamped mode decaying at up to " << rate_per_s
            << " 1/s, on which rk4 is stable only while rate x dt_s <= " << kRk4RealAxisReach << ")";
      s.stiffest_element = where.str();
    }
  }
  return s;
}

// What a checkpoint needs besides the state to rebuild and continue a run
// (section "run" of io/checkpoint.h).
struct RunMeta {
  std::filesystem::path case_file;  // absolute
  std::vector<CaseFileFingerprint> files;  // the case file and its records, each with its fingerprint
  double checkpoint_every_s = 0.0;
  bool allow_unstable_time_step = false;
  std::string case_name;
};

void write_run_meta(StateWriter& out, const RunMeta& m, const Simulation& sim) {
  out.section("run");
  out.str(m.case_file.string());
  out.u64(m.files.size());
  for (const CaseFileFingerprint& f : m.files) {
    out.str(f.what);
    out.str(f.file.string());
    out.u64(f.hash);
  }
  out.f64(m.checkpoint_every_s);
  out.boolean(m.allow_unstable_time_step);
  out.str(m.case_name);
  out.i64(sim.steps_done());
  out.f64(sim.time_s());
}

RunMeta read_run_meta(StateReader& in) {
  RunMeta m;
  in.section("run");
  m.case_file = in.str("case file");
  const std::uint64_t n_files = in.u64("count of case files");
  // A case file and one record per component (at most three).
  if (n_files > 16) in.fail("implausible count of case files (" + std::to_string(n_files) + ")");
  for (std::uint64_t k = 0; k < n_files; ++k) {
    CaseFileFingerprint f;
    f.what = in.str("case file kind");
    f.file = in.str("case file path");
    f.hash = in.u64("case file fingerprint");
    m.files.push_back(std::move(f));
  }
  m.checkpoint_every_s = in.f64("checkpoint interval");
  m.allow_unstable_time_step = in.boolean("force flag");
  m.case_name = in.str("case name");
  (void)in.i64("step");
  (void)in.f64("time");
  if (!(m.checkpoint_every_s > 0.0)) in.fail("checkpoint interval is not positive");
  return m;
}

// Writes the checkpoint after the history and frame observers of the same
// step (it is registered after them), so the files it describes hold that
// step's rows and frame.
class CheckpointObserver final : public StepObserver {
 public:
  CheckpointObserver(std::filesystem::path file, RunMeta meta, RunOutput* output, const StoreyDriftMonitor* storeys)
      : file_(std::move(file)), meta_(std::move(meta)), output_(output), storeys_(storeys) {}
  void on_sample(const Simulation& sim) override {
    // Step 0 needs no checkpoint; a state already saved is not saved twice.
    if (sim.steps_done() == 0 || sim.steps_done() == last_step_) return;
    last_step_ = sim.steps_done();
    try {
      StateWriter w;
      write_run_meta(w, meta_, sim);
      output_->save_state(sim, w);
      storeys_->save_state(w);
      sim.save_state(w);
      write_checkpoint_file(file_, w.bytes());
    } catch (const std::exception& e) {
      throw OutputError(std::string("cannot write the checkpoint: ") + e.what());
    }
  }

 private:
  std::filesystem::path file_;
  RunMeta meta_;
  RunOutput* output_;
  const StoreyDriftMonitor* storeys_;
  std::int64_t last_step_ = -1;
};

// Keeps the storeys' peak drifts at every step (StoreyDriftRecord): taken
// only at history rows, a peak between two rows was missed, so a coarser
// history interval could turn a damaged storey into a standing one
// (geometry probe: 0.03407 rad, damaged, at 1 ms rows; 0.03324 rad,
// standing, at 50 ms rows, of one and the same run).
class StoreyPeakMonitor final : public StepObserver {
 public:
  explicit StoreyPeakMonitor(StoreyDriftMonitor* storeys) : storeys_(storeys) {}
  void on_sample(const Simulation& sim) override { storeys_->track(sim.bodies(), sim.time_s()); }

 private:
  StoreyDriftMonitor* storeys_;
};

// How much more a run will write, said once it has written a few history
// rows (OutputSizeCheck): an upper bound on the latest frame's size
// (RunOutput::frame_bytes_bound) times the frames to come, plus the rows to
// come at their mean length. A warning when that exceeds the space left on
// the output's disk (a run that fills it ends with an output error, exit 3);
// a note above kNoteOutputBytes. Frames grow as contacts appear, so it
// bounds the output of the cells the run has at that point. (A probe's duration_s of 1e5 s on the
// falling-block demo would have written some 67 GB without a word.)
constexpr double kNoteOutputBytes = 1e9;

// A note per joint type in use that is a link system without shear links:
// its stiffness against shear along t2 is 4 k_s sin^2(theta) = 0 (the seed's
// planar system, joints/joint_layout.h). A frame loaded in its plane never
// shears those joints that way; a load across the plane is resisted only
// as the links turn (a probe's column swung to 0.86 rad under 0.5 g).
std::vector<std::string> planar_link_system_notes(const CaseDef& def, const Scene& scene) {
  std::vector<std::string> notes;
  std::vector<std::string> seen;
  for (const std::string& name : scene.joint_types) {
    if (std::find(seen.begin(), seen.end(), name) != seen.end()) continue;
    seen.push_back(name);
    const int t = def.joint_type_index(name);
    if (t < 0) continue;
    const JointTypeDef& type = def.joint_types[std::size_t(t)];
    if (type.layout != JointLayoutKind::LinkSystem || type.with_shear_links) continue;
    notes.push_back("joint type '" + name +
                    "' is a link_system without shear_link, the seed's planar system: it has no stiffness against "
                    "shear along its t2 axis (the joined member's depth direction), so a load across the frame's "
                    "plane is resisted only as its links turn; give it a shear_link spring if the frame is "
                    "loaded out of its plane");
  }
  return notes;
}

// A note when the run goes on after its ground motion has ended (a
// duration_s longer than the record's window): from then on the ground is
// still and the frame vibrates freely. "" otherwise.
std::string ground_motion_end_note(const Simulation& sim) {
  const GroundMotion& gm = sim.ground_motion();
  if (gm.empty()) return "";
  const double end_s = gm.end_time_s(), run_s = sim.settings().duration_s;
  if (!(run_s > end_s + sim.settings().dt_s)) return "";
  std::ostringstream note;
  note << std::setprecision(6) << "the ground motion ends at t = " << end_s << " s; from there to the run's end at "
       << run_s << " s the ground is still (free vibration)";
  return note.str();
}

// A record whose file's times do not start at 0 is shifted so that record
// time 0 is its first sample, and window_start_s counts from there: said,
// with the file time the window starts at (a probe's window_start_s of 10 s
// on a file starting at 5 s played file time 15 s, and nothing said so).
std::string record_time_shift_text(const GroundMotionComponent& c) {
  if (c.record.file_start_time_s == 0.0) return "";
  std::ostringstream text;
  text << std::setprecision(10) << "the times in " << c.record.source << " start at " << c.record.file_start_time_s
       << " s; record time counts from that first sample, so window_start_s = " << c.window_start_s
       << " s is t = " << c.record.file_start_time_s + c.window_start_s << " s in the file";
  return text.str();
}

std::vector<std::string> record_time_shift_notes(const Simulation& sim) {
  std::vector<std::string> notes;
  for (const GroundMotionComponent& c : sim.ground_motion().components())
    if (std::string note = record_time_shift_text(c); !note.empty()) notes.push_back(std::move(note));
  return notes;
}

class OutputSizeCheck final : public StepObserver {
 public:
  using Say = std::function<void(const std::string&)>;
  OutputSizeCheck(const RunOutput* writer, std::int64_t total_steps, Say note, Say warn)
      : writer_(writer), total_steps_(total_steps), note_(std::move(note)), warn_(std::move(warn)) {}
  // Called at every history row: once this process has written
  // kRowsMeasured rows and a frame, a row's size is their mean length and a
  // frame's the bound on the latest frame's size. (Its file's size was 4.5-5
  // times too small when that was frame 0, all of whose velocities and forces
  // are zero: 2.28 GB announced for 10.7 GB; scale probe.) (The size of history.csv over its rows, at
  // the first row, counted the header in, 67 % too much for a probe's run,
  // and a resumed run's rows before the checkpoint: 18 GB announced for a
  // 16 MB run. The first row alone, mostly zeros, is short.)
  static constexpr std::int64_t kRowsMeasured = 10;
  void on_sample(const Simulation&) override {
    const double frame_bytes = writer_->frame_bytes_bound();
    if (done_ || writer_->history_rows_this_process() < kRowsMeasured || frame_bytes <= 0.0) return;
    done_ = true;
    namespace fs = std::filesystem;
    std::error_code ec;
    const double history_bytes = writer_->history_mean_row_bytes();
    // What is still to come: a resumed run has written part of it.
    const double frames = double(std::max<std::int64_t>(
        0, samples_written(total_steps_, writer_->frame_every_steps()) - std::int64_t(writer_->frames_written())));
    const double rows = double(std::max<std::int64_t>(
        0, samples_written(total_steps_, writer_->history_every_steps()) - writer_->history_rows()));
    const double estimate = frames * frame_bytes + rows * history_bytes;
    const fs::space_info space = fs::space(writer_->folder(), ec);
    auto amount = [](double bytes) {
      std::ostringstream a;
      a << std::setprecision(3) << (bytes >= 1e9 ? bytes / 1e9 : bytes / 1e6) << (bytes >= 1e9 ? " GB" : " MB");
      return a.str();
    };
    std::ostringstream what;
    what << std::setprecision(3) << "up to about " << amount(estimate) << " more output (" << std::llround(frames)
         << " frames of up to about " << frame_bytes / 1e3 << " kB, their uncompressed size, " << std::llround(rows)
         << " history rows; more if contacts multiply)";
    if (!ec && estimate > double(space.available)) {
      std::ostringstream w;
      w << std::setprecision(3) << "this run will write " << what.str() << " into " << writer_->folder().string()
        << ", whose disk has " << amount(double(space.available))
        << " free: it may end with an output error when the disk is full; raise output.frame_interval_s or "
           "history_interval_s, or free space";
      if (warn_) warn_(w.str());
    } else if (estimate > kNoteOutputBytes && note_) {
      note_("this run will write " + what.str());
    }
  }

 private:
  const RunOutput* writer_;
  std::int64_t total_steps_;
  Say note_, warn_;
  bool done_ = false;
};

// The joints' and contacts' cell blocks and history columns. The blocks
// keep their numbers in every scene (cell_block 0 bodies, 1 springs, 2
// contacts; docs/paraview.md): a scene with contacts but no joints gets an
// empty springs block, so a ParaView threshold on 2 finds its contacts.
void attach_provider_output(RunOutput& writer, const Scene& scene) {
  if (scene.joints)
    attach_joint_output(writer, *scene.joints, scene.joint_nodes, scene.joint_names);
  else if (scene.contacts)
    writer.add_cell_block("springs", [](const Simulation&, VtkFrameBuilder&) {});
  if (scene.contacts) attach_contact_output(writer, *scene.contacts);
  if (scene.joints || scene.contacts) attach_base_force_output(writer, scene.joints, scene.contacts);
}

// A note when --checkpoint-every asks for more than kManyCheckpoints
// checkpoints: each writes the whole state to a new file and renames it,
// so a checkpoint every step turned a run of 0.15 s into one of 36 s
// (failure-mode probe). The state's size is measured by writing it once.
constexpr std::int64_t kManyCheckpoints = 1000;
std::string checkpoint_count_note(double every_s, const Simulation& sim) {
  const std::int64_t every = steps_per_interval(every_s, sim.settings().dt_s);
  const std::int64_t count = sim.total_steps() / std::max<std::int64_t>(1, every);
  if (count <= kManyCheckpoints) return "";
  StateWriter w;
  sim.save_state(w);
  std::ostringstream note;
  note << std::setprecision(3) << "--checkpoint-every " << every_s << " s writes " << count << " checkpoints (one every "
       << every << (every == 1 ? " step" : " steps") << "), each the whole state, at least "
       << double(w.bytes().size()) / 1024.0
       << " KiB (bodies, joints, contacts; the list of frames written and the storeys' drift books add to it): "
          "writing them may take longer than the run; an interval of a few minutes of wall time is enough to lose "
          "little to a crash";
  return note.str();
}

// A note when an output interval is not shorter than the run: the file
// then holds the start and the end only, which a user who asked for a
// history is better told before the run than after it (closed-form probe:
// history_interval_s 2 s on a 1 s run, accepted without a word).
std::string interval_beyond_run_note(const char* field, double interval_s, const Simulation& sim, const char* what) {
  const std::int64_t steps = sim.total_steps();
  const std::int64_t every = steps_per_interval(interval_s, sim.settings().dt_s);
  if (steps <= 1 || every < steps) return "";
  // Worded on the interval used: a requested one shorter than the run can
  // round up to it (1.6e-5 s on a run of two 1e-5 s steps; review probe).
  std::ostringstream note;
  note << std::setprecision(6) << field << " = " << interval_s << " s";
  // (Only where rounding changed it: 30 x 1e-5 is 3.0000000000000003e-4, so
  // an interval typed as the run's own length would be "used as" itself.)
  if (std::abs(double(every) * sim.settings().dt_s - interval_s) > 1e-9 * interval_s)
    note << ", used as " << every << " steps (" << double(every) * sim.settings().dt_s << " s),";
  note << " is not shorter than the run (" << double(steps) * sim.settings().dt_s << " s): " << what
       << " at the start and the end only";
  return note.str();
}

// The ground motion a run applied, for summary.json: each component's
// record, direction and scales and the part of the record used, and the
// peaks the run felt (up to its end), so that a results folder can be
// checked against its input on its own (geometry probe: only info and
// sweep.csv said which record a run had felt). null without ground motion.
// The simulation time up to which a run felt its ground motion: its end, or
// where it was stopped or blew up (a stopped run reported the motion it had
// not yet felt; new-features probe).
double ground_motion_felt_until_s(const Simulation& sim) { return std::min(sim.settings().duration_s, sim.time_s()); }

std::string ground_motion_summary(const Simulation& sim) {
  const GroundMotion& gm = sim.ground_motion();
  if (gm.empty()) return "null";
  const double duration_s = ground_motion_felt_until_s(sim);
  JsonWriter w(0);
  w.begin_object().key("components").begin_array();
  for (const GroundMotionComponent& c : gm.components()) {
    // Record seconds the run applies: the window, cut by the record's end
    // and by the run's end (a 1 s run of a 142 s window applies 1 s of it;
    // output probe).
    const double used_s = std::max(
        0.0, std::min({c.window_length_s, c.record.duration_s() - c.window_start_s, duration_s / c.time_scale}));
    // The component's own peak over those seconds, |amplitude_scale a(t)|
    // at its samples and at the ends of the span: which component is the
    // strongest, which the summed peaks per world axis cannot tell when
    // components are oblique.
    double peak_mps2 =
        std::max(std::abs(c.record.at(c.window_start_s)), std::abs(c.record.at(c.window_start_s + used_s)));
    for (std::size_t k = 0; k < c.record.acceleration_mps2.size(); ++k) {
      const double t_rec = c.record.time_of(k);
      if (t_rec > c.window_start_s + used_s) break;  // sample times increase
      if (t_rec >= c.window_start_s) peak_mps2 = std::max(peak_mps2, std::abs(c.record.acceleration_mps2[k]));
    }
    peak_mps2 *= std::abs(c.amplitude_scale);
    std::error_code ec;
    const std::filesystem::path record = c.record.source.empty()
                                             ? std::filesystem::path()
                                             : std::filesystem::absolute(c.record.source, ec).lexically_normal();
    w.begin_object()
        .key("record")
        .value(ec ? c.record.source : record.string())
        .key("direction")
        .begin_array()
        .value(c.direction.x() + 0.0)
        .value(c.direction.y() + 0.0)
        .value(c.direction.z() + 0.0)
        .end_array()
        .key("amplitude_scale")
        .value(c.amplitude_scale)
        .key("peak_mps2")
        .value(peak_mps2)
        .key("time_scale")
        .value(c.time_scale)
        .key("window_start_s")
        .value(c.window_start_s)
        .key("window_length_s")
        .value(used_s)
        .end_object();
  }
  const Vec3 peak = gm.peak_abs_mps2(duration_s);
  w.end_array()
      .key("end_time_s")
      .value(gm.end_time_s())
      .key("peak_horizontal_mps2")
      .value(gm.peak_horizontal_mps2(duration_s))
      .key("peak_abs_mps2")
      .begin_array()
      .value(peak.x())
      .value(peak.y())
      .value(peak.z())
      .end_array()
      .end_object();
  return w.str();
}

// The part of a run shared by run_case and resume_case: observers, the
// step loop and the summary.
CaseRunReport execute(Scene& scene, RunOutput& writer, const CaseRunOptions& options, const RunMeta* checkpoints,
                      const CaseDef& def, StoreyDriftMonitor& storeys) {
  Simulation& sim = *scene.simulation;
  StoreyPeakMonitor peaks(&storeys);
  if (!storeys.storeys().empty()) sim.add_step_monitor(&peaks);
  // Asked after every step, as a monitor (no energy gathering), so that it
  // redraws on wall time: asked every 1000 steps, it changed every 15-20 s
  // of wall time at 19k bodies (scale probe).
  if (options.progress) sim.add_step_monitor(options.progress);
  std::optional<CheckpointObserver> checkpoint;
  if (checkpoints) {
    checkpoint.emplace(writer.folder() / kCheckpointFileName, *checkpoints, &writer, &storeys);
    sim.add_observer(&*checkpoint,
                     steps_per_interval(checkpoints->checkpoint_every_s, sim.settings().dt_s));
  }
  {
    // The shortest text that reads back to the same double, as every number
    // of the summary (17 digits printed a last digit too many; review probe).
    writer.add_summary_field("stable_dt_s", JsonWriter::number(scene.stable_time_step.dt_crit_s));
    writer.add_summary_field("integrator", std::string("\"") + integrator_name(sim.settings().integrator) + "\"");
    if (def.contact)
      writer.add_summary_field("contact_intact_nodes",
                               std::string("\"") + intact_node_contact_name(def.contact->intact_nodes) + "\"");
  }

  CaseRunReport report;
  auto warn = [&](const std::string& text) {
    report.warnings.push_back(text);
    if (options.on_warning) options.on_warning(text);
  };
  // Registered after the output's observers, so it samples once the first
  // frame and row are written; with the largest interval, so that it is
  // asked at the start and the end only.
  OutputSizeCheck size_check(&writer, sim.total_steps(), options.on_note, warn);
  sim.add_observer(&size_check, std::max<std::int64_t>(1, writer.history_every_steps()));
  if (const double dt = sim.settings().dt_s; dt > scene.stable_time_step.dt_crit_s) {
    std::ostringstream w;
    w << std::setprecision(4) << "dt_s = " << dt << " s ";
    if (scene.stable_time_step.dt_crit_s > 0.0)
      w << "is " << dt / scene.stable_time_step.dt_crit_s << " times the stable time step of "
        << integrator_name(sim.settings().integrator) << ", " << scene.stable_time_step.dt_crit_s << " s,";
    else  // forward Euler: no stable step estimated (see check_run_start)
      w << "has no estimated stable limit with " << integrator_name(sim.settings().integrator)
        << " (stable only while dt < 2 zeta / omega on each mode, never on an undamped one) on the mode";
    w << " set by " << scene.stable_time_step.stiffest_element << "; the run was forced: "
      << (scene.stable_time_step.dt_crit_s > 0.0 ? "compare its results with a run below the limit"
                                                 : "check its results with another integrator");
    warn(w.str());
  }
  if (!writer.folder_lock_warning().empty()) warn(writer.folder_lock_warning());
  for (const std::string& w : case_warnings(def, scene)) warn(w);
  // Step 0's forces (run() would do it first): the contacts then know which
  // pairs overlap at the start.
  sim.initialize();
  if (scene.contacts) {
    if (const std::string w = initial_overlap_warning(scene.contacts->initial_overlaps(), sim.bodies()); !w.empty())
      warn(w);
  }
  // The warnings a run's end state gives (a run that was not unstable): the
  // ledger, the contacts' press, storeys whose mean hides a column or a
  // floor past a worse verdict (one side braced, the other not; workflow
  // probe: a storey 'damaged' at 0.044 rad whose West columns had passed
  // 0.1 rad), and, for a completed run (a stopped one's verdicts are
  // already "so far"), a peak in the run's last moments.
  // Joints still holding near a whole turn (whole_turn_joints_warning).
  auto warn_of_whole_turns = [&] {
    if (scene.joints)
      if (const std::string w = whole_turn_joints_warning(*scene.joints, sim.bodies(), scene.joint_names); !w.empty())
        warn(w);
  };
  auto warn_of_end_state = [&](bool completed) {
    for (const std::string& w : energy_warnings(sim.ledger(), case_has_dashpots(def), sim.settings().integrator))
      warn(w);
    if (scene.contacts)
      if (const std::string w =
              contact_press_warning(scene.contacts->press_peak(), sim.bodies(), scene.contacts->initial_overlaps());
          !w.empty())
        warn(w);
    warn_of_whole_turns();
    for (std::size_t i = 0; i < storeys.storeys().size(); ++i)
      for (const std::string& w : {storeys.twist_warning(i), storey_slip_warning(storeys, i, scene.joints),
                                   scene.joints ? loose_columns_warning(storeys.storeys()[i], storeys.verdict(i),
                                                                        *scene.joints)
                                                : std::string()})
        if (!w.empty()) warn(w);
    if (completed)
      for (std::size_t i = 0; i < storeys.storeys().size(); ++i)
        if (const std::string w = storeys.peak_at_end_warning(i, sim.time_s()); !w.empty()) warn(w);
  };
  // What summary.json holds beside the run's own figures (docs/summary_json.md),
  // as far as the run got; `assessed`: the storeys get verdicts.
  auto add_end_fields = [&](bool assessed) {
    JsonWriter list(0);
    list.begin_array();
    for (const std::string& w : report.warnings) list.value(w);
    writer.add_summary_field("warnings", list.end_array().str());
    writer.add_summary_field("ground_motion", ground_motion_summary(sim));
    if (scene.joints) add_joint_summary(writer, *scene.joints, sim.events(), scene.joint_labels, scene.joint_names);
    if (scene.contacts) add_contact_summary(writer, *scene.contacts, sim.bodies());
    if (!scene.storeys.empty()) add_storey_summary(writer, storeys, assessed);
    char hash[19];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(sim.state_hash()));
    writer.add_summary_field("state_hash", std::string("\"") + hash + "\"");
  };
  try {
    report.result = sim.run(options.stop_requested);
  } catch (const OutputError& e) {
    // A frame, a row or a checkpoint could not be written: the folder is
    // left with whole rows and a summary saying so (where the disk allows),
    // with the warnings, joints, storeys and state hash so far (the summary
    // had the ground motion only; review probe).
    try {
      warn_of_end_state(false);
      add_end_fields(true);
    } catch (const std::exception&) {
      // The summary is still written with the run's own figures.
    }
    const bool summary_written = writer.abandon(sim, e.what());
    std::ostringstream m;
    m << e.what() << " (the run ended at t = " << sim.time_s() << " s; the rows and frames before it are kept"
      << (summary_written ? ", and summary.json says output_failed)" : "; summary.json could not be written either)");
    throw OutputError(m.str());
  }
  if (report.result.status == RunStatus::Stopped && report.result.message.empty()) {
    std::ostringstream m;
    m << "stopped on request (Ctrl-C, SIGTERM or SIGHUP) at t = " << report.result.simulated_s << " s of "
      << sim.settings().duration_s << " s";
    report.result.message = m.str();
  }
  // An unstable run has already failed with its own message.
  if (report.result.status != RunStatus::Unstable) {
    warn_of_end_state(report.result.status == RunStatus::Completed);
  } else {
    // An unstable run's end state says nothing of the structure, but a
    // joint near a whole turn can be why it blew up (frame probe, stop 41:
    // a portal back upright after a whole turn about its feet); the state
    // the energy guard stops at is still finite (a non-finite one gives no
    // turn, and no warning).
    warn_of_whole_turns();
  }
  try {
    add_end_fields(report.result.status != RunStatus::Unstable);
    writer.finish(sim, report.result);
  } catch (const std::exception& e) {
    throw OutputError(e.what());
  }
  report.output_folder = writer.folder();
  report.stable_time_step = scene.stable_time_step;
  report.assessment = def.assessment;
  for (std::size_t i = 0; i < storeys.storeys().size(); ++i)
    report.storeys.push_back({storeys.storeys()[i].number, storeys.storeys()[i].height_m(), storeys.records()[i],
                              storeys.verdict(i)});
  if (scene.joints) {
    report.joints = scene.joints->counts();
    report.joint_count = scene.joints->joint_count();
  }
  report.first_joint_failure_time_s = first_joint_failure_time_s(sim.events());
  report.first_joint_failure = first_joint_failure_label(sim.events(), scene.joint_labels);
  report.first_joint_failure_name = first_joint_failure_label(sim.events(), scene.joint_names);
  report.first_joint_failure_break_time_s = first_joint_failure_break_time_s(sim.events());
  report.energy_balance_error_relative = sim.ledger().balance_error_relative();
  // What the run felt, not the whole window.
  report.peak_ground_acceleration_mps2 = sim.ground_motion().peak_horizontal_mps2(ground_motion_felt_until_s(sim));
  report.wall_s = report.result.wall_s;
  return report;
}

}  // namespace

std::string contact_press_warning(const ContactPressPeak& peak, const BodyStore& bodies,
                                  const std::vector<InitialOverlap>& initial_overlaps) {
  if (!(peak.ratio > kWarnContactPressRatio)) return "";
  auto name = [&](BodyId b) { return "'" + bodies.info[std::size_t(b)].name + "'"; };
  std::ostringstream w;
  w << std::setprecision(3) << "contacts pressed ";
  if (peak.body_a == kNoBody)
    w << name(peak.body_b) << " " << peak.depth_m * 1e3 << " mm into the ground";
  else
    w << name(peak.body_a) << " and " << name(peak.body_b) << " " << peak.depth_m * 1e3 << " mm into each other";
  // Times from 0.1 s on to the millisecond; earlier ones to two
  // significant digits at least, so that a peak at 0.57 ms does not read
  // "0.001 s" (nor 10 us "1e-05 s").
  const int decimals = peak.time_s >= 0.1 || !(peak.time_s > 0.0)
                           ? 3
                           : std::max(3, 1 - int(std::floor(std::log10(peak.time_s))));
  w << " at t = " << std::fixed << std::setprecision(decimals) << peak.time_s << " s, " << std::defaultfloat;
  w << std::setprecision(3) << 100.0 * peak.ratio << " % of the " << peak.half_dimension_m * 1e3
    << " mm half-thickness of " << name(peak.measured)
    << (peak.body_a == kNoBody ? "" : ", the thinner free box of the two")
    << " (the largest fraction of the run; more than " << 100.0 * kWarnContactPressRatio
    << " %): penalty contacts this soft let members sink into each other, so where they bear, pivot and come to "
       "rest, and when a rocking member tips over, are off by about that fraction of the section; run again with a "
       "stiffer contact (contact.*.normal_stiffness_N_per_m; a smaller dt_s if the stable step asks for it) to see "
       "whether the results depend on it";
  // A pair that started inside each other: each point of its first
  // manifold counts its press from its overlap then; a point taken later,
  // as the boxes move or another face of the two becomes the contact's,
  // from no more than the pair's allowance (the largest reference depth of
  // its points the step before; contacts/README.md), so the press can
  // exceed what the boxes moved (house probe, stop 40: a brace
  // starting 10 mm inside a roof beam pressed 2.8 mm after 0.55 ms from
  // rest, when gravity had moved it 1.5 um). Said here, so that the two
  // warnings do not read as contradicting each other.
  for (const InitialOverlap& o : initial_overlaps) {
    if (!((o.body_a == peak.body_a && o.body_b == peak.body_b) || (o.body_a == peak.body_b && o.body_b == peak.body_a)))
      continue;
    w << ". These two already overlapped by " << std::setprecision(3) << o.depth_m * 1e3
      << " mm at the start (one of the pairs of the warning that bodies overlap at the start), and the "
      << peak.depth_m * 1e3
      << " mm is beyond that; in boxes that start inside each other the contact's points change as they move, "
         "and the press can then exceed what the boxes moved: trim the members, turn their sections or move the "
         "blocks so that they do not start inside each other";
    break;
  }
  return w.str();
}

std::string initial_overlap_warning(const std::vector<InitialOverlap>& overlaps, const BodyStore& bodies) {
  if (overlaps.empty()) return "";
  std::ostringstream w;
  w << std::setprecision(3) << overlaps.size() << (overlaps.size() == 1 ? " pair" : " pairs")
    << " of bodies not held by a joint overlap at the start (";
  const std::size_t shown = std::min<std::size_t>(3, overlaps.size());
  for (std::size_t k = 0; k < shown; ++k) {
    const InitialOverlap& o = overlaps[k];
    w << (k ? "; " : "") << "'" << bodies.info[std::size_t(o.body_a)].name << "' and '"
      << bodies.info[std::size_t(o.body_b)].name << "' by " << o.depth_m * 1e3 << " mm";
  }
  if (overlaps.size() > shown) w << "; ...";
  w << "): their contacts take the overlap as their rest state, as for members a broken joint releases, and "
       "resist only further penetration; if the boxes should not overlap, trim the members (trim_m), turn "
       "their sections (roll_deg) or move the blocks";
  return w.str();
}

namespace {
// The case's nodes by id and sections by name (the geometry warnings below).
std::pair<std::unordered_map<std::string, const NodeDef*>, std::unordered_map<std::string, const SectionDef*>>
nodes_and_sections_by_name(const CaseDef& def) {
  std::unordered_map<std::string, const NodeDef*> nodes;
  for (const NodeDef& n : def.nodes) nodes.emplace(n.id, &n);
  std::unordered_map<std::string, const SectionDef*> sections;
  for (const SectionDef& s : def.sections) sections.emplace(s.name, &s);
  return {std::move(nodes), std::move(sections)};
}
}  // namespace

namespace {

// Member end nodes lying inside or on another member (within 1 mm of its
// box), with that member, in member order: nodes_inside_members_warning
// names them, and brace_free_ends_warning leaves them to it.
struct NodeInMember {
  const NodeDef* node;
  const MemberDef* member;
};
std::vector<NodeInMember> nodes_inside_members(const CaseDef& def) {
  const auto [nodes, sections] = nodes_and_sections_by_name(def);
  // Nodes where some member ends: only there do members meet at a joint.
  std::vector<const NodeDef*> ends;
  {
    std::unordered_set<std::string> seen;
    for (const MemberDef& m : def.members)
      for (const std::string* id : {&m.node_a, &m.node_b})
        if (nodes.count(*id) && seen.insert(*id).second) ends.push_back(nodes.at(*id));
  }
  constexpr double kEndClearance_m = 1e-3;
  // The end nodes in a grid, so each member meets only the nodes near its
  // box, not all of them (quadratic: a large share of the 90 s set-up of a
  // 100k-body grid). Cells of a typical member's length keep both the cells
  // a member covers and the nodes per cell few.
  std::vector<double> lengths;
  lengths.reserve(def.members.size());
  for (const MemberDef& m : def.members) {
    const auto a = nodes.find(m.node_a), b = nodes.find(m.node_b);
    if (a != nodes.end() && b != nodes.end()) lengths.push_back((b->second->xyz_m - a->second->xyz_m).norm());
  }
  double cell_m = 1.0;
  if (!lengths.empty()) {
    std::nth_element(lengths.begin(), lengths.begin() + std::ptrdiff_t(lengths.size() / 2), lengths.end());
    cell_m = lengths[lengths.size() / 2];
  }
  std::vector<Vec3> end_xyz;
  end_xyz.reserve(ends.size());
  for (const NodeDef* n : ends) end_xyz.push_back(n->xyz_m);
  const PointGrid grid(std::move(end_xyz), cell_m);
  std::vector<int> near;
  std::vector<NodeInMember> inside;
  for (const MemberDef& m : def.members) {
    const auto a = nodes.find(m.node_a), b = nodes.find(m.node_b);
    const auto sec = sections.find(m.section);
    if (a == nodes.end() || b == nodes.end() || sec == sections.end()) continue;  // build_model refuses these
    const Vec3 pa = a->second->xyz_m, axis = b->second->xyz_m - pa;
    const double length = axis.norm();
    if (!(length > 2.0 * kEndClearance_m)) continue;
    const Vec3 dir = axis / length;
    // The member's box (model.h, member_orientation: width along local y,
    // depth along local z) and 1 mm beyond its faces: a node on a face (a
    // post drawn standing on a beam's top) is held no better than one
    // inside.
    const Mat3 frame = member_orientation(pa, b->second->xyz_m, m.roll_rad).toRotationMatrix();
    const double half_width = 0.5 * sec->second->width_m + kEndClearance_m;
    const double half_depth = 0.5 * sec->second->depth_m + kEndClearance_m;
    // A node passing the test below lies within half_width + half_depth of
    // the axis between the ends (more than the box's half diagonal); 1 um
    // more covers rounding. The candidates come in `ends` order, as the
    // warning lists them.
    const double reach_m = half_width + half_depth + 1e-6;
    near.clear();
    grid.candidates(pa.cwiseMin(b->second->xyz_m) - Vec3::Constant(reach_m),
                    pa.cwiseMax(b->second->xyz_m) + Vec3::Constant(reach_m), near);
    for (const int k : near) {
      const NodeDef* n = ends[std::size_t(k)];
      if (n->id == m.node_a || n->id == m.node_b) continue;
      const double along = (n->xyz_m - pa).dot(dir);
      if (along <= kEndClearance_m || along >= length - kEndClearance_m) continue;
      const Vec3 across = n->xyz_m - pa - along * dir;
      if (std::abs(across.dot(frame.col(1))) > half_width || std::abs(across.dot(frame.col(2))) > half_depth) continue;
      inside.push_back({n, &m});
    }
  }
  return inside;
}

// The form of the case's list warnings: "<file>: <count> <what> (<the
// first items>[, ...]): <advice>", `what` in its singular and plural forms,
// `items` the first three at most, joined by `separator`.
std::string list_warning(const CaseDef& def, std::size_t count, const char* what_one, const char* what_many,
                         const std::vector<std::string>& items, const char* separator, const char* advice) {
  std::ostringstream w;
  w << def.source_file.string() << ": " << count << (count == 1 ? what_one : what_many) << " (";
  for (std::size_t k = 0; k < items.size(); ++k) w << (k ? separator : "") << items[k];
  if (count > items.size()) w << separator << "...";
  w << "): " << advice;
  return w.str();
}

}  // namespace

std::string nodes_inside_members_warning(const CaseDef& def) {
  const std::vector<NodeInMember> inside = nodes_inside_members(def);
  const std::size_t count = inside.size();
  std::vector<std::string> found;
  for (std::size_t k = 0; k < count && k < 3; ++k) {
    std::ostringstream f;
    f << "node '" << inside[k].node->id << "' (line " << inside[k].node->line << ") inside or on member '"
      << inside[k].member->id << "' (line " << inside[k].member->line << ")";
    found.push_back(f.str());
  }
  if (count == 0) return {};
  return list_warning(def, count, " node lies inside or on a member without being one of its ends",
                      " nodes lie inside or on a member without being one of its ends", found, "; ",
                      "joints join members only where they end, so the members ending at such a node are not held to "
                      "the member it lies in; split that member at the node if they should be joined");
}

std::string unused_nodes_warning(const CaseDef& def) {
  std::set<std::string> used;
  for (const MemberDef& m : def.members) {
    used.insert(m.node_a);
    used.insert(m.node_b);
  }
  std::vector<const NodeDef*> unused;
  for (const NodeDef& n : def.nodes)
    if (!used.count(n.id)) unused.push_back(&n);
  if (unused.empty()) return "";
  std::vector<std::string> found;
  for (std::size_t k = 0; k < unused.size() && k < 3; ++k)
    found.push_back("'" + unused[k]->id + "' (line " + std::to_string(unused[k]->line) + ")");
  return list_warning(def, unused.size(), " node is the end of no member", " nodes are the end of no member", found,
                      ", ", "a member meant to end there names another node, or the node is a leftover");
}

std::string duplicate_members_warning(const CaseDef& def) {
  // Members by their two end nodes, either way round.
  std::map<std::pair<std::string, std::string>, const MemberDef*> first_between;
  std::size_t count = 0;
  std::vector<std::string> found;
  for (const MemberDef& m : def.members) {
    const auto ends = std::minmax(m.node_a, m.node_b);
    const auto [at, fresh] = first_between.emplace(std::make_pair(ends.first, ends.second), &m);
    if (fresh) continue;
    ++count;
    if (found.size() < 3)
      found.push_back("'" + m.id + "' (line " + std::to_string(m.line) + ") and '" + at->second->id + "' (line " +
                      std::to_string(at->second->line) + ") between nodes '" + m.node_a + "' and '" + m.node_b + "'");
  }
  if (count == 0) return "";
  return list_warning(def, count, " member runs between the same two nodes as another",
                      " members run between the same two nodes as others", found, "; ",
                      "two boxes in one place double that member's mass and stiffness, and their joints hold "
                      "both; a line copied and not edited?");
}

std::string near_nodes_warning(const CaseDef& def) {
  const auto [nodes, sections] = nodes_and_sections_by_name(def);
  // Per end node: the thinnest section size of the members ending there (m).
  std::unordered_map<std::string, double> thinnest;
  std::set<std::pair<std::string, std::string>> member_ends;  // the two ends of one member
  for (const MemberDef& m : def.members) {
    const auto sec = sections.find(m.section);
    if (sec == sections.end() || !nodes.count(m.node_a) || !nodes.count(m.node_b)) continue;  // build_model refuses
    const double size = std::min(sec->second->width_m, sec->second->depth_m);
    for (const std::string* id : {&m.node_a, &m.node_b}) {
      auto [it, inserted] = thinnest.emplace(*id, size);
      if (!inserted) it->second = std::min(it->second, size);
    }
    member_ends.emplace(std::min(m.node_a, m.node_b), std::max(m.node_a, m.node_b));
  }
  // Sweep along x: only pairs within the largest tolerance can be near.
  std::vector<const NodeDef*> ends;
  double reach_m = 0.0;
  for (const auto& [id, size] : thinnest) {
    ends.push_back(nodes.at(id));
    reach_m = std::max(reach_m, 0.5 * size);
  }
  std::sort(ends.begin(), ends.end(), [](const NodeDef* a, const NodeDef* b) {
    return a->xyz_m.x() < b->xyz_m.x() || (a->xyz_m.x() == b->xyz_m.x() && a->line < b->line);
  });
  // The pairs in sweep order, but each node meets only the later nodes in
  // the cells around it: a sweep alone is quadratic when many nodes share
  // an x (a floor, a frame drawn in the y-z plane).
  std::vector<Vec3> end_xyz;
  end_xyz.reserve(ends.size());
  for (const NodeDef* n : ends) end_xyz.push_back(n->xyz_m);
  const PointGrid grid(std::move(end_xyz), reach_m);
  std::vector<int> near;
  std::vector<std::string> found;
  std::size_t count = 0;
  for (std::size_t i = 0; i < ends.size(); ++i) {
    near.clear();
    // 1 um beyond the reach covers rounding of the box's bounds.
    const Vec3 reach = Vec3::Constant(reach_m + 1e-6);
    grid.candidates(ends[i]->xyz_m - reach, ends[i]->xyz_m + reach, near);
    for (const int k : near) {
      const std::size_t j = std::size_t(k);
      if (j <= i || !(ends[j]->xyz_m.x() - ends[i]->xyz_m.x() <= reach_m)) continue;
      const NodeDef& a = *ends[i];
      const NodeDef& b = *ends[j];
      const double gap_m = (a.xyz_m - b.xyz_m).norm();
      if (gap_m >= 0.5 * std::min(thinnest.at(a.id), thinnest.at(b.id))) continue;
      if (member_ends.count({std::min(a.id, b.id), std::max(a.id, b.id)})) continue;
      ++count;
      if (found.size() < 3) {
        const NodeDef& first = a.line <= b.line ? a : b;
        const NodeDef& second = a.line <= b.line ? b : a;
        std::ostringstream f;
        f << "nodes '" << first.id << "' (line " << first.line << ") and '" << second.id << "' (line " << second.line
          << ") " << std::setprecision(3) << gap_m * 1e3 << " mm apart";
        found.push_back(f.str());
      }
    }
  }
  if (count == 0) return {};
  return list_warning(def, count,
                      " pair of member end nodes lie closer than half the thinnest section of their members",
                      " pairs of member end nodes lie closer than half the thinnest section of their members", found,
                      "; ",
                      "joints form only where members share a node, so the members ending at them are not joined; use "
                      "one node if they should meet");
}

namespace {
// f(member, length (m), section) for each member whose nodes and section
// exist (build_model refuses the others).
template <class F>
void for_each_member_length(const CaseDef& def, F&& f) {
  const auto [nodes, sections] = nodes_and_sections_by_name(def);
  for (const MemberDef& m : def.members) {
    const auto a = nodes.find(m.node_a), b = nodes.find(m.node_b);
    const auto sec = sections.find(m.section);
    if (a == nodes.end() || b == nodes.end() || sec == sections.end()) continue;
    f(m, (b->second->xyz_m - a->second->xyz_m).norm(), *sec->second);
  }
}

// The members a geometry check flags and the worst of them: measure(length
// (m), section) gives the flagged member's side (m) and ratio, or a ratio
// of 0 for a member it does not flag; the worst has the largest ratio (the
// first of equals).
struct FlaggedMembers {
  std::size_t count = 0;
  const MemberDef* worst = nullptr;
  double ratio = 0.0, length_m = 0.0, side_m = 0.0;
};
template <class Measure>
FlaggedMembers flag_members(const CaseDef& def, Measure&& measure) {
  FlaggedMembers out;
  for_each_member_length(def, [&](const MemberDef& m, double length_m, const SectionDef& section) {
    const auto [side_m, ratio] = measure(length_m, section);
    if (!(ratio > 0.0)) return;
    ++out.count;
    if (ratio > out.ratio) out = {out.count, &m, ratio, length_m, side_m};
  });
  return out;
}
}  // namespace

std::string stout_members_warning(const CaseDef& def) {
  const FlaggedMembers f = flag_members(def, [](double length_m, const SectionDef& section) {
    const double side_m = std::max(section.width_m, section.depth_m);
    return std::pair{side_m, section_typed_in_mm(side_m, length_m) ? side_m / length_m : 0.0};
  });
  if (f.count == 0) return {};
  std::ostringstream w;
  w << std::setprecision(3) << def.source_file.string() << ": " << f.count
    << (f.count == 1 ? " member has" : " members have") << " a section wider than "
    << (f.count == 1 ? "it is" : "they are") << " long (the stoutest, '" << f.worst->id << "' (line " << f.worst->line
    << "), is " << f.length_m << " m long with a side of " << f.side_m << " m, section '" << f.worst->section
    << "'): section sizes are in metres (width_m, depth_m); were they typed in millimetres?";
  return w.str();
}

std::string slender_members_warning(const CaseDef& def) {
  const FlaggedMembers f = flag_members(def, [](double length_m, const SectionDef& section) {
    const double thickness_m = std::min(section.width_m, section.depth_m);
    const double ratio = thickness_m > 0.0 ? length_m / thickness_m : 0.0;
    return std::pair{thickness_m, ratio > kSlenderMemberRatio ? ratio : 0.0};
  });
  if (f.count == 0) return {};
  std::ostringstream w;
  w << std::setprecision(3) << def.source_file.string() << ": " << f.count
    << (f.count == 1 ? " member is" : " members are") << " more than " << static_cast<long>(kSlenderMemberRatio)
    << " times longer than the thinner side of " << (f.count == 1 ? "its section" : "their sections")
    << " (the most slender, '" << f.worst->id << "' (line " << f.worst->line << "), is " << f.length_m
    << " m long and " << f.side_m << " m thin, " << f.ratio
    << " times): node coordinates are in metres (xyz_m); were they typed in millimetres?";
  return w.str();
}

std::string horizontal_columns_warning(const CaseDef& def) {
  const auto [nodes, sections] = nodes_and_sections_by_name(def);
  std::vector<const MemberDef*> flat;
  for (const MemberDef& m : def.members) {
    if (m.kind != MemberKind::Column) continue;
    const auto a = nodes.find(m.node_a), b = nodes.find(m.node_b);
    if (a == nodes.end() || b == nodes.end()) continue;  // build_model refuses these
    // Nearer horizontal than vertical: a column rising 2 mm over 0.49 m
    // made a storey 2 mm tall of its own (new-features probe).
    const Vec3 d = b->second->xyz_m - a->second->xyz_m;
    if (std::abs(d.z()) < kStoreyLevelTolerance_m || std::abs(d.z()) < d.head<2>().norm()) flat.push_back(&m);
  }
  if (flat.empty()) return {};
  std::ostringstream w;
  w << def.source_file.string() << ": " << flat.size() << (flat.size() == 1 ? " member" : " members")
    << " of kind column " << (flat.size() == 1 ? "lies" : "lie") << " nearer horizontal than vertical (";
  for (std::size_t k = 0; k < std::min<std::size_t>(3, flat.size()); ++k)
    w << (k ? ", " : "") << "'" << flat[k]->id << "' (line " << flat[k]->line << ")";
  if (flat.size() > 3) w << ", ...";
  w << "): a horizontal column spans no storey and is left out of the drift assessment, and a slightly sloping one "
       "makes a storey as tall as its rise; give it kind: beam, or check its nodes' heights";
  return w.str();
}

std::string turned_column_sections_warning(const CaseDef& def, const Scene& scene) {
  const auto [nodes, sections] = nodes_and_sections_by_name(def);
  const BodyStore& bodies = scene.simulation->bodies();
  std::unordered_map<std::string, BodyId> body_of;
  for (std::size_t i = 0; i < bodies.size(); ++i) body_of.emplace(bodies.info[i].name, BodyId(i));
  // The plan direction of every member that is not a column, by end node.
  std::unordered_map<std::string, std::vector<Vec3>> plan_directions_at;
  for (const MemberDef& m : def.members) {
    if (m.kind == MemberKind::Column) continue;
    const auto a = nodes.find(m.node_a), b = nodes.find(m.node_b);
    if (a == nodes.end() || b == nodes.end()) continue;
    Vec3 d = b->second->xyz_m - a->second->xyz_m;
    d.z() = 0.0;
    if (d.norm() < 1e-6) continue;  // vertical: no plan direction
    plan_directions_at[m.node_a].push_back(d.normalized());
    plan_directions_at[m.node_b].push_back(d.normalized());
  }
  std::size_t count = 0;
  std::vector<std::string> found;
  for (const MemberDef& m : def.members) {
    if (m.kind != MemberKind::Column) continue;
    const auto section = sections.find(m.section);
    const auto body = body_of.find(m.id);
    if (section == sections.end() || body == body_of.end()) continue;
    const double w = section->second->width_m, d = section->second->depth_m;
    if (std::abs(w - d) <= 0.01 * std::max(w, d)) continue;  // square: every plan angle alike
    const Mat3 r = bodies.orientation[body->second].toRotationMatrix();
    const Vec3 width_axis = r.col(1), depth_axis = r.col(2);
    if (std::abs(width_axis.z()) > 0.2 || std::abs(depth_axis.z()) > 0.2) continue;  // not upright
    // The turn (deg) that brings the section's width or depth onto the
    // nearest member framing into the column, in (-45, 45]; roll_deg turns
    // local y towards local z, so that turn is what roll_deg should add.
    double best_deg = HUGE_VAL;
    for (const std::string* node : {&m.node_a, &m.node_b}) {
      const auto at = plan_directions_at.find(*node);
      if (at == plan_directions_at.end()) continue;
      for (const Vec3& dir : at->second) {
        double deg = std::atan2(dir.dot(depth_axis), dir.dot(width_axis)) * 180.0 / M_PI;
        deg = std::remainder(deg, 90.0);
        if (std::abs(deg) < std::abs(best_deg)) best_deg = deg;
      }
    }
    if (!(std::abs(best_deg) > kTurnedSectionTolerance_deg) || !std::isfinite(best_deg)) continue;
    ++count;
    if (found.size() < 3) {
      std::ostringstream f;
      f << std::setprecision(3) << "'" << m.id << "' (line " << m.line << "), " << best_deg
        << " deg off: roll_deg " << (m.roll_rad * 180.0 / M_PI + best_deg);
      found.push_back(f.str());
    }
  }
  if (count == 0) return {};
  return list_warning(def, count, " column of rectangular section is turned against every member framing into it",
                      " columns of rectangular section are turned against every member framing into them", found,
                      "; ",
                      "a column's section keeps its width along world x whatever the plan's angle (cases/README.md, "
                      "members), so in a plan turned off the axes it bends about other axes than its beams do; give "
                      "the roll_deg named to align it, or ignore this if the turn is meant");
}

std::string no_columns_warning(const CaseDef& def) {
  const bool member_column = std::any_of(def.members.begin(), def.members.end(),
                                         [](const MemberDef& m) { return m.kind == MemberKind::Column; });
  // A block given kind column: storeys are found from members (between
  // nodes) only, so it spans none (input probe, stop 41: a case whose
  // columns were blocks got no storeys, and nothing said why).
  std::vector<const BlockDef*> column_blocks;
  for (const BlockDef& b : def.blocks)
    if (b.kind == MemberKind::Column) column_blocks.push_back(&b);
  // Blocks only, none a column: no frame to assess.
  if ((def.members.empty() || member_column) && column_blocks.empty()) return {};
  std::ostringstream w;
  w << def.source_file.string() << ": ";
  if (!def.members.empty() && !member_column)
    w << "no member is of kind column, so the case has no storeys and the run gives no "
      << "storey drift and no verdict (storeys are the bands between the floors its columns reach: cases/README.md, "
         "assessment); give the posts that carry the floors kind: column";
  if (!column_blocks.empty()) {
    if (!def.members.empty() && !member_column) w << "; ";
    w << "block '" << column_blocks.front()->id << "' (line " << column_blocks.front()->line << ")";
    if (column_blocks.size() > 1) w << " and " << column_blocks.size() - 1 << " more";
    w << (column_blocks.size() > 1 ? " are" : " is") << " of kind column, but storeys are found from members "
      << "(between two nodes) only, so " << (column_blocks.size() > 1 ? "they span" : "it spans")
      << " no storey and " << (column_blocks.size() > 1 ? "their" : "its")
      << " drift is not assessed; make a post a member between two nodes to have it assessed";
  }
  return w.str();
}

StoreyColumnJoints storey_column_joints(const Storey& storey, const JointSystem& joints) {
  StoreyColumnJoints n;
  if (storey.columns.empty()) return n;
  // Each body's column line in this storey (-1: none), then one pass over
  // the joints (a pass per column was columns x joints, thousands of
  // millions on a large generated grid).
  BodyId last_body = 0;
  for (const StoreyColumn& c : storey.columns) last_body = std::max({last_body, c.bottom_body, c.top_body});
  std::vector<int> column_of(std::size_t(last_body) + 1, -1);
  for (std::size_t k = 0; k < storey.columns.size(); ++k)
    for (const BodyId b : {storey.columns[k].bottom_body, storey.columns[k].top_body})
      if (b >= 0) column_of[std::size_t(b)] = int(k);
  const auto column = [&](BodyId b) { return b >= 0 && b <= last_body ? column_of[std::size_t(b)] : -1; };
  std::vector<char> has_joint(storey.columns.size(), 0);
  for (std::size_t j = 0; j < joints.joint_count(); ++j) {
    const int ca = column(joints.joint_body_a(j)), cb = column(joints.joint_body_b(j));
    if (ca < 0 && cb < 0) continue;
    const bool broken = joints.joint_status(j) == JointStatus::Broken;
    const std::size_t holds = std::size_t(ca >= 0) + std::size_t(cb >= 0 && cb != ca);
    ++n.joints;
    if (broken) {
      ++n.broken;
      n.broken_holds += holds;
    }
    for (const int c : {ca, cb})
      if (c >= 0) has_joint[std::size_t(c)] = 1;
  }
  n.every_column_held = std::find(has_joint.begin(), has_joint.end(), 0) == has_joint.end();
  return n;
}

std::string whole_turn_joints_warning(const JointSystem& joints, const BodyStore& bodies,
                                      const std::vector<std::string>& joint_names) {
  constexpr double kTurnWarned_rad = 1.5 * std::numbers::pi;
  std::size_t count = 0, worst = 0;
  double worst_rad = 0.0;
  for (std::size_t j = 0; j < joints.joint_count(); ++j) {
    if (joints.joint_status(j) == JointStatus::Broken) continue;
    const double turn_rad = joints.relative_turn_rad(bodies, j);
    if (!(turn_rad > kTurnWarned_rad)) continue;
    ++count;
    if (turn_rad > worst_rad) {
      worst_rad = turn_rad;
      worst = j;
    }
  }
  if (count == 0) return {};
  std::ostringstream w;
  w << std::setprecision(4) << "joint '" << (worst < joint_names.size() ? joint_names[worst] : std::to_string(worst))
    << "'";
  if (count > 1) w << " and " << count - 1 << (count == 2 ? " other" : " others");
  w << " still holding at the end " << (count > 1 ? "have" : "has") << " turned " << (count > 1 ? "their" : "its")
    << " two bodies more than three quarters of a whole turn against each other (" << worst_rad * 180.0 / std::numbers::pi
    << " deg" << (count > 1 ? " the most" : "")
    << "): near a whole turn a joint's half-way frame is undefined, and past it the frame is turned half a turn, so "
       "the forces of "
    << (count > 1 ? "these joints" : "this joint")
    << " after that are unreliable (joints/README.md, Large rotations); joints that can break (an ultimate "
       "strain) break long before";
  return w.str();
}

// The slip warning of storey i, told whether the joints holding its
// columns broke (none: they held and were soft in shear).
std::string storey_slip_warning(const StoreyDriftMonitor& storeys, std::size_t i, const JointSystem* joints) {
  if (joints == nullptr) return storeys.slip_warning(i, 0, 0);
  const StoreyColumnJoints n = storey_column_joints(storeys.storeys()[i], *joints);
  return storeys.slip_warning(i, int(n.broken), int(n.joints));
}

// A storey whose columns have lost every joint stands, if at all, on loose
// posts: its drift-based verdict (standing or damaged) says nothing of a
// frame any more (a house probe's storey read "damaged" at 0.071 rad with
// all 18 of its column joints broken). Said, with the count (a joint
// counted once per column it holds).
std::string loose_columns_warning(const Storey& storey, StoreyVerdict verdict, const JointSystem& joints) {
  if (verdict == StoreyVerdict::Collapsed || storey.columns.empty()) return {};
  const StoreyColumnJoints n = storey_column_joints(storey, joints);
  // A column no joint ever held: not a frame's storey.
  if (n.broken != n.joints || !n.every_column_held) return {};
  const std::size_t joint_count = n.broken_holds;
  const bool one = storey.columns.size() == 1;
  std::ostringstream w;
  w << "storey " << storey.number << ": every joint of its ";
  if (one)
    w << "column";
  else
    w << storey.columns.size() << " columns";
  w << " is broken (" << joint_count << (joint_count == 1 ? " joint" : " joints") << "), so "
    << (one ? "it stands, if at all, as a loose post on its contacts" : "they stand, if at all, as loose posts on "
                                                                          "their contacts")
    << "; its verdict (" << storey_verdict_name(verdict) << ") follows " << (one ? "the post's" : "their")
    << " drift, not that of a frame (events.csv lists the breaks; cases/README.md, assessment)";
  return w.str();
}

// A frame with no support, no ground (neither a ground section nor a
// contact with the ground) and no fixed block is held by nothing:
// under gravity it falls from the start, and its storeys' drifts and
// verdicts describe a falling frame (a probe's unsupported portal fell
// 4.9 m in 1 s and read "standing", with no warning). Blocks alone are
// left to fall unwarned (free-fall and impact set-ups).
std::string nothing_holds_the_frame_warning(const CaseDef& def, const Scene& scene) {
  // contact.ground alone makes a ground surface (at z = 0 without a ground
  // section) that the frame stands on (docs audit: such a frame was told
  // it falls).
  if (def.members.empty() || def.ground || !def.supports.empty() || (def.contact && def.contact->ground)) return {};
  if (!(def.time.gravity_mps2.norm() > 0.0)) return {};
  const BodyStore& bodies = scene.simulation->bodies();
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies.is_fixed[i]) return {};
  std::ostringstream w;
  w << def.source_file.string()
    << ": nothing holds the frame up (no supports, no ground section, no contact.ground and no fixed block), so "
    << "under gravity (" << def.time.gravity_mps2.norm()
    << " m/s^2) it falls freely from the start and its storey drifts and verdicts describe a falling frame; give "
       "supports (supports: [{node: ..., type: ...}]) or a ground with contact.ground (cases/README.md, supports, "
       "ground)";
  return w.str();
}

std::string ground_without_contact_warning(const CaseDef& def, const Scene& scene) {
  // A ground body exists with a ground section or any support (cases/README.md, ground).
  if (!def.ground && def.supports.empty()) return {};
  if (def.contact && def.contact->ground) return {};
  // The free bodies no chain of joints holds to a fixed body (the ground, a
  // fixed block) fall from the start: a frame held by its supports gets no
  // warning (review probe: the portal demo with a ground section was told
  // to add a contact that would change its results).
  const BodyStore& bodies = scene.simulation->bodies();
  std::vector<std::size_t> root(bodies.size());
  for (std::size_t i = 0; i < root.size(); ++i) root[i] = i;
  auto find = [&](std::size_t i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  if (scene.joints)
    for (std::size_t j = 0; j < scene.joints->joint_count(); ++j)
      root[find(std::size_t(scene.joints->joint_body_a(j)))] = find(std::size_t(scene.joints->joint_body_b(j)));
  std::vector<char> held(bodies.size(), 0);
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies.is_fixed[i]) held[find(i)] = 1;
  std::vector<std::string> loose;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (!bodies.is_fixed[i] && !held[find(i)]) loose.push_back(bodies.info[i].name);
  if (loose.empty()) return {};
  std::ostringstream w;
  w << def.source_file.string();
  const auto line = def.section_line.find(def.ground ? "ground" : "supports");
  if (line != def.section_line.end()) w << ":" << line->second;
  w << ": the case has a ground";
  if (def.ground) w << " (ground.level_m = " << def.ground->level_m << " m)";
  w << " but no contact with it (contact.ground), so nothing rests on it: " << loose.size()
    << (loose.size() == 1 ? " body" : " bodies") << " no joint holds to a support ('" << loose.front() << "'"
    << (loose.size() > 1 ? " and others" : "")
    << (loose.size() == 1 ? ") falls" : ") fall")
    << " through its surface, as will any member whose joints break; give contact: {ground: "
       "{normal_stiffness_N_per_m: ..., restitution: ..., friction_coefficient: ...}} for a ground that bears "
       "(cases/README.md, contact)";
  return w.str();
}

std::string unjoined_members_warning(const CaseDef& def, const Scene& scene) {
  if (scene.joints == nullptr || scene.joints->joint_count() == 0) return {};
  const BodyStore& bodies = scene.simulation->bodies();
  std::vector<char> joined(bodies.size(), 0);
  for (std::size_t j = 0; j < scene.joints->joint_count(); ++j) {
    joined[std::size_t(scene.joints->joint_body_a(j))] = 1;
    joined[std::size_t(scene.joints->joint_body_b(j))] = 1;
  }
  std::unordered_map<std::string, int> member_line;
  for (const MemberDef& m : def.members) member_line.emplace(m.id, m.line);
  std::vector<std::string> found;
  std::size_t count = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const auto line = member_line.find(bodies.info[i].name);
    if (joined[i] || bodies.is_fixed[i] || line == member_line.end()) continue;  // blocks are meant to be free
    ++count;
    if (found.size() < 3) found.push_back("'" + bodies.info[i].name + "' (line " + std::to_string(line->second) + ")");
  }
  if (count == 0) return {};
  return list_warning(def, count, " member is held by no joint or support", " members are held by no joint or support",
                      found, ", ",
                      "such a member stands only on its contacts, or falls where it has none; if it should be joined, "
                      "end it at the nodes of the members it meets");
}

std::vector<std::string> case_warnings(const CaseDef& def, const Scene& scene) {
  std::vector<std::string> out;
  for (std::string w : {duplicate_members_warning(def), nodes_inside_members_warning(def), near_nodes_warning(def),
                        unused_nodes_warning(def),
                        slender_members_warning(def), stout_members_warning(def), unjoined_members_warning(def, scene),
                        brace_free_ends_warning(def, scene), brace_on_supported_node_warning(def, scene),
                        unused_joint_rules_warning(def),
                        horizontal_columns_warning(def), turned_column_sections_warning(def, scene),
                        no_columns_warning(def), ground_without_contact_warning(def, scene),
                        nothing_holds_the_frame_warning(def, scene)})
    if (!w.empty()) out.push_back(std::move(w));
  for (std::string& w : ground_motion_direction_warnings(scene.simulation->ground_motion())) out.push_back(std::move(w));
  if (std::string w = ground_motion_sampling_warning(*scene.simulation); !w.empty()) out.push_back(std::move(w));
  if (std::string w = runge_kutta_sampling_warning(*scene.simulation); !w.empty()) out.push_back(std::move(w));
  return out;
}

std::string runge_kutta_sampling_warning(const Simulation& sim) {
  if (sim.settings().integrator != Integrator::RungeKutta4) return {};
  const double dt = sim.settings().dt_s;
  const double run_end_s = double(sim.total_steps()) * dt;
  // Where the run's time t = n dt meets a bend of the forcing: each record
  // sample the window plays (the record is linear between samples) and the
  // window's end, where the motion stops. A bend within 1e-4 of a step of a
  // boundary is counted as on it: it costs about 1e-4 of what it would cost
  // mid-step, and a dt_s typed to 15 digits stays that close over 1e9 steps
  // (a tolerance of 1e-6 steps sent a probe's suggested dt_s back with the
  // same warning after a few thousand steps).
  auto on_a_boundary = [dt](double t_s) {
    const double steps = t_s / dt;
    return std::abs(steps - std::round(steps)) <= 1e-4;
  };
  const GroundMotionComponent* sample_in = nullptr;  // the component with the earliest sample inside a step
  const GroundMotionComponent* end_in = nullptr;     // the first whose window ends between samples, inside a step
  double sample_in_s = HUGE_VAL, end_in_s = 0.0;
  for (const GroundMotionComponent& c : sim.ground_motion().components()) {
    if (dt > c.record.dt_s * c.time_scale * (1.0 + 1e-9)) continue;  // ground_motion_sampling_warning's case
    const AccelerationRecord& r = c.record;
    const std::vector<double>& a = r.acceleration_mps2;
    const double window_end_s = std::min(c.window_start_s + c.window_length_s, r.duration_s());
    // A sample bends the forcing where the slopes on its two sides differ
    // (a stretch of equal slopes, such as zeros, has no bend to straddle).
    auto slope = [&](std::size_t k) { return (a[k + 1] - a[k]) / (r.time_of(k + 1) - r.time_of(k)); };
    const std::size_t n = a.size();
    for (std::size_t k = 1; k + 1 < n; ++k) {
      const double t_rec = r.time_of(k);
      if (t_rec <= c.window_start_s || t_rec >= window_end_s) continue;
      const double t_s = (t_rec - c.window_start_s) * c.time_scale;
      if (t_s > run_end_s || t_s >= sample_in_s) break;
      if (slope(k - 1) != slope(k) && !on_a_boundary(t_s)) {
        sample_in = &c, sample_in_s = t_s;
        break;
      }
    }
    // Where the window (or the record) ends, the forcing drops to zero: a
    // bend unless it was already zero and flat there. An end on a sample is
    // one more sample (a step that divides the intervals puts it on a
    // boundary); an end between samples needs a window of whole samples.
    const double end_s = (window_end_s - c.window_start_s) * c.time_scale;
    std::size_t last = 0;  // the segment [last, last + 1] that holds the end
    while (last + 2 < n && r.time_of(last + 1) < window_end_s) ++last;
    const bool flat_zero = r.at(window_end_s) == 0.0 && (n < 2 || slope(last) == 0.0);
    if (end_s < run_end_s && !flat_zero && !on_a_boundary(end_s)) {
      // (Here the record has two samples or more: one sample ends the motion at t = 0, a boundary.)
      const double end_samples = (window_end_s - r.time_of(last)) / (r.time_of(last + 1) - r.time_of(last));
      const bool end_on_sample = std::abs(end_samples - std::round(end_samples)) <= 1e-6;
      if (end_on_sample) {
        if (end_s < sample_in_s) sample_in = &c, sample_in_s = end_s;
      } else if (end_in == nullptr) {
        end_in = &c, end_in_s = end_s;
      }
    }
  }
  if (sample_in == nullptr && end_in == nullptr) return {};
  std::ostringstream w;
  // Times to 10 digits (a sample at 0.005 s printed as 0.00500000000000012
  // to 15); the suggested step to 15, so that it can be typed back.
  w << std::setprecision(10) << "the integrator rk4 is fourth order only where the forcing is smooth within each "
    << "step; at dt_s = " << dt << " s ";
  if (sample_in != nullptr)
    w << "a sample of " << sample_in->record.source << " (at t = " << sample_in_s
      << " s; the record is linear between its samples, so its slope jumps there)";
  if (sample_in != nullptr && end_in != nullptr) w << " and ";
  if (end_in != nullptr) w << "the end of the window of " << end_in->record.source << " (at t = " << end_in_s << " s)";
  w << std::setprecision(15);
  w << (sample_in != nullptr && end_in != nullptr ? " fall" : " falls")
    << " inside a step, and each such bend costs rk4 an error of order dt_s^2 (docs/speed_accuracy.md). For rk4's "
       "accuracy ";
  if (sample_in != nullptr) {
    const double step = record_aligned_step_s(sim.ground_motion(), dt);
    if (step > 0.0)
      w << "give dt_s = " << step << " s, the largest step up to dt_s that puts every played sample of every "
        << "record on a step boundary (it divides each played sample interval, record dt x time_scale)";
    else
      w << "give dt_s dividing every played sample interval (record dt x time_scale) and the time of every "
           "record's first played sample (none up to dt_s that divides a thousandth of the shortest of these does)";
  }
  if (sample_in != nullptr && end_in != nullptr) w << ", and ";
  if (end_in != nullptr)
    w << "give the window's length (window_length_s, or --window-length of compare and sweep) a whole number of "
         "the record's samples ("
      << end_in->record.dt_s << " s)";
  return w.str();
}

double record_aligned_step_s(const GroundMotion& motion, double dt_max_s) {
  const std::vector<GroundMotionComponent>& components = motion.components();
  if (components.empty() || !(dt_max_s > 0.0)) return 0.0;
  // The simulated lengths a step must divide for every played sample to
  // fall on a boundary: each record's sample intervals (its distinct gaps,
  // for an unevenly sampled one) and the time of its first played sample
  // (not 0 when the window starts between samples), times its time scale.
  std::vector<double> lengths_s;
  auto add = [&lengths_s](double length_s) {
    if (!(length_s > 0.0)) return;
    for (const double l : lengths_s)
      if (std::abs(l - length_s) <= 1e-9 * l) return;
    lengths_s.push_back(length_s);
  };
  for (const GroundMotionComponent& c : components) {
    const AccelerationRecord& r = c.record;
    const std::size_t n = r.acceleration_mps2.size();
    const double window_end_s = std::min(c.window_start_s + c.window_length_s, r.duration_s());
    bool first = true;
    double previous_s = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      const double t_rec = r.time_of(k);
      if (t_rec < c.window_start_s || t_rec > window_end_s) continue;
      if (first) {
        // A sample within a millionth of an interval of the window's start is at it.
        const double offset_s = t_rec - c.window_start_s;
        if (offset_s > 1e-6 * r.dt_s) add(offset_s * c.time_scale);
        first = false;
        if (r.sample_time_s.empty()) {
          add(r.dt_s * c.time_scale);  // every gap of an evenly sampled record is this
          break;
        }
      } else {
        add((t_rec - previous_s) * c.time_scale);
      }
      previous_s = t_rec;
    }
  }
  if (lengths_s.empty()) return 0.0;
  // dt = (the shortest length) / n for the smallest n that makes dt <=
  // dt_max_s and divides every other length to 1e-9 of it; n is searched up
  // to a thousand times its first value (lengths whose ratios are not ratios
  // of small whole numbers have no common step worth suggesting).
  const double shortest_s = *std::min_element(lengths_s.begin(), lengths_s.end());
  const double n0 = std::max(1.0, std::ceil(shortest_s / dt_max_s * (1.0 - 1e-12)));
  for (double n = n0; n <= 1000.0 * n0; n += 1.0) {
    const double step = shortest_s / n;
    bool divides = true;
    for (const double l : lengths_s) {
      const double ratio = l / step;
      divides = divides && std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio;
    }
    if (divides) return step;
  }
  return 0.0;
}

std::string ground_motion_sampling_warning(const Simulation& sim) {
  // gsl_rk8pd evaluates the motion wherever its adaptive sub-steps fall
  // within dt_s, and its error control follows the record between samples
  // to its tolerance (a probe's elastic frame at dt_s = 0.01 s drifted as
  // at 1e-5 s to 9e-14 m, and was told it stepped over samples).
  if (sim.settings().integrator == Integrator::GslRk8pd) return {};
  const GroundMotion& motion = sim.ground_motion();
  const double dt = sim.settings().dt_s;
  // The record's finest interval as the run plays it (record seconds times
  // time_scale); a step no longer than it meets every sample's
  // neighbourhood, a longer one steps over samples.
  const GroundMotionComponent* coarsest = nullptr;
  double interval_s = HUGE_VAL;
  for (const GroundMotionComponent& c : motion.components()) {
    const double played = c.record.dt_s * c.time_scale;
    if (played < interval_s) {
      interval_s = played;
      coarsest = &c;
    }
  }
  if (coarsest == nullptr || !(dt > interval_s * (1.0 + 1e-9))) return {};
  // What the run applies: the motion at its step times (forces are taken at
  // t = n dt), against what the record holds over the same span. A step
  // longer than a sample means no more steps than samples here.
  const std::int64_t steps = sim.total_steps();
  const double end_s = double(steps) * dt;
  Vec3 applied = Vec3::Zero();
  for (std::int64_t n = 0; n <= steps; ++n) applied = applied.cwiseMax(motion.acceleration(double(n) * dt).cwiseAbs());
  const Vec3 recorded = motion.peak_abs_mps2(end_s);
  Eigen::Index axis = 0;
  recorded.maxCoeff(&axis);
  std::ostringstream w;
  w << std::setprecision(4) << "time.dt_s = " << dt << " s is longer than the sample interval of "
    << coarsest->record.source << " as the run plays it (" << coarsest->record.dt_s << " s x time_scale "
    << coarsest->time_scale << " = " << interval_s << " s): the run steps over samples, and applies a peak "
    << "ground acceleration of " << applied[axis] << " m/s^2 along " << "xyz"[axis] << " where the record holds "
    << recorded[axis] << " m/s^2 (summary.json gives the record's); give dt_s at most " << interval_s << " s";
  return w.str();
}

std::string brace_free_ends_warning(const CaseDef& def, const Scene& scene) {
  if (scene.joints == nullptr || scene.joints->joint_count() == 0) return {};
  // Members ending at each node, and the supported nodes: joints form only
  // there (cases/README.md, "Joints").
  std::unordered_map<std::string, int> members_at;
  for (const MemberDef& m : def.members) {
    ++members_at[m.node_a];
    ++members_at[m.node_b];
  }
  std::set<std::string> supported;
  for (const SupportDef& sp : def.supports) supported.insert(sp.node);
  std::unordered_map<std::string, int> node_line;
  for (const NodeDef& n : def.nodes) node_line.emplace(n.id, n.line);
  // A node inside another member is named by nodes_inside_members_warning,
  // whose advice (split that member there) fits a brace meant to reach it.
  std::set<std::string> in_member;
  for (const NodeInMember& n : nodes_inside_members(def)) in_member.insert(n.node->id);
  auto joins_something = [&](const std::string& node) {
    return members_at[node] > 1 || supported.count(node) > 0 || in_member.count(node) > 0;
  };
  std::vector<std::string> found;
  std::size_t count = 0;
  for (const MemberDef& m : def.members) {
    if (m.kind != MemberKind::Brace) continue;
    const bool a = joins_something(m.node_a), b = joins_something(m.node_b);
    if (a == b) continue;  // joined at both ends, or at neither (unjoined_members_warning)
    const std::string& free_node = a ? m.node_b : m.node_a;
    ++count;
    if (found.size() < 3)
      found.push_back("'" + m.id + "' (line " + std::to_string(m.line) + ") at node '" + free_node + "' (line " +
                      std::to_string(node_line[free_node]) + ")");
  }
  if (count == 0) return {};
  return list_warning(def, count, " brace is joined at one end only", " braces are joined at one end only", found, ", ",
                      "no other member ends at that node and no support holds it, so the brace hangs from its other "
                      "end and braces nothing; end it at the node of the corner it should reach");
}

std::string brace_on_supported_node_warning(const CaseDef& def, const Scene& scene) {
  if (scene.joints == nullptr || scene.joints->joint_count() == 0) return {};
  std::set<std::string> supported;
  for (const SupportDef& sp : def.supports) supported.insert(sp.node);
  // The members other than braces that end at each node.
  std::unordered_map<std::string, const MemberDef*> other_at;
  for (const MemberDef& m : def.members)
    if (m.kind != MemberKind::Brace)
      for (const std::string* n : {&m.node_a, &m.node_b}) other_at.emplace(*n, &m);
  std::vector<std::string> found;
  std::size_t count = 0;
  for (const MemberDef& m : def.members) {
    if (m.kind != MemberKind::Brace) continue;
    for (const std::string* n : {&m.node_a, &m.node_b}) {
      const auto other = other_at.find(*n);
      if (supported.count(*n) == 0 || other == other_at.end()) continue;
      ++count;
      if (found.size() < 3)
        found.push_back("'" + m.id + "' (line " + std::to_string(m.line) + ") at node '" + *n + "' with '" +
                        other->second->id + "'");
      break;
    }
  }
  if (count == 0) return {};
  return list_warning(def, count, " brace ends at a supported node where another member ends too",
                      " braces end at a supported node where another member ends too", found, ", ",
                      "such a brace is joined both to that member (the hub there, with its joint type) and to the "
                      "ground (with the support's), two connections where one is meant (cases/README.md, "
                      "\"supports\"); give the brace a foot node of its own, with its own support and joint type, as "
                      "frame_C.yaml does");
}

std::string unused_joint_rules_warning(const CaseDef& def) {
  if (def.joints.rules.empty()) return {};
  // Every planned joint names the rule that gave it its type, if one did
  // (by its line, a rule written on the line where joints: {...} begins
  // counted as used by every joint of default_type; docs probe).
  std::set<int> used;
  for (const PlannedJoint& p : plan_joints(build_model(def))) used.insert(p.rule);
  std::ostringstream list;
  std::size_t unused = 0;
  for (std::size_t k = 0; k < def.joints.rules.size(); ++k) {
    const JointRuleDef& r = def.joints.rules[k];
    if (!used.count(int(k)))
      list << (unused++ ? ", " : "") << "[" << member_kind_name(r.kind_1) << ", " << member_kind_name(r.kind_2)
           << "] (line " << r.line << ")";
  }
  if (unused == 0) return {};
  std::ostringstream w;
  w << def.source_file.string() << ": " << unused << (unused == 1 ? " joint rule makes" : " joint rules make")
    << " no joint (" << list.str();
  w << "): no two members of those kinds are joined to each other at any node (each member is joined to the node's "
       "hub, the first member of kind "
    << member_kind_name(def.joints.hub_kind)
    << " there: joints.hub_kind), or an override gives every such pair its type";
  return w.str();
}

std::vector<std::string> ground_motion_direction_warnings(const GroundMotion& motion) {
  std::vector<std::string> warnings;
  for (const GroundMotionComponent& c : motion.components()) {
    // The component: the last comma-separated field of the header line.
    const std::string& d = c.record.description;
    const std::size_t comma = d.rfind(',');
    if (comma == std::string::npos) continue;
    std::string field;
    for (char ch : d.substr(comma + 1))
      if (ch != ' ' && ch != '\t') field += char(std::toupper(static_cast<unsigned char>(ch)));
    if (field.empty()) continue;
    const bool vertical_name = field == "UP" || field == "DWN" || field == "DOWN" || field == "UD" || field == "V" ||
                               field == "VER" || field == "VERT" || field == "Z";
    bool azimuth = field.size() <= 3 && std::all_of(field.begin(), field.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
    // Station-prefixed azimuths ("I-ELC180"): trailing three digits.
    if (!azimuth && field.size() > 3) {
      const std::string tail = field.substr(field.size() - 3);
      azimuth = std::all_of(tail.begin(), tail.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
    }
    const bool horizontal_name = azimuth || field == "EW" || field == "NS" || field == "E" || field == "N";
    // Mostly vertical: more than 45 degrees above the horizontal (a 30
    // degree cut called a direction 42 degrees up "mostly vertical"); at 45
    // degrees exactly, neither warning.
    const double up = std::abs(c.direction.normalized().z());
    const bool applied_vertically = up > std::sqrt(0.5), applied_horizontally = up < std::sqrt(0.5);
    std::ostringstream w;
    if (vertical_name && applied_horizontally)
      w << c.record.source << " is a vertical component ('" << field << "' in its header: " << d
        << ") applied along the mostly horizontal direction (" << (c.direction.array() + 0.0).transpose()
        << "); give a horizontal record, or this one along z";
    else if (horizontal_name && applied_vertically && !vertical_name)
      w << c.record.source << " is a horizontal component ('" << field << "' in its header: " << d
        << ") applied along the mostly vertical direction (" << (c.direction.array() + 0.0).transpose()
        << "); give the record's vertical component, or this one along x or y";
    if (!w.str().empty()) warnings.push_back(w.str());
  }
  return warnings;
}

bool case_has_dashpots(const CaseDef& def) {
  auto damped = [](const SpringDef& s) { return s.dashpot.coefficient_Nspm > 0.0 || s.dashpot.damping_ratio > 0.0; };
  for (const JointTypeDef& t : def.joint_types)
    if (damped(t.normal) || damped(t.shear) || damped(t.axial) || damped(t.diagonal) || damped(t.shear_link))
      return true;
  if (def.contact) {
    const ContactDef& c = *def.contact;
    if (c.ground && c.ground->restitution < 1.0) return true;
    // A pair's restitution damps only where two bodies of its materials
    // exist: a lone block on the ground has no pair contact, whatever the
    // default pair's restitution (which defaults to 0.5).
    std::map<std::string, int> bodies_of_material;
    for (const MemberDef& m : def.members) ++bodies_of_material[m.material];
    for (const BlockDef& b : def.blocks) ++bodies_of_material[b.material];
    for (auto i = bodies_of_material.begin(); i != bodies_of_material.end(); ++i) {
      for (auto j = i; j != bodies_of_material.end(); ++j) {
        if (i == j && i->second < 2) continue;
        const ContactParams* params = &c.default_pair;
        for (const ContactPairDef& p : c.pairs)
          if ((p.material_1 == i->first && p.material_2 == j->first) ||
              (p.material_1 == j->first && p.material_2 == i->first))
            params = &p.params;
        if (params->restitution < 1.0) return true;
      }
    }
  }
  return false;
}

std::vector<std::string> energy_warnings(const EnergyLedger& l, bool has_dashpots, Integrator method) {
  std::vector<std::string> warnings;
  const double error = l.balance_error_relative();
  if (std::fabs(error) > kWarnBalanceErrorRelative) {
    std::ostringstream w;
    w << std::setprecision(3) << "the energy balance does not close: error " << error
      << " of the largest energy in play (warned above " << kWarnBalanceErrorRelative << "); ";
    if (method == Integrator::ForwardEuler)
      w << "forward_euler gains energy at every dt_s on an undamped mode, and on a damped one once dt_s passes 2 "
           "zeta / omega: run again with another integrator";
    else if (method == Integrator::GslRk8pd)
      // Its motion is resolved by its own sub-steps; the ledger's work terms
      // are not (Simulation::update_ledger_synchronised).
      w << "gsl_rk8pd follows the motion within each step by its own adaptive sub-steps, but the ledger books the "
           "ground motion's work and the dashpots' loss once per dt_s (trapezoid rule), so a long dt_s leaves the "
           "ledger open rather than the motion wrong: run again with a smaller dt_s to close it";
    else
      w << "the time step does not resolve the motion: run again with a smaller dt_s";
    warnings.push_back(w.str());
  }
  // Without any dashpot the viscous book holds only the contact springs'
  // own discretisation error, whose sign says nothing about a dashpot.
  if (has_dashpots && l.dissipated_viscous_J < -kWarnViscousGainRelative * l.scale_J) {
    std::ostringstream w;
    w << std::setprecision(3) << "the dashpots gained " << -l.dissipated_viscous_J << " J ("
      << -l.dissipated_viscous_J / l.scale_J
      << " of the largest energy in play); a dashpot only dissipates, so some damped mode (a stiff contact or "
         "joint) is unstable at this time step: run again with a smaller dt_s";
    warnings.push_back(w.str());
  }
  if (!has_dashpots && std::fabs(l.dissipated_viscous_J) > kWarnContactDiscretisationRelative * l.scale_J) {
    std::ostringstream w;
    w << std::setprecision(3) << "the contact springs' discretisation error reached " << l.dissipated_viscous_J
      << " J (" << l.dissipated_viscous_J / l.scale_J
      << " of the largest energy in play; summary.json's dissipated_viscous_J, which holds only this error in a "
         "scene without dashpots); the time step does not resolve the contacts, which can gain energy below the "
         "stable estimate when they open and close: run again with a smaller dt_s";
    warnings.push_back(w.str());
  }
  return warnings;
}

namespace {

// contact.intact_nodes other than touch: every two joints planned at the same
// node that join one common body (the hub, or the ground of a support) hold
// their other two bodies together, as the node's connection does, until one
// of them breaks -- unless a joint joins those two directly: then that joint
// alone decides (a column and a brace each supported at one node and joined
// to each other would otherwise keep the column off the ground, under none,
// after its own support broke, for as long as the brace's held). Joints are
// planned node by node (joint_builder.h), so a node's joints are found by its id.
void hold_pairs_at_nodes(JointSystem& joints, const std::vector<PlannedJoint>& planned) {
  const auto pair_of = [](BodyId a, BodyId b) { return a < b ? std::pair(a, b) : std::pair(b, a); };
  std::set<std::pair<BodyId, BodyId>> joined_directly;
  std::map<std::string, std::vector<std::size_t>> joints_at_node;
  for (std::size_t j = 0; j < planned.size(); ++j) {
    joints_at_node[planned[j].node].push_back(j);
    joined_directly.insert(pair_of(planned[j].def.body_a, planned[j].def.body_b));
  }
  for (const auto& node_joints : joints_at_node) {
    const std::vector<std::size_t>& at = node_joints.second;
    for (std::size_t i = 0; i < at.size(); ++i)
      for (std::size_t k = i + 1; k < at.size(); ++k) {
        const JointDef& p = planned[at[i]].def;
        const JointDef& q = planned[at[k]].def;
        const bool p_a_shared = p.body_a == q.body_a || p.body_a == q.body_b;
        const bool p_b_shared = p.body_b == q.body_a || p.body_b == q.body_b;
        if (p_a_shared == p_b_shared) continue;  // no common body, or the same two
        const BodyId hub = p_a_shared ? p.body_a : p.body_b;
        const BodyId x = p_a_shared ? p.body_b : p.body_a;
        const BodyId y = q.body_a == hub ? q.body_b : q.body_a;
        if (!joined_directly.count(pair_of(x, y))) joints.hold_pair_through(at[i], at[k]);
      }
  }
}

}  // namespace

Scene build_scene(const CaseDef& def) {
  Model model = build_model(def);
  const std::vector<PlannedJoint> planned = plan_joints(model);
  Scene scene;
  scene.storeys = find_storeys(model);
  scene.simulation = std::make_unique<Simulation>(model.bodies, model.settings, model.ground_motion);
  Simulation& sim = *scene.simulation;
  if (!planned.empty()) {
    auto joints = std::make_unique<JointSystem>(&sim.bonded_pairs());
    for (const PlannedJoint& p : planned) {
      try {
        joints->add_joint(sim.bodies(), p.def);
      } catch (const std::invalid_argument& e) {
        throw InputError(def.source_file.string(), p.line, "joint_types." + p.type,
                         p.label + ": " + e.what());
      }
      scene.joint_labels.push_back(p.label);
      scene.joint_types.push_back(p.type);
      scene.joint_names.push_back(p.name);
      scene.joint_nodes.push_back(p.node);
    }
    if (def.contact && def.contact->intact_nodes != IntactNodeContact::Touch) hold_pairs_at_nodes(*joints, planned);
    scene.joints = joints.get();
    sim.add_force_provider(std::move(joints));
  }
  if (def.contact) {
    const ContactDef& c = *def.contact;
    ContactSystemSettings contact_settings;
    contact_settings.ground_under_intact_supports = c.intact_nodes != IntactNodeContact::None;
    auto contacts = std::make_unique<ContactSystem>(&sim.bonded_pairs(), contact_settings);
    for (std::size_t i = 0; i < def.members.size(); ++i)
      contacts->set_body_material(model.member_body[i], def.material_index(def.members[i].material));
    for (std::size_t i = 0; i < def.blocks.size(); ++i)
      contacts->set_body_material(model.block_body[i], def.material_index(def.blocks[i].material));
    const int materials = int(def.materials.size());
    for (int i = 0; i < materials; ++i)
      for (int j = i; j < materials; ++j) contacts->set_pair_params(i, j, c.default_pair);
    for (const ContactPairDef& p : c.pairs)
      contacts->set_pair_params(def.material_index(p.material_1), def.material_index(p.material_2), p.params);
    if (c.ground) contacts->set_ground(def.ground ? def.ground->level_m : 0.0, *c.ground);
    scene.contacts = contacts.get();
    sim.add_force_provider(std::move(contacts));
  }
  scene.stable_time_step = estimate_stable_time_step(*scene.simulation, scene.joint_names);
  return scene;
}

namespace {

// The case as a run sees it: the case file's, or a copy with the integrator
// of --integrator.
struct EffectiveCase {
  CaseDef copy;
  const CaseDef* def = nullptr;
  bool integrator_from_command_line = false;
};

EffectiveCase effective_case(const CaseDef& case_def, const CaseRunOptions& options) {
  EffectiveCase e;
  e.def = &case_def;
  if (options.integrator.has_value()) {
    e.copy = case_def;
    e.copy.time.integrator = *options.integrator;
    e.def = &e.copy;
    e.integrator_from_command_line = true;
  }
  return e;
}

// The checks a run makes before it writes anything: an integrator the
// scene's force providers cannot serve, and a time step above the stable
// estimate unless forced. An integrator chosen on the command line is named
// as the option (no file or line); one chosen in the case file by its key's
// line.
// A refusal of the integrator, named where it was chosen: the option, or
// the case file's key.
InputError integrator_error(const CaseDef& def, bool integrator_from_command_line, const std::string& why) {
  if (integrator_from_command_line) return InputError("", 0, "--integrator", why);
  const int line = line_of(def, "time.integrator");
  return InputError(def.source_file.string(), line ? line : line_of(def, "time"), "time.integrator", why);
}

// check_integrator = false skips the first check (describe_case reports it
// as a line instead).
void check_run_start(const CaseDef& def, const Scene& scene, const CaseRunOptions& options,
                     bool integrator_from_command_line, bool check_integrator = true) {
  const Simulation& sim = *scene.simulation;
  const double dt = sim.settings().dt_s;
  const Integrator method = sim.settings().integrator;
  if (const std::string why = sim.integrator_refusal(); check_integrator && !why.empty())
    throw integrator_error(def, integrator_from_command_line, why);
  if (std::isnan(scene.stable_time_step.omega_max_radps)) {
    // Not overridable: no dt can be checked, and the run's arithmetic would
    // be meaningless. The masses and inertias are checked in build_model;
    // this catches what they let pass (a stiffness of 1e300).
    const int line = line_of(def, "time.dt_s");
    throw InputError(def.source_file.string(), line ? line : line_of(def, "time"), "time.dt_s",
                     "the stable time step cannot be estimated: a mode's frequency is not a finite number; a mass, "
                     "an inertia or a stiffness of the case is out of the range double precision resolves (check the "
                     "densities, sizes, and the joints' and contacts' stiffnesses)");
  }
  if (dt > scene.stable_time_step.dt_crit_s && !options.allow_unstable_time_step) {
    std::ostringstream msg;
    if (method == Integrator::ForwardEuler) {
      // Forward Euler is stable on a mode of damping ratio zeta only while
      // omega dt < 2 zeta (|1 + lambda dt| <= 1), on an undamped one never.
      // The engine estimates no such limit: its network estimate is the
      // leapfrog's, which a damped mode raises instead of lowering.
      msg << "forward_euler is stable only while dt_s < 2 zeta / omega on every mode (zeta: the mode's damping "
             "ratio) and never on an undamped mode (|1 + i omega dt| > 1); framequake estimates no such limit, so "
             "it refuses forward_euler for a scene with a stiff mode: the stiffest here, "
          << scene.stable_time_step.omega_max_radps << " rad/s, is " << scene.stable_time_step.stiffest_element
          << "; choose another integrator (or run with --force to override)";
      throw integrator_error(def, integrator_from_command_line, msg.str());
    }
    // omega_max is the undamped frequency that would set the same limit
    // (dem_core/linearised_network.h): dashpots included, not 2/omega of
    // the stiffest spring alone.
    msg << "dt_s = " << dt << " s exceeds the stable time step of " << integrator_name(method) << ", "
        << limit_text(scene.stable_time_step.dt_crit_s) << " s (" << integrator_stability_factor(method)
        << "/omega_max, omega_max = " << scene.stable_time_step.omega_max_radps
        << " rad/s: the scene's stiffest mode, its dashpots included), set by "
        << scene.stable_time_step.stiffest_element
        << "; lower dt_s below it (or run with --force to override)";
    const int line = line_of(def, "time.dt_s");
    throw InputError(def.source_file.string(), line ? line : line_of(def, "time"), "time.dt_s", msg.str());
  }
}

}  // namespace

std::string summary_value(const std::filesystem::path& folder, const std::string& key);  // below

void check_case_runnable(const CaseDef& case_def, const CaseRunOptions& options) {
  const EffectiveCase e = effective_case(case_def, options);
  const Scene scene = build_scene(*e.def);
  check_run_start(*e.def, scene, options, e.integrator_from_command_line);
}

CaseRunReport run_case(const CaseDef& case_def, const CaseRunOptions& options) {
  const EffectiveCase effective = effective_case(case_def, options);
  const CaseDef& def = *effective.def;
  Scene scene = build_scene(def);
  Simulation& sim = *scene.simulation;
  const Integrator method = sim.settings().integrator;
  check_run_start(def, scene, options, effective.integrator_from_command_line);

  OutputDef output = def.output;
  if (options.output_folder) output.folder = *options.output_folder;
  if (output.folder.empty()) output.folder = default_output_folder(def.name);
  std::optional<RunMeta> meta;
  if (options.checkpoint_every_s) {
    if (!(*options.checkpoint_every_s > 0.0) || !std::isfinite(*options.checkpoint_every_s))
      throw InputError("", 0, "--checkpoint-every", "expected a positive number of simulated seconds");
    // A checkpoint at every step writes the whole state 1e5 times a
    // simulated second (a probe's 1e-9 s made a 0.04 s run take 5.5 s).
    if (*options.checkpoint_every_s < def.time.dt_s * (1.0 - 1e-9)) {
      std::ostringstream why;
      why << "expected at least one time step (dt_s = " << def.time.dt_s << " s), got "
          << *options.checkpoint_every_s << " s";
      throw InputError("", 0, "--checkpoint-every", why.str());
    }
    if (def.source_file.empty())
      throw InputError("", 0, "--checkpoint-every", "checkpoints need a case read from a file (resume reloads it)");
    if (method != Integrator::CentralDifference)
      throw InputError("", 0, "--checkpoint-every",
                       std::string("checkpoints save the state of the central-difference scheme only; this run uses ") +
                           integrator_name(method) + " (run it without --checkpoint-every, or with central_difference)");
    meta.emplace();
    meta->case_file = std::filesystem::absolute(def.source_file);
    try {
      meta->files = case_file_fingerprints(def);
    } catch (const CheckpointError& e) {
      throw InputError(def.source_file.string(), 0, "", e.what());
    }
    meta->checkpoint_every_s = *options.checkpoint_every_s;
    meta->allow_unstable_time_step = options.allow_unstable_time_step;
    meta->case_name = def.name;
  }
  if (options.on_note) {
    const double dt = sim.settings().dt_s;
    for (const std::string& note :
         {interval_rounding_note("output.frame_interval_s", output.frame_interval_s, dt),
          interval_rounding_note("output.history_interval_s", output.history_interval_s, dt),
          meta ? interval_rounding_note("--checkpoint-every", meta->checkpoint_every_s, dt) : std::string(),
          meta ? checkpoint_count_note(meta->checkpoint_every_s, sim) : std::string(),
          interval_beyond_run_note("output.frame_interval_s", output.frame_interval_s, sim, "frames are written"),
          interval_beyond_run_note("output.history_interval_s", output.history_interval_s, sim, "history.csv has rows"),
          ground_motion_end_note(sim), hub_choice_note(def)})
      if (!note.empty()) options.on_note(note);
    for (const std::string& note : planar_link_system_notes(def, scene)) options.on_note(note);
    for (const std::string& note : record_time_shift_notes(sim)) options.on_note(note);
  }

  // A run into a folder that holds a stopped run resume could continue
  // replaces it as any earlier run, but that one was not finished: said,
  // so that it is not lost unawares (workflow probe). Stopped (Ctrl-C) it
  // has a summary saying so; killed, none. Told once the folder is locked:
  // before, a run still writing the folder (no summary yet) read as killed.
  const auto note_unfinished_run = [&]() {
    if (!options.on_note) return;
    std::error_code ec;
    const std::string status = summary_value(output.folder, "status");
    if (std::filesystem::exists(output.folder / kCheckpointFileName, ec) && (status == "stopped" || status.empty()))
      options.on_note("the output folder " + output.folder.string() + " held an unfinished run (" +
                      (status.empty() ? std::string("killed, no summary")
                                      : "stopped at t = " + summary_value(output.folder, "simulated_time_s") + " s") +
                      ") that `framequake resume " + output.folder.string() +
                      "` could have continued from its checkpoint; this run replaces it");
  };
  std::unique_ptr<RunOutput> writer;
  StoreyDriftMonitor storeys(scene.storeys, def.assessment, sim.settings().dt_s, residual_drift_window_s(def));
  try {
    writer = std::make_unique<RunOutput>(output, def.name, note_unfinished_run);
    attach_provider_output(*writer, scene);
    if (!scene.storeys.empty()) attach_storey_output(*writer, storeys);
    writer->attach(sim);
  } catch (const std::exception& e) {
    throw OutputError(e.what());
  }
  return execute(scene, *writer, options, meta ? &*meta : nullptr, def, storeys);
}

// The value of "key" in the folder's summary.json (a string without its
// quotes, or a number as written), or "" when there is none.
std::string summary_value(const std::filesystem::path& folder, const std::string& key) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(summary_path(folder), ec);
  if (ec || size > (1u << 24)) return "";
  std::ifstream in(summary_path(folder), std::ios::binary);
  if (!in) return "";
  std::string text(std::size_t(size), '\0');
  in.read(text.data(), std::streamsize(size));
  if (in.gcount() != std::streamsize(size)) return "";
  const std::string tag = "\"" + key + "\": ";
  const std::size_t at = text.find(tag);
  if (at == std::string::npos) return "";
  std::size_t begin = at + tag.size();
  if (begin < text.size() && text[begin] == '"') {
    const std::size_t end = text.find('"', begin + 1);
    return end == std::string::npos ? "" : text.substr(begin + 1, end - begin - 1);
  }
  std::size_t end = begin;
  while (end < text.size() && text[end] != ',' && text[end] != '\n' && text[end] != '}') ++end;
  return text.substr(begin, end - begin);
}

CaseRunReport resume_case(const std::filesystem::path& folder, const CaseRunOptions& options,
                          const std::optional<std::filesystem::path>& moved_case_file) {
  const std::filesystem::path file = folder / kCheckpointFileName;
  {
    // A case file or a mistyped name given for the folder: said as such
    // (it was "checkpoint file 'frame_A.yaml/checkpoint.bin' does not
    // exist (was the run started with --checkpoint-every?)").
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(folder, ec);
    if (!std::filesystem::exists(st))
      throw CheckpointError("no such folder: '" + folder.string() +
                            "' (resume takes the output folder of a run started with --checkpoint-every)");
    if (!std::filesystem::is_directory(st))
      throw CheckpointError("'" + folder.string() +
                            "' is not a folder (resume takes the output folder of a run started with "
                            "--checkpoint-every, not its case file)");
  }
  // What the folder's summary says of the run, for a clear refusal: a run
  // that completed has nothing to resume (resuming it rewrote its summary
  // with the wall time of a no-op), and one stopped before its first step
  // left no checkpoint (resume used to ask whether it had been started with
  // --checkpoint-every).
  const std::string status = summary_value(folder, "status");
  if (status == "completed")
    throw CheckpointError("the run in '" + folder.string() +
                          "' completed (summary.json); there is nothing to resume");
  std::error_code ec;
  if (!std::filesystem::exists(file, ec) && status == "stopped" && summary_value(folder, "steps") == "0")
    throw CheckpointError("the run in '" + folder.string() +
                          "' was stopped before its first step, so it left no checkpoint; start it again with "
                          "framequake run");
  const std::string payload = read_checkpoint_file(file);
  const std::string damaged = "checkpoint file '" + file.string() + "' is damaged or does not fit this case: ";
  StateReader in(payload);
  RunMeta meta;
  try {
    meta = read_run_meta(in);
  } catch (const StateFormatError& e) {
    throw CheckpointError(damaged + e.what());
  }
  // The case where it was when the run began, or where it is now
  // (resume --case): a project folder moved with its records keeps their
  // bytes, which is what the checkpoint checks (workflow probe: a moved
  // project could not be resumed at all).
  if (moved_case_file) {
    meta.case_file = std::filesystem::absolute(*moved_case_file);
  } else if (std::error_code missing; !std::filesystem::exists(meta.case_file, missing)) {
    throw CheckpointError("the case file the run in '" + folder.string() + "' was started from, '" +
                          meta.case_file.string() +
                          "', is not there any more; if it was moved (with its records), give its new place with "
                          "--case FILE");
  }
  CaseDef def = load_case_file(meta.case_file);
  std::vector<CaseFileFingerprint> now;
  try {
    now = case_file_fingerprints(def);
  } catch (const CheckpointError& e) {
    throw CheckpointError("checkpoint file '" + file.string() + "': " + e.what());
  }
  // Named file by file (a user who edited a record did not know what "the
  // case" meant).
  if (const std::string which = changed_case_files(meta.files, now); !which.empty()) {
    throw CheckpointError("checkpoint file '" + file.string() + "' was written for case file '" +
                          meta.case_file.string() + "' as it was then; since then " + which +
                          ", so the run cannot be resumed (start it again with framequake run)");
  }
  def.output.folder = folder;
  // Checkpoints are written by central-difference runs only (run_case
  // refuses --checkpoint-every otherwise), whatever the case file names: a
  // run may have chosen it with --integrator over the file's integrator.
  def.time.integrator = Integrator::CentralDifference;
  Scene scene = build_scene(def);
  Simulation& sim = *scene.simulation;
  const std::vector<Vec3> initial_position_m = sim.bodies().position_m;

  std::unique_ptr<RunOutput> writer;
  StoreyDriftMonitor storeys(scene.storeys, def.assessment, sim.settings().dt_s, residual_drift_window_s(def));
  try {
    writer = std::make_unique<RunOutput>(RunOutput::resume(def.output, def.name, in));
    storeys.load_state(in);
    sim.load_state(in);
    if (in.remaining() != 0) in.fail(std::to_string(in.remaining()) + " bytes left over after the state");
  } catch (const StateFormatError& e) {
    throw CheckpointError(damaged + e.what());
  } catch (const std::logic_error& e) {
    throw CheckpointError(damaged + e.what());
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::runtime_error& e) {
    // The folder itself: locked by another process, or not to be opened.
    // An output error, as run reports it (it was an "internal error",
    // exit 4; failure-mode probe).
    throw OutputError(e.what());
  }
  try {
    attach_provider_output(*writer, scene);
    if (!scene.storeys.empty()) attach_storey_output(*writer, storeys);
    writer->attach(sim, &initial_position_m);
  } catch (const std::exception& e) {
    throw OutputError(e.what());
  }
  return execute(scene, *writer, options, &meta, def, storeys);
}

void describe_case(const CaseDef& case_def, std::ostream& out, std::optional<Integrator> integrator,
                   bool list_joints) {
  CaseRunOptions forced;
  forced.integrator = integrator;
  const EffectiveCase effective = effective_case(case_def, forced);
  const CaseDef& def = *effective.def;
  Scene scene = build_scene(def);
  // The case is described whatever run would say of it; each reason run
  // would refuse it (an integrator the scene's laws cannot serve, a dt above
  // the stable limit without --force) is one line under the time step. Only
  // a scene whose stable step cannot be estimated at all is an error here.
  const std::string integrator_refused = scene.simulation->integrator_refusal();
  forced.allow_unstable_time_step = true;
  check_run_start(def, scene, forced, effective.integrator_from_command_line, false);
  const Simulation& sim = *scene.simulation;
  const BodyStore& bodies = sim.bodies();
  double total_mass = 0.0;
  std::size_t free_bodies = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies.is_fixed[i]) continue;
    total_mass += bodies.mass_kg[i];
    ++free_bodies;
  }
  const SimulationSettings& s = sim.settings();
  out << "case        " << def.name << "  (" << def.source_file.string() << ")\n";
  if (!def.description.empty()) out << "            " << utf8_repaired(def.description) << "\n";
  out << "bodies      " << bodies.size() << " (" << free_bodies << " free, " << bodies.size() - free_bodies
      << " fixed)\n";
  out << "total mass  " << total_mass << " kg (free bodies)\n";
  if (scene.joints) {
    out << "joints      " << scene.joints->joint_count() << " (" << scene.joints->spring_count() << " springs)\n";
    // How many joints of each type, in the order the types first occur: a
    // retrofit (a stronger foot joint) shows here (info of a retrofitted
    // frame read the same as the original's; workflow probe).
    std::vector<std::pair<std::string, int>> by_type;
    for (const std::string& type : scene.joint_types) {
      auto it = std::find_if(by_type.begin(), by_type.end(), [&](const auto& p) { return p.first == type; });
      if (it == by_type.end())
        by_type.emplace_back(type, 1);
      else
        ++it->second;
    }
    if (!by_type.empty()) {
      out << "            by type:";
      for (std::size_t k = 0; k < by_type.size(); ++k)
        out << (k ? ", " : " ") << by_type[k].first << " " << by_type[k].second;
      out << "\n";
    }
    if (!list_joints) out << "            (--joints lists them with their ids, nodes, members and types)\n";
  }
  if (!scene.storeys.empty()) {
    // What the run's drifts and verdicts will be taken over (io/storey_drift.h).
    // One line each, with the columns: a post meant as a roof strut shows
    // up here as a storey of its own (cases/README.md, "assessment").
    out << "storeys     " << scene.storeys.size() << "\n";
    for (std::size_t i = 0; i < scene.storeys.size(); ++i) {
      const Storey& st = scene.storeys[i];
      out << "            " << i + 1 << " from z = " << st.bottom_z_m << " to " << st.top_z_m << " m, "
          << st.columns.size() << " column" << (st.columns.size() == 1 ? "" : "s") << ":";
      // The first kColumnsListed only, like the other lists of names: a
      // 35x35 grid's storeys printed 1296 columns each, 12 KB a line.
      constexpr std::size_t kColumnsListed = 12;
      const std::size_t listed = std::min(st.column_names.size(), kColumnsListed);
      for (std::size_t c = 0; c < listed; ++c) {
        out << (c ? ", " : " ") << st.column_names[c];
        // A column shorter than its storey (its foot inside the band) has
        // its drift ratio taken over its own height (io/storey_drift.h).
        if (st.height_m() - st.columns[c].height_m > kStoreyLevelTolerance_m) out << " (" << st.columns[c].height_m << " m)";
      }
      if (st.column_names.size() > listed) out << ", ... and " << st.column_names.size() - listed << " more";
      out << "\n";
    }
    out << "            verdicts: damaged above " << def.assessment.safety_drift_ratio_rad
        << " rad, collapsed from " << def.assessment.collapse_drift_ratio_rad << " rad of peak drift ratio (assessment)\n";
  } else if (!def.members.empty()) {
    // A frame without storeys: said here, not left out silently (geometry
    // probe); the warnings below say why.
    out << "storeys     none: no column spans a storey, so a run gives no storey drift and no verdict\n";
  }
  if (def.contact) {
    // Which contacts act across joints that still hold (contact.intact_nodes):
    // a choice of model that changes results, so said where the case is described.
    out << "contacts    across intact joints: ";
    switch (def.contact->intact_nodes) {
      case IntactNodeContact::Touch:
        out << "touch (members meeting at a node without a joint between them bear on each other; supported "
               "members bear on the ground)\n";
        break;
      case IntactNodeContact::GroundOnly:
        out << "ground_only (members joined at a node through a common member, not to each other, touch once "
               "one of their joints to it breaks; supported members bear on the ground)\n";
        break;
      case IntactNodeContact::None:
        out << "none (seed 001: no contact across an intact joint, the ground under a supported member "
               "included, until the joint breaks)\n";
        break;
    }
  }
  for (const std::string& w : case_warnings(def, scene)) out << "warning     " << w << "\n";
  if (scene.contacts) {
    // Step 0's forces, as run evaluates them first: the contacts then know
    // which pairs overlap at the start, which run warns of. An integrator
    // the contacts refuse cannot start the scene: the overlaps are those of
    // the same scene under central difference (the start's forces are the
    // same).
    Scene central_difference_scene;
    Scene* start = &scene;
    if (!integrator_refused.empty()) {
      CaseDef copy = def;
      copy.time.integrator = Integrator::CentralDifference;
      central_difference_scene = build_scene(copy);
      start = &central_difference_scene;
    }
    start->simulation->initialize();
    if (const std::string w = initial_overlap_warning(start->contacts->initial_overlaps(), start->simulation->bodies());
        !w.empty())
      out << "warning     " << w << "\n";
  }
  out << "time step   " << s.dt_s << " s (" << integrator_name(s.integrator)
      << (effective.integrator_from_command_line ? ", from --integrator" : "") << ")";
  if (scene.stable_time_step.dt_crit_s == 0.0)  // forward Euler on an undamped mode
    out << "  (no stable time step with " << integrator_name(s.integrator)
        << ": it is stable only while dt < 2 zeta / omega on every mode, never on an undamped one, and no such "
           "limit is estimated; the stiffest mode is "
        << scene.stable_time_step.stiffest_element << ")";
  else if (std::isfinite(scene.stable_time_step.dt_crit_s))
    out << "  (stable limit " << limit_text(scene.stable_time_step.dt_crit_s) << " s, set by "
        << scene.stable_time_step.stiffest_element << ")";
  // What run will say (run_case refuses it unless forced).
  if (std::isnan(scene.stable_time_step.dt_crit_s))
    out << "\n            NO STABLE LIMIT CAN BE ESTIMATED (a mode's frequency is not a finite number): run refuses "
           "this case";
  else if (scene.stable_time_step.dt_crit_s == 0.0)
    out << "\n            NO ESTIMATED STABLE STEP: run refuses this integrator here unless --force is given";
  else if (s.dt_s > scene.stable_time_step.dt_crit_s)
    out << "\n            ABOVE THE STABLE LIMIT: run refuses this time step unless --force is given";
  if (!integrator_refused.empty())
    out << "\n            RUN WOULD REFUSE THIS INTEGRATOR (--force does not override it): "
        << integrator_error(def, effective.integrator_from_command_line, integrator_refused).what();
  out << "\nduration    " << s.duration_s << " s = " << sim.total_steps() << " steps\n";
  const GroundMotion& gm = sim.ground_motion();
  if (gm.empty()) {
    out << "ground      no ground motion\n";
  } else {
    // The peaks the run feels: up to its end, which may come before the
    // window's (a record's strongest part beyond it is never applied).
    const Vec3 peak = gm.peak_abs_mps2(s.duration_s);
    out << "ground      " << gm.components().size() << " component(s), peak |a_g| x/y/z = " << peak.x() << " / "
        << peak.y() << " / " << peak.z() << " m/s^2, horizontal |(a_x, a_y)| " << gm.peak_horizontal_mps2(s.duration_s)
        << " m/s^2";
    if (s.duration_s < gm.end_time_s())
      out << " over the run's " << s.duration_s << " s (the windows end at " << gm.end_time_s()
          << " s; the whole windows peak at " << gm.peak_horizontal_mps2() << " m/s^2 horizontal)";
    out << "\n";
    for (const GroundMotionComponent& c : gm.components())
      // + 0.0 prints a negative zero component of `-z` as 0.
      out << "            " << c.record.source << "  along (" << (c.direction.array() + 0.0).transpose() << ") x "
          << c.amplitude_scale << ", time scale " << c.time_scale << ", window from " << c.window_start_s
          << " s" << (c.record.file_start_time_s != 0.0 ? " (" + record_time_shift_text(c) + ")" : std::string())
          << "\n";
  }
  OutputDef o = def.output;
  if (o.folder.empty()) o.folder = default_output_folder(def.name);
  // What run writes: every whole number of steps (steps_per_interval),
  // from the start, and the last state once more when it is off that grid.
  const std::int64_t steps = sim.total_steps();
  auto samples = [steps](std::int64_t every) { return samples_written(steps, every); };
  const std::int64_t frame_every = steps_per_interval(o.frame_interval_s, s.dt_s);
  const std::int64_t history_every = steps_per_interval(o.history_interval_s, s.dt_s);
  // An interval longer than the run: the start and the end only.
  auto spacing = [&](std::int64_t every) {
    std::ostringstream t;
    if (every >= steps)
      t << "(the start and the end)";
    else
      t << "every " << double(every) * s.dt_s << " s";
    return t.str();
  };
  out << "output      " << o.folder.string() << ": " << samples(frame_every) << " frames " << spacing(frame_every)
      << ", " << samples(history_every) << " history rows " << spacing(history_every) << "\n";
  for (const std::string& note : {interval_rounding_note("output.frame_interval_s", o.frame_interval_s, s.dt_s),
                                  interval_rounding_note("output.history_interval_s", o.history_interval_s, s.dt_s),
                                  ground_motion_end_note(sim), hub_choice_note(def)})
    if (!note.empty()) out << "note        " << note << "\n";
  for (const std::string& note : planar_link_system_notes(def, scene)) out << "note        " << note << "\n";
  if (list_joints && scene.joints) {
    // One line per joint id: its name (events.csv's joint_name, the frames'
    // joint_names) and where it is, so that a joint that never yielded can
    // be found as well as one an event names.
    std::size_t width = 4;
    for (const std::string& name : scene.joint_names) width = std::max(width, name.size());
    out << "joint list  id  " << std::left << std::setw(int(width)) << "name" << "  node, members and type\n";
    for (std::size_t j = 0; j < scene.joint_names.size(); ++j)
      out << "            " << std::right << std::setw(2) << j << "  " << std::left << std::setw(int(width))
          << scene.joint_names[j] << "  " << scene.joint_labels[j] << "\n";
    out << std::right;
  }
}

}  // namespace fq
