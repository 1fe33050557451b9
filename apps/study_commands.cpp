// `framequake compare` and `framequake sweep`: several runs side by side
// (io/batch_runner.h), a table of what each storey did, and a figure drawn by
// scripts/plot/fq_plot.py (matplotlib, Debian's python3).
#include "study_commands.h"

#include <algorithm>
#include <csignal>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <sys/wait.h>
#include <vector>

#include "collapse_bracket.h"
#include "comparison_notes.h"
#include "option_number.h"
#include "run_outcome.h"
#include "usage_error.h"
#include "fq_config.h"
#include "io/accelerogram.h"
#include "io/atomic_file.h"
#include "io/batch_runner.h"
#include "io/case_file.h"
#include "io/csv_text.h"
#include "io/folder_lock.h"
#include "io/input_error.h"
#include "io/model.h"
#include "io/run_output.h"

namespace fq_app {

namespace fs = std::filesystem;

namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr int kExitOutputFailed = 3;
constexpr int kExitInterrupted = 130;  // main.cpp turns it into 128 + the signal received

const char* kCompareHelp =
    "Usage: framequake compare CASE... [options]\n"
    "\n"
    "Runs the cases side by side (one core each) and compares their storeys:\n"
    "  DIR/<case name>/            each run's full output (case.pvd, history.csv, ...)\n"
    "  DIR/comparison.csv, .md     peak drift ratio and verdict per storey, first joint\n"
    "                              failure, broken joints, energy balance error, integrator\n"
    "                              and time step (csv; for gsl_rk8pd the output interval),\n"
    "                              wall time\n"
    "  DIR/first_storey_drift.png  drift ratio against time of every storey, one panel each\n"
    "                              (the name is kept from when it showed storey 1 only): the\n"
    "                              magnitude of its x and y parts, which the verdicts are\n"
    "                              taken from, with each case's drift limits\n"
    "An earlier study's tables and figure in DIR are removed before the runs start;\n"
    "a file of the same name that no study of ours wrote stops the study.\n"
    "A run that did not reach its end is standing or damaged only \"so far\".\n"
    "\n"
    "Options:\n"
    "  --out DIR            output folder (default out/compare)\n"
    "  --jobs N             runs at a time (default: number of cores)\n"
    "  --window-length S    use only S record seconds of each case's ground-motion window\n"
    "  --force              run even if dt_s exceeds the estimated stable time step\n"
    "  --no-figure          write the tables only\n"
    "  --help               this text\n"
    "\n"
    "Exit codes: 0 all runs completed and everything was written; 1 a run became\n"
    "unstable; 2 bad input (nothing run); 3 output failed; 130 interrupted (143 by SIGTERM, 129 by SIGHUP).\n";

const char* kSweepHelp =
    "Usage: framequake sweep CASE... [options]\n"
    "\n"
    "Runs every case at each amplitude scale (and with each record), one core per run,\n"
    "and writes:\n"
    "  DIR/<case>_<record>_x<scale>/   each run's full output\n"
    "  DIR/sweep.csv                   one row per run: scale, PGA (peak of the horizontal\n"
    "                                  ground acceleration's magnitude up to the run's end),\n"
    "                                  peak drift ratio and verdict per storey, first\n"
    "                                  failure, broken joints, integrator and time step\n"
    "                                  (for gsl_rk8pd the output interval)\n"
    "  DIR/collapse_scales.csv, .md    per case and record: the smallest scale at which a\n"
    "                                  storey collapsed (from the runs that completed), and\n"
    "                                  the scales above it that stood (not monotonic)\n"
    "  DIR/sweep.png                   peak drift ratio of the largest storey against PGA,\n"
    "                                  with the runs' damage and collapse drift limits\n"
    "An earlier study's tables and figure in DIR are removed before the runs start;\n"
    "a file of the same name that no study of ours wrote stops the study.\n"
    "\n"
    "Options:\n"
    "  --scales LIST        comma-separated amplitude scales (default 0.5,0.75,1,1.25,1.5,2);\n"
    "                       each multiplies every ground-motion component's amplitude_scale\n"
    "  --record FILE        a PEER .AT2 record to use instead of the case's (repeatable; the\n"
    "                       case must have one component; the window is kept, cut at the\n"
    "                       record's end). Without --record the case's own record is used.\n"
    "  --out DIR            output folder (default out/sweep)\n"
    "  --jobs N             runs at a time (default: number of cores)\n"
    "  --window-length S    use only S record seconds of the ground-motion window\n"
    "  --force              run even if dt_s exceeds the estimated stable time step\n"
    "  --no-figure          write the tables only\n"
    "  --help               this text\n"
    "\n"
    "Exit codes: 0 all runs completed and everything was written; 1 a run became\n"
    "unstable; 2 bad input (nothing run); 3 output failed; 130 interrupted (143 by SIGTERM, 129 by SIGHUP).\n";

// Decimal only, as the case file's numbers (option_number.h): strtod read
// "--scales 0x1" as hexadecimal.
double parse_positive(const std::string& text, const std::string& option, const char* help) {
  return positive_number_option(option, text, help);
}

struct StudyArgs {
  std::vector<std::string> cases;
  fs::path out;
  int jobs = 0;
  std::optional<double> window_length_s;
  bool force = false;
  bool figure = true;
  std::vector<double> scales{0.5, 0.75, 1.0, 1.25, 1.5, 2.0};
  std::vector<std::string> records;
};

StudyArgs parse_study_args(int argc, char** argv, const char* help, bool sweep) {
  StudyArgs a;
  a.out = sweep ? "out/sweep" : "out/compare";
  std::vector<std::string> seen;  // options that take one value, given once each (as run)
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* name) -> std::string {
      // "--out A --out B": which was meant is not for us to guess (the last
      // one won silently; CLI probe). --record may be given once per record.
      if (std::string(name) != "--record") {
        if (std::find(seen.begin(), seen.end(), name) != seen.end())
          usage_error(std::string(name) + " is given twice; give it once", help);
        seen.push_back(name);
      }
      std::string given = option_value(name, argc, argv, i, help);
      ++i;
      return given;
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << help;
      std::exit(kExitOk);
    } else if (arg == "--out") {
      a.out = value("--out");
    } else if (arg == "--jobs") {
      a.jobs = whole_number_option("--jobs", value("--jobs"), 1, 256, help);
    } else if (arg == "--window-length") {
      a.window_length_s = parse_positive(value("--window-length"), "--window-length", help);
    } else if (arg == "--force") {
      a.force = true;
    } else if (arg == "--no-figure") {
      a.figure = false;
    } else if (sweep && arg == "--scales") {
      a.scales.clear();
      const std::string text = value("--scales");
      // getline drops an empty last item: "1," would pass as "1".
      if (text.back() == ',') parse_positive("", "--scales", help);
      std::stringstream list(text);
      for (std::string item; std::getline(list, item, ',');) a.scales.push_back(parse_positive(item, "--scales", help));
      if (a.scales.empty()) usage_error("--scales needs at least one scale", help);
      std::sort(a.scales.begin(), a.scales.end());
      a.scales.erase(std::unique(a.scales.begin(), a.scales.end()), a.scales.end());
    } else if (sweep && arg == "--record") {
      a.records.push_back(value("--record"));
    } else if (!arg.empty() && arg[0] == '-') {
      unknown_option(arg, help);
    } else {
      a.cases.push_back(arg);
    }
  }
  if (a.cases.empty()) usage_error("missing CASE (one or more YAML case files)", help);
  return a;
}

// Shortens the ground-motion window to `length_s` record seconds (never the
// physics: same model, same record, same scales). `say_when_not_shorter`:
// note on stderr when the case's window is not longer (a sweep with
// --record says it per record instead, whose lengths are not the case's).
void shorten_window(fq::CaseDef& def, double length_s, bool say_when_not_shorter = true) {
  if (!def.ground_motion)
    throw fq::InputError(def.source_file.string(), 0, "ground_motion",
                         "--window-length given but the case has no ground motion");
  fq::GroundMotionDef& gm = *def.ground_motion;
  // The window the case would use: window_length_s, or to the end of the
  // shortest record (no longer than a record's remaining seconds).
  double window_s = gm.window_length_s;
  for (const fq::GroundMotionComponentDef& c : gm.components)
    window_s = std::min(window_s, c.record.duration_s() - gm.window_start_s);
  if (length_s >= window_s && say_when_not_shorter)
    std::cerr << "framequake: note: --window-length " << length_s << " s is not shorter than the window of '"
              << def.name << "' (" << window_s << " record s); its whole window is used\n";
  // An option that leaves less than one step is the option's fault, named
  // as such (it was reported at the case file's ground_motion line).
  if (length_s * gm.time_scale < def.time.dt_s) {
    std::ostringstream why;
    why << "expected at least one time step: " << length_s << " record s at the time scale " << gm.time_scale
        << " of '" << def.name << "' is " << length_s * gm.time_scale << " s, less than its dt_s = " << def.time.dt_s
        << " s";
    throw fq::InputError("", 0, "--window-length", why.str());
  }
  // (Also when it is not shorter: a sweep's --record may be longer than the
  // case's own record, and the option limits its window too.)
  gm.window_length_s = std::min(gm.window_length_s, length_s);
  // A quick look: a case that runs on after its motion (time.duration_s)
  // stops with the shortened motion too.
  if (def.time.duration_s) {
    const double simulated = def.ground_motion->window_length_s * def.ground_motion->time_scale;
    // The case's own window may be the shorter one, and shorter than a step
    // (a run of the case goes on to its duration_s): named here as the
    // option's doing, not as the case's duration_s, which was not the
    // mistake (review probe).
    if (simulated < def.time.dt_s) {
      std::ostringstream why;
      why << "expected at least one time step: with --window-length, '" << def.name
          << "' stops with its ground motion, whose window (window_length_s = " << gm.window_length_s
          << " record s at the time scale " << gm.time_scale << ") lasts " << simulated
          << " s, less than its dt_s = " << def.time.dt_s << " s";
      throw fq::InputError("", 0, "--window-length", why.str());
    }
    def.time.duration_s = std::min(*def.time.duration_s, simulated);
  }
}

// A case's window before --window-length shortened it, to tell what the
// option cut.
struct UnshortenedWindow {
  double window_length_s;
  std::optional<double> duration_s;
};

UnshortenedWindow unshortened_window(const fq::CaseDef& def) {
  return {def.ground_motion ? def.ground_motion->window_length_s : 0.0, def.time.duration_s};
}

// The part of its record a study's run applied, for the tables' notes.
struct WindowUse {
  std::string label;    // the case, or in a sweep the case and record
  double start_s;       // window start (record s)
  double applied_s;     // record seconds run
  double record_s;      // the shortest record's duration (record s)
  double unshortened_s; // record seconds the run would have applied without --window-length
  // time.duration_s ends the run before the window (and the record) end:
  // the run's simulated seconds then, else negative.
  double duration_limit_s = -1.0;
  bool cut() const { return applied_s < unshortened_s; }
};

// Record seconds of its ground motion a run applies: the window, cut by the
// end of the shortest record and by time.duration_s, as the run does.
double applied_window_s(const fq::GroundMotionDef& gm, double window_length_s,
                        const std::optional<double>& duration_s) {
  double w = window_length_s;
  for (const fq::GroundMotionComponentDef& c : gm.components)
    w = std::min(w, c.record.duration_s() - gm.window_start_s);
  if (duration_s) w = std::min(w, *duration_s / gm.time_scale);
  return w;
}

// `job_def` as it will run (shortened, records in place); `before` the
// case's own window.
WindowUse window_use(std::string label, const fq::CaseDef& job_def, const UnshortenedWindow& before) {
  const fq::GroundMotionDef& gm = *job_def.ground_motion;
  WindowUse u;
  u.label = std::move(label);
  u.start_s = gm.window_start_s;
  u.applied_s = applied_window_s(gm, gm.window_length_s, job_def.time.duration_s);
  u.unshortened_s = applied_window_s(gm, before.window_length_s, before.duration_s);
  // The duration, not the window or the record, ended the run (a review
  // probe's case ran 0.0063 of its 0.05 record seconds and was said to
  // have run its whole window, not cut by a 0.02 s option).
  if (job_def.time.duration_s && u.applied_s < applied_window_s(gm, gm.window_length_s, std::nullopt))
    u.duration_limit_s = *job_def.time.duration_s;
  u.record_s = std::numeric_limits<double>::infinity();
  for (const fq::GroundMotionComponentDef& c : gm.components) u.record_s = std::min(u.record_s, c.record.duration_s());
  return u;
}

std::string fixed(double x, int digits) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

// A run's input (a sweep's scale, a time step) in its shortest form that
// reads back as itself: in the runs' folder names ("_x0.5") and in the
// tables, unlike the measured values of csv_number (a step chosen to fall
// on the record's samples, 9.99052132701422e-06 s, read 9.99052133e-06
// with nine digits, and two scales differing in the tenth digit, which get
// folders of their own, would have shared a row key; black-box probe).
std::string exact_text(double x) {
  char digits[32];
  const auto end = std::to_chars(digits, digits + sizeof digits, x).ptr;
  return std::string(digits, end);
}

// What a case's ground motion applies, for comparison.md's note: each
// record by file name (`whole_paths`: by its whole path), its axis and
// amplitude scale, then the record seconds run and the time scale
// ("RSN1106_KOBE_KJM000.AT2 along x, record seconds 0 to 20 at time scale
// 0.3162"); "" without ground motion.
std::string ground_motion_text(const fq::CaseDef& def, bool whole_paths) {
  if (!def.ground_motion) return {};
  const fq::GroundMotionDef& gm = *def.ground_motion;
  auto axis = [](const fq::Vec3& d) -> std::string {
    // (Appended with +=: GCC 12 warns falsely of overlapping copies in a
    // chain of + on short strings.)
    const char* names[3] = {"x", "y", "z"};
    std::string name;
    for (int k = 0; k < 3; ++k)
      if (d[k] == 1.0 || d[k] == -1.0) {
        if (d[k] < 0.0) name += '-';
        name += names[k];
        return name;
      }
    name += '(';
    name += exact_text(d.x());
    name += ", ";
    name += exact_text(d.y());
    name += ", ";
    name += exact_text(d.z());
    name += ')';
    return name;
  };
  std::string text;
  for (const fq::GroundMotionComponentDef& c : gm.components) {
    if (!text.empty()) text += ", ";
    text += (whole_paths ? c.resolved_file.string() : c.resolved_file.filename().string()) + " along " +
            axis(c.direction);
    if (c.amplitude_scale != 1.0) text += " x " + exact_text(c.amplitude_scale);
  }
  const double applied_s = applied_window_s(gm, gm.window_length_s, def.time.duration_s);
  std::ostringstream window;
  window << std::setprecision(6) << ", record seconds " << gm.window_start_s << " to "
         << gm.window_start_s + applied_s;
  if (gm.time_scale != 1.0) window << " at time scale " << gm.time_scale;
  return text + window.str();
}

// A scale in the collapse table: two decimals where they read back as the
// scale ("0.50", as the table always printed the usual scales), else as
// given: two decimals alone printed 0.004 as 0.00, and 0.3333333 and
// 0.33333333 alike (workflow probe).
std::string table_scale_text(double scale) {
  const std::string two = fixed(scale, 2);
  double back = 0.0;
  const auto [end, ec] = std::from_chars(two.data(), two.data() + two.size(), back);
  return ec == std::errc() && end == two.data() + two.size() && back == scale ? two : exact_text(scale);
}

std::string scientific(double x) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  s << std::scientific << std::setprecision(1) << x;
  return s.str();
}

std::string csv_number(double x) {
  if (!std::isfinite(x)) return "";
  std::ostringstream s;
  s << std::setprecision(9) << x;
  return s.str();
}

// The headers of the csv tables, one definition for the writers and for
// is_our_csv_table, which recognises the tables by them. The integrator
// and time step columns (before the wall time, which they set) came with
// stop 40; a table of the form before them (`with_time_integration`
// false) is still ours to replace.
std::string comparison_csv_header(std::size_t storeys, bool with_time_integration = true) {
  std::ostringstream h;
  h << "case,status";
  for (std::size_t k = 1; k <= storeys; ++k)
    h << ",storey" << k << "_peak_drift_ratio_rad,storey" << k << "_peak_drift_ratio_x_rad,storey" << k
      << "_peak_drift_ratio_y_rad,storey" << k << "_verdict";
  h << ",first_joint_failure_s,broken_joints,joints,energy_balance_error_relative"
    << (with_time_integration ? ",integrator,dt_s" : "") << ",wall_s,output";
  return h.str();
}

std::string sweep_csv_header(std::size_t storeys, bool with_time_integration = true) {
  std::ostringstream h;
  h << "case,record,scale,pga_mps2,pga_g,status";
  for (std::size_t k = 1; k <= storeys; ++k) h << ",storey" << k << "_peak_drift_ratio_rad,storey" << k << "_verdict";
  h << ",collapsed,first_joint_failure_s,broken_joints,joints,energy_balance_error_relative"
    << (with_time_integration ? ",integrator,dt_s" : "") << ",wall_s,output";
  return h.str();
}

// A run's integrator and time step (s) as the tables give them: the
// case's own, which studies do not override.
std::string time_integration_csv(const fq::CaseDef& def) {
  return std::string(fq::integrator_name(def.time.integrator)) + "," + exact_text(def.time.dt_s);
}

const char* const kCollapseCsvHeader =
    "case,record,largest_scale_without_collapse,smallest_scale_with_collapse,pga_at_collapse_mps2,"
    "collapsed_storeys_at_that_scale,stood_above_collapse";
// The header before stood_above_collapse: an earlier study's table of that
// form is still ours to replace.
const char* const kCollapseCsvHeaderWithoutStoodAbove =
    "case,record,largest_scale_without_collapse,smallest_scale_with_collapse,pga_at_collapse_mps2,"
    "collapsed_storeys_at_that_scale";

// The line of a case's `name` key (0 when the name is the file's stem).
int name_line(const fq::CaseDef& def) {
  const auto it = def.section_line.find("name");
  return it == def.section_line.end() ? 0 : it->second;
}

// Loads every case; the first bad one ends the command (nothing is run).
std::vector<fq::CaseDef> load_cases(const std::vector<std::string>& files) {
  std::vector<fq::CaseDef> defs;
  for (const std::string& f : files) defs.push_back(fq::load_case_file(f));
  return defs;
}

// The checks a run makes at its start (integrator, stable time step unless
// --force), made for every case before any runs, so that exit code 2 means
// nothing was run.
void check_runnable(const fq::CaseDef& def, const StudyArgs& args) {
  fq::CaseRunOptions options;
  options.allow_unstable_time_step = args.force;
  fq::check_case_runnable(def, options);
}

// Exit codes of fq_plot.py (its header): the figure could not be written,
// having said why in one line naming the file; matplotlib is missing.
constexpr int kPlotWriteFailed = 3;
constexpr int kPlotNoMatplotlib = 4;
constexpr int kShellCommandNotFound = 127;  // the interpreter itself is missing

// Where the figure script may be when FQ_PLOT_SCRIPT does not say
// (find_plot_script): beside the program (scripts/plot/ under its folder or
// one or two folders up, as in a source tree whose build/apps/ holds it),
// then the source tree it was built from.
// Only the last was looked at (workflow probe: a copied binary next to its
// own scripts/plot/fq_plot.py failed, after all its runs).
std::vector<fs::path> plot_script_candidates() {
  std::vector<fs::path> c;
  std::error_code ec;
  const fs::path exe_dir = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (!ec && !exe_dir.empty())
    for (const fs::path& dir : {exe_dir, exe_dir.parent_path(), exe_dir.parent_path().parent_path()})
      c.push_back(dir / "scripts/plot/fq_plot.py");
  c.push_back(fs::path(FQ_SOURCE_DIR) / "scripts/plot/fq_plot.py");
  return c;
}

// The first candidate that is a file, or empty after saying which were tried.
fs::path find_plot_script() {
  // A script named by FQ_PLOT_SCRIPT must be there: falling back to
  // another copy without a word hid the mistake (new-features probe).
  if (const char* env = std::getenv("FQ_PLOT_SCRIPT"); env && *env) {
    std::error_code ec;
    if (fs::is_regular_file(env, ec)) return env;
    std::cerr << "framequake: error: FQ_PLOT_SCRIPT names '" << env
              << "', which is not a file; point it at fq_plot.py, unset it, or give --no-figure (nothing was run)\n";
    return {};
  }
  const std::vector<fs::path> candidates = plot_script_candidates();
  for (const fs::path& p : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(p, ec)) return p;
  }
  std::cerr << "framequake: error: the figure script fq_plot.py was not found (looked for";
  for (std::size_t k = 0; k < candidates.size(); ++k) std::cerr << (k ? ", " : " ") << candidates[k].string();
  std::cerr << "); set FQ_PLOT_SCRIPT to its path, or give --no-figure (nothing was run)\n";
  return {};
}

std::string plot_interpreter() {
  const char* python_env = std::getenv("FQ_PYTHON");
  return python_env && *python_env ? python_env : "/usr/bin/python3";
}

std::string shell_quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Whether the figure can be drawn: the script is there and its
// interpreter imports matplotlib (fq_plot.py --check). Asked before a
// study's first run; a missing interpreter or matplotlib was found only
// after every run (docs probe, 2026-11-27: FQ_PYTHON=/nonexistent ran the
// whole study, then exited 3), though the README promised the study would
// stop before its first run.
bool figure_can_be_drawn() {
  const fs::path script = find_plot_script();
  if (script.empty()) return false;
  const std::string command = shell_quoted(plot_interpreter()) + " " + shell_quoted(script.string()) + " --check";
  const int status = std::system((command + " > /dev/null").c_str());
  if (status == 0) return true;
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::cerr << "framequake: error: the figure cannot be drawn: " << command << " exited with status " << code;
  if (code == kPlotNoMatplotlib || code == kShellCommandNotFound)
    std::cerr << " (it needs Debian's python3 with python3-matplotlib: bash scripts/install_deps.sh; FQ_PYTHON "
                 "selects another interpreter)";
  std::cerr << "; give --no-figure to write the tables only (nothing was run)\n";
  return false;
}

int run_figure(const std::string& kind, const fs::path& folder, const char* file) {
  const std::string python = plot_interpreter();
  const fs::path script = find_plot_script();
  if (script.empty()) return kExitOutputFailed;
  const std::string command = shell_quoted(python) + " " + shell_quoted(script.string()) + " " + kind + " " +
                              shell_quoted(folder.string());
  const int status = std::system(command.c_str());
  if (status != 0) {
    // The script removes its temporary file itself; a script killed
    // outright cannot, and no failure may leave one.
    std::error_code ec;
    fs::remove(folder / (std::string(file) + ".tmp.png"), ec);
  }
  // Ctrl-C or SIGTERM while the figure is drawn reaches the plotting
  // process (system() lets the child take them): a stop on request, not a
  // missing matplotlib (CLI probe: a traceback, then exit 3).
  const bool stopped = (WIFSIGNALED(status) && (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM)) ||
                       (WIFEXITED(status) && (WEXITSTATUS(status) == 130 || WEXITSTATUS(status) == 143));
  if (stopped) {
    std::cerr << "framequake: the figure was not drawn: stopped on request. The tables are written.\n";
    return kExitInterrupted;
  }
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  if (status != 0 && code == kPlotWriteFailed) {
    // A full disk or an unwritable folder: the script's one line named the
    // file and the system's reason, all there is to say (a probe's full
    // disk was blamed on a missing matplotlib, under a traceback).
    return kExitOutputFailed;
  }
  if (status != 0 && (code == kPlotNoMatplotlib || code == kShellCommandNotFound)) {
    std::cerr << "framequake: error: the figure could not be drawn: " << command << " exited with status " << code
              << " (it needs Debian's python3 with python3-matplotlib: bash scripts/install_deps.sh; FQ_PYTHON "
                 "selects another interpreter). The tables are written.\n";
    return kExitOutputFailed;
  }
  if (status != 0) {
    std::cerr << "framequake: error: the figure could not be drawn: " << command << " exited with status " << code
              << " (its message is above). The tables are written.\n";
    return kExitOutputFailed;
  }
  // A script that ended well without writing the figure (another script
  // under FQ_PLOT_SCRIPT): the figure was announced all the same
  // (new-features probe).
  if (std::error_code ec; !fs::is_regular_file(folder / file, ec)) {
    std::cerr << "framequake: error: " << command << " ended without writing " << (folder / file).string()
              << ". The tables are written.\n";
    return kExitOutputFailed;
  }
  return kExitOk;
}

// A run's status for the tables: its own, or "not run" when Ctrl-C came
// before it started, or "failed" when it ended in an error.
std::string outcome_status(const fq::BatchOutcome& o) {
  if (o.ok) return fq::run_status_name(o.report.result.status);
  return o.exit_code == kExitInterrupted ? "not run" : "failed";
}

// The verdict in the csv tables: the bare name, or not_assessed for an
// unstable run (see verdict_text).
std::string verdict_csv(const fq::CaseRunReport& r, const fq::StoreyOutcome& s) {
  return r.result.status == fq::RunStatus::Unstable ? std::string("not_assessed")
                                                    : std::string(fq::storey_verdict_name(s.verdict));
}

int worst_exit(const std::vector<fq::BatchOutcome>& outcomes) {
  int code = kExitOk;
  auto rank = [](int c) { return c == 0 ? 0 : c == 130 ? 1 : c == 1 ? 2 : c == 3 ? 3 : c == 2 ? 4 : 5; };
  for (const fq::BatchOutcome& o : outcomes)
    if (rank(o.exit_code) > rank(code)) code = o.exit_code;
  return code;
}

// True once the study has warned that its folder's file system has no
// locks: its runs, on the same file system, do not say it again each.
bool g_said_no_locks = false;

// Warnings the study said once before its first run, which its runs would
// otherwise repeat each, after running (direction of a record).
// Keyed by the case's name and the warning: two cases may share a text
// (variants of one frame overlapping alike), and each is said for its case.
std::set<std::pair<std::string, std::string>> g_said_before_runs;

// The warnings that follow from a case and its record alone (a node no
// member ends at, a brace joined at one end, a record applied along a
// direction its header contradicts, bodies overlapping at the start...)
// hold for every run of that case and record: said once before the runs,
// not after each (workflow probe: the sweep ran first; review probe: a
// sweep of six scales said the same node warning six times). Runs differing
// only in their scale share one scene build.
void warn_before_runs(const std::vector<fq::BatchJob>& jobs) {
  std::set<std::string> built;
  for (const fq::BatchJob& job : jobs) {
    std::string key = job.def.name;
    for (const fq::GroundMotionComponentDef& c : job.def.ground_motion ? job.def.ground_motion->components
                                                                       : std::vector<fq::GroundMotionComponentDef>{})
      key.append("\n").append(c.resolved_file.string());
    if (!built.insert(key).second) continue;
    fq::Scene scene = fq::build_scene(job.def);
    std::vector<std::string> warnings = fq::case_warnings(job.def, scene);
    if (scene.contacts) {
      scene.simulation->initialize();  // step 0's forces: the contacts learn which pairs overlap at the start
      if (std::string w = fq::initial_overlap_warning(scene.contacts->initial_overlaps(), scene.simulation->bodies());
          !w.empty())
        warnings.push_back(std::move(w));
    }
    for (const std::string& w : warnings)
      if (g_said_before_runs.insert({job.def.name, w}).second)
        std::cerr << "framequake: warning: case " << job.def.name << ": " << w << "\n";
  }
}

void print_done(std::size_t, const fq::BatchJob& job, const fq::BatchOutcome& out, std::size_t done,
                std::size_t total) {
  std::ostringstream line;
  line << "[" << done << "/" << total << "] " << job.label << ": ";
  if (!out.ok) {
    // A run Ctrl-C kept from starting did not fail (CLI probe: "FAILED: not run").
    line << (out.exit_code == kExitInterrupted ? "" : "FAILED: ") << out.error;
  } else {
    const fq::CaseRunReport& r = out.report;
    line << fq::run_status_name(r.result.status) << ", t = " << fixed(r.result.simulated_s, 2) << " s in "
         << fixed(r.wall_s, 1) << " s wall";
    for (const fq::StoreyOutcome& s : r.storeys)
      line << "; storey " << s.number << " " << verdict_text(r, s) << " (peak "
           << fixed(s.drift.peak_ratio_rad, 3) << " rad)";
    for (const std::string& w : r.warnings)
      if (!(g_said_no_locks && fq::is_folder_lock_warning(w)) && !g_said_before_runs.count({job.def.name, w}))
        line << "\n  warning: " << w;
  }
  std::cerr << line.str() << "\n";
}

std::size_t max_storeys(const std::vector<fq::BatchOutcome>& outcomes) {
  std::size_t n = 0;
  for (const fq::BatchOutcome& o : outcomes)
    if (o.ok) n = std::max(n, o.report.storeys.size());
  return n;
}

bool write_text(const fs::path& file, const std::string& text) {
  try {
    fq::detail::write_file_atomically(file, text);
    return true;
  } catch (const std::exception& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return false;
  }
}

bool prepare_folder(const fs::path& out) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    std::cerr << "framequake: error: cannot create the output folder " << out.string() << ": " << ec.message()
              << "\n";
    return false;
  }
  return true;
}

// The records of a CSV text with RFC 4180 quoting (csv_text); nullopt when
// a quote is stray or left open, or the text does not end in a line end.
std::optional<std::vector<std::vector<std::string>>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false, was_quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c != '"') {
        field += c;
      } else if (i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else {
        quoted = false;
      }
    } else if (c == '"') {
      if (!field.empty() || was_quoted) return std::nullopt;  // a quote inside an unquoted field
      quoted = was_quoted = true;
    } else if (c == ',' || c == '\n') {
      row.push_back(std::move(field));
      field.clear();
      was_quoted = false;
      if (c == '\n') {
        rows.push_back(std::move(row));
        row.clear();
      }
    } else {
      if (was_quoted) return std::nullopt;  // text after a closing quote
      field += c;
    }
  }
  if (quoted || !field.empty() || was_quoted || !row.empty()) return std::nullopt;
  return rows;
}

// Whether `value` is what our tables write in the column `column`.
bool is_our_csv_field(const std::string& column, const std::string& value) {
  auto one_of = [&](std::initializer_list<const char*> names) {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return value == n; });
  };
  auto digits_only = [&](std::string_view also) {
    return std::all_of(value.begin(), value.end(),
                       [&](char c) { return (c >= '0' && c <= '9') || also.find(c) != std::string_view::npos; });
  };
  if (column == "case" || column == "record" || column == "output") return true;  // the user's names
  if (column == "status") return one_of({"completed", "stopped", "unstable", "failed", "not run"});
  if (column.ends_with("_verdict")) return one_of({"", "standing", "damaged", "collapsed", "not_assessed"});
  if (column == "collapsed") return one_of({"", "0", "1"});
  if (column == "integrator") {
    const std::vector<std::string> names = fq::integrator_names();
    return std::find(names.begin(), names.end(), value) != names.end();
  }
  if (column == "broken_joints" || column == "joints") return digits_only("");
  if (column == "collapsed_storeys_at_that_scale") return digits_only(" ");
  if (column == "stood_above_collapse") return digits_only(" .e+-");
  if (value.empty()) return true;  // csv_number of a value not known
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  return end == value.c_str() + value.size() && std::isfinite(v) && !std::isspace(static_cast<unsigned char>(value[0]));
}

// Whether `text` is the table `name` (comparison.csv, sweep.csv or
// collapse_scales.csv) as a study of ours wrote it: our header, for some
// number of storeys, and every row one of ours, field by field. A user's
// own table under the name, or ours with the user's rows added, is not.
bool is_our_csv_table(const std::string& name, const std::string& text) {
  const auto rows = parse_csv(text);
  if (!rows || rows->empty()) return false;
  const std::vector<std::string>& header = rows->front();
  // Our headers of this table's width: with the time integration columns
  // and without (the form before stop 40).
  std::vector<std::string> candidates;
  for (const bool with_time_integration : {true, false}) {
    const std::size_t extra = with_time_integration ? 2 : 0;
    if (name == "comparison.csv" && header.size() >= 8 + extra && (header.size() - 8 - extra) % 4 == 0)
      candidates.push_back(comparison_csv_header((header.size() - 8 - extra) / 4, with_time_integration));
    else if (name == "sweep.csv" && header.size() >= 13 + extra && (header.size() - 13 - extra) % 2 == 0)
      candidates.push_back(sweep_csv_header((header.size() - 13 - extra) / 2, with_time_integration));
  }
  if (name == "collapse_scales.csv")
    candidates.push_back(header.size() == 6 ? kCollapseCsvHeaderWithoutStoodAbove : kCollapseCsvHeader);
  const bool header_is_ours = std::any_of(candidates.begin(), candidates.end(), [&](const std::string& expected) {
    const auto expected_rows = parse_csv(expected + "\n");
    return expected_rows && expected_rows->front() == header;
  });
  if (!header_is_ours) return false;
  // Each run, or each case and record, once: a study never writes two rows
  // of one key, so a row copied and edited by hand makes the table the
  // user's (black-box probe: a duplicated row passed the field checks).
  std::vector<std::size_t> key_columns;
  for (std::size_t c = 0; c < header.size(); ++c)
    if (header[c] == "case" || header[c] == "record" || header[c] == "scale") key_columns.push_back(c);
  std::set<std::vector<std::string>> keys;
  for (std::size_t r = 1; r < rows->size(); ++r) {
    const std::vector<std::string>& row = (*rows)[r];
    if (row.size() != header.size()) return false;
    for (std::size_t c = 0; c < row.size(); ++c)
      if (!is_our_csv_field(header[c], row[c])) return false;
    std::vector<std::string> key;
    for (const std::size_t c : key_columns) key.push_back(row[c]);
    if (!keys.insert(key).second) return false;
  }
  return true;
}

// Whether the PNG `file` carries the mark fq_plot.py gives the figures it
// draws (figure_marker there): a tEXt chunk "Software" whose text begins
// "framequake fq_plot.py <its file name>;". Any matplotlib figure says
// "Matplotlib" in it, a user's own of the same name too (CLI probe: a
// user's first_storey_drift.png was deleted). A comparison figure drawn
// before the mark existed (stop 27) is recognised by the Description
// fq_plot.py gave it then, "<case> along <direction>" for each trace, so
// that the main job run again into its old out/compare is not refused
// (those since carry the mark; their Description is "<case>: |(x, y)|
// peaks ...").
bool is_legacy_comparison_description(const std::string& text) {
  if (text.empty()) return false;
  for (std::size_t from = 0; from <= text.size();) {
    const std::size_t end = std::min(text.find("; ", from), text.size());
    const std::string item = text.substr(from, end - from);
    const std::size_t along = item.find(" along ");
    if (along == std::string::npos || along == 0 || along + 7 >= item.size()) return false;
    from = end + 2;
  }
  return true;
}

bool is_our_figure(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  char signature[8];
  if (!in.read(signature, 8) || std::string(signature, 8) != std::string("\x89PNG\r\n\x1a\n", 8)) return false;
  const std::string mark = "framequake fq_plot.py " + file.filename().string() + ";";
  constexpr std::uint32_t kMaxText = 1 << 16;  // ours are short; a longer chunk is skipped, not read
  for (unsigned char head[8]; in.read(reinterpret_cast<char*>(head), 8);) {
    const std::uint32_t length = std::uint32_t(head[0]) << 24 | std::uint32_t(head[1]) << 16 |
                                 std::uint32_t(head[2]) << 8 | std::uint32_t(head[3]);
    const std::string type(reinterpret_cast<const char*>(head) + 4, 4);
    if (type == "IEND") break;
    if (type == "tEXt" && length <= kMaxText) {
      std::string data(length, '\0');
      if (!in.read(data.data(), std::streamsize(length))) break;
      if (data.rfind("Software", 0) == 0 && data.size() > 8 && data[8] == '\0' && data.compare(9, mark.size(), mark) == 0)
        return true;
      if (file.filename() == "first_storey_drift.png" && data.rfind("Description", 0) == 0 && data.size() > 11 &&
          data[11] == '\0' && is_legacy_comparison_description(data.substr(12)))
        return true;
      in.seekg(4, std::ios::cur);  // the CRC
    } else {
      in.seekg(std::streamoff(length) + 4, std::ios::cur);
    }
  }
  return false;
}

// Whether `file` is a table or figure a study of ours wrote: our csv tables
// by their header and rows (is_our_csv_table), our Markdown tables by their
// start "| case |", our figures by fq_plot.py's mark (is_our_figure). Only
// those are removed: a user's own notes named comparison.md were deleted by
// name (CLI probe).
bool is_earlier_study_file(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".png") return is_our_figure(file);
  // Our tables are a few hundred bytes a run; a larger file is not one.
  constexpr std::uintmax_t kMaxTable = std::uintmax_t(64) << 20;
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec || size > kMaxTable) return false;
  std::ifstream in(file, std::ios::binary);
  std::string text(size, '\0');
  if (!in.read(text.data(), std::streamsize(size))) return false;
  if (ext == ".csv") return is_our_csv_table(file.filename().string(), text);
  if (ext == ".md") return text.rfind("| case |", 0) == 0;
  return false;
}

// Removes the tables and figure an earlier study wrote into `out`, before
// any run starts: a study that then fails or is stopped must not leave a
// table of the earlier results beside its own runs' folders (a probe's
// failed compare left comparison.md saying "completed"). False, with the
// message printed, when one of them cannot be removed or is not ours
// (is_earlier_study_file). Every file is checked before any is removed: a
// study refused for one file that is not ours had already deleted the
// tables before it (workflow probe: a user's comparison.md refused, but
// comparison.csv gone), where the message says nothing was touched.
bool remove_earlier_tables(const fs::path& out, const std::vector<const char*>& names) {
  std::vector<fs::path> ours;
  for (const char* name : names) {
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(out / name, ec);
    if (!fs::exists(st)) continue;
    if (!fs::is_regular_file(st) || !is_earlier_study_file(out / name)) {
      std::cerr << "framequake: error: " << (out / name).string()
                << " is not a table or figure of an earlier framequake study; refusing to replace it: move it or "
                   "choose another --out (nothing was run)"
                // Figures drawn before the mark existed are not known as ours.
                << (fs::path(name).extension() == ".png" ? "; a figure of an older framequake, without "
                                                           "fq_plot.py's mark, is refused too"
                                                         : "")
                << "\n";
      return false;
    }
    ours.push_back(out / name);
  }
  for (const fs::path& file : ours) {
    std::error_code ec;
    fs::remove(file, ec);
    if (ec) {
      std::cerr << "framequake: error: cannot remove the earlier study's " << file.string() << ": " << ec.message()
                << "\n";
      return false;
    }
  }
  return true;
}

// Prepares the output folder, locks it into `lock` (held by the caller
// until its tables and figure are written: a second study, or a run or
// resume, into the same folder at the same time is refused instead of
// replacing this study's tables; io/folder_lock.h), removes the earlier
// study's `tables` and runs the jobs side by side, one line per finished
// run; false when the folder cannot be made, locked or cleared.
bool run_jobs(const StudyArgs& args, const std::vector<fq::BatchJob>& jobs, const std::atomic<bool>* stop_requested,
              const std::string& what, const std::vector<const char*>& tables, fq::FolderLock& lock,
              std::vector<fq::BatchOutcome>& outcomes) {
  // Every run's folder is checked before the first run starts, so that a
  // folder a run would refuse (a user's own files, a file in its place, a
  // run named like one of the tables) stops the study with nothing run.
  for (const fq::BatchJob& job : jobs) {
    const std::string folder_name = job.output_folder.filename().string();
    for (const char* table : tables)
      if (folder_name == table) {
        std::cerr << "framequake: error: the run '" << job.label << "' would write into " << job.output_folder.string()
                  << ", the name of one of the study's tables; rename the case\n";
        return false;
      }
    try {
      (void)fq::check_output_folder(job.output_folder);
    } catch (const std::exception& e) {
      std::cerr << "framequake: error: " << e.what() << " (run '" << job.label << "'; nothing was run)\n";
      return false;
    }
  }
  // A figure that cannot be drawn for want of its script, its interpreter
  // or matplotlib is said before any run, not after all of them.
  if (args.figure && !figure_can_be_drawn()) return false;
  if (!prepare_folder(args.out)) return false;
  try {
    lock = fq::FolderLock(args.out);
  } catch (const fq::OutputError& e) {
    std::cerr << "framequake: error: " << e.what() << " (nothing was run)\n";
    return false;
  }
  if (!lock.warning().empty()) {
    std::cerr << "framequake: warning: " << lock.warning() << "\n";
    g_said_no_locks = true;
  }
  if (!remove_earlier_tables(args.out, tables)) return false;
  fq::BatchOptions options;
  options.parallel_runs = args.jobs;
  options.allow_unstable_time_step = args.force;
  options.stop_requested = stop_requested;
  options.on_done = print_done;
  // A line every 10 s while runs go: a study of long runs said nothing
  // until the first one ended (CLI probe: 13.8 s of silence).
  options.progress_interval_s = 10.0;
  options.on_progress = [](const std::string& line) { std::cerr << "framequake: running " << line << "\n"; };
  warn_before_runs(jobs);
  std::cerr << "framequake: " << what << ", output in " << args.out.string() << "\n";
  outcomes = fq::run_batch(jobs, options);
  return true;
}

// The Markdown tables' note on --window-length ("" without it): what each
// run applied of its record, since `what` holds for that part only. A
// window not longer than the option is run whole, and the note says so (it
// said "cut to the first 100 record seconds" of a 6 s window; records
// probe).
std::string window_length_note(const StudyArgs& args, const std::vector<WindowUse>& uses, const char* what) {
  if (!args.window_length_s) return "";
  const double length_s = *args.window_length_s;
  std::ostringstream note;
  if (std::all_of(uses.begin(), uses.end(), [](const WindowUse& u) { return u.cut(); })) {
    note << "\nGround motion cut to the first " << length_s
         << " record seconds of each case's window (--window-length): " << what
         << " hold for that part of the record only.\n";
    return note.str();
  }
  note << "\nGround motion with --window-length " << length_s << " s:";
  for (const WindowUse& u : uses) {
    note << "\n- " << u.label << ": ";
    if (u.cut()) {
      note << "cut to the first " << length_s << " record seconds of its window; " << what
           << " hold for that part of the record only";
      continue;
    }
    if (u.duration_limit_s >= 0.0) {
      note << "not cut: its time.duration_s of " << u.duration_limit_s << " s ended the run after record seconds "
           << u.start_s << " to " << u.start_s + u.applied_s << " (" << u.applied_s << " s), before " << length_s
           << " s of its window";
      continue;
    }
    note << "not cut (its window is not longer than " << length_s << " s): it ran ";
    if (u.start_s == 0.0 && u.applied_s == u.record_s)
      note << "the whole record (" << u.applied_s << " s)";
    else
      note << "its whole window, record seconds " << u.start_s << " to " << u.start_s + u.applied_s << " ("
           << u.applied_s << " s)";
  }
  note << "\n";
  return note.str();
}

// Draws `kind`'s figure when asked and at least one run finished; the exit
// code folds in a figure failure only when the runs themselves succeeded.
int finish_with_figure(const StudyArgs& args, const std::vector<fq::BatchOutcome>& outcomes, const char* kind,
                       const char* file) {
  int code = worst_exit(outcomes);
  if (args.figure && std::any_of(outcomes.begin(), outcomes.end(), [](const auto& o) { return o.ok; })) {
    const int fig = run_figure(kind, args.out, file);
    if (fig == kExitOk)
      std::cout << "framequake: figure in " << (args.out / file).string() << "\n";
    else if (code == kExitOk)
      code = fig;
  }
  return code;
}

}  // namespace

int command_compare(int argc, char** argv, const std::atomic<bool>* stop_requested) {
  const StudyArgs args = parse_study_args(argc, argv, kCompareHelp, false);
  std::vector<fq::BatchJob> jobs;
  std::vector<WindowUse> window_uses;  // with --window-length: what each case runs of its record
  try {
    std::vector<fq::CaseDef> defs = load_cases(args.cases);
    std::set<std::string> names;
    for (fq::CaseDef& def : defs) {
      if (!names.insert(def.name).second)
        throw fq::InputError(def.source_file.string(), name_line(def), "name",
                             "two cases are named '" + def.name + "'; each case needs its own output folder");
      const UnshortenedWindow before = unshortened_window(def);
      if (args.window_length_s) shorten_window(def, *args.window_length_s);
      check_runnable(def, args);
      if (args.window_length_s) window_uses.push_back(window_use(def.name, def, before));
      fq::BatchJob job;
      job.label = def.name;
      job.output_folder = args.out / def.name;
      job.def = std::move(def);
      jobs.push_back(std::move(job));
    }
  } catch (const fq::InputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  }
  fq::FolderLock lock;  // held until the figure is drawn
  std::vector<fq::BatchOutcome> outcomes;
  if (!run_jobs(args, jobs, stop_requested, "comparing " + std::to_string(jobs.size()) + " case(s)",
                {"comparison.csv", "comparison.md", "first_storey_drift.png"}, lock, outcomes))
    return kExitOutputFailed;

  const std::size_t storeys = max_storeys(outcomes);
  std::ostringstream csv, md;
  csv << comparison_csv_header(storeys) << "\n";
  md << "| case | status";
  for (std::size_t k = 1; k <= storeys; ++k) md << " | storey " << k << " peak drift ratio (rad)";
  for (std::size_t k = 1; k <= storeys; ++k) md << " | storey " << k;
  md << " | first joint failure (s) | broken joints | energy balance error | wall time (s) |\n|---|---";
  for (std::size_t k = 0; k < 2 * storeys; ++k) md << "|---";
  md << "|---|---|---|---|\n";
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const fq::BatchOutcome& o = outcomes[i];
    const std::string status = outcome_status(o);
    csv << fq::csv_text(jobs[i].label) << "," << status;
    md << "| " << jobs[i].label << " | " << status;
    for (std::size_t k = 0; k < storeys; ++k) {
      if (o.ok && k < o.report.storeys.size()) {
        const fq::StoreyOutcome& s = o.report.storeys[k];
        csv << "," << csv_number(s.drift.peak_ratio_rad) << "," << csv_number(s.drift.peak_ratio_x_rad) << ","
            << csv_number(s.drift.peak_ratio_y_rad) << "," << verdict_csv(o.report, s);
        md << " | " << fixed(s.drift.peak_ratio_rad, 4);
      } else {
        csv << ",,,,";
        md << " | -";
      }
    }
    for (std::size_t k = 0; k < storeys; ++k)
      md << " | " << (o.ok && k < o.report.storeys.size() ? verdict_text(o.report, o.report.storeys[k]) : "-");
    if (o.ok) {
      const fq::CaseRunReport& r = o.report;
      csv << "," << csv_number(r.first_joint_failure_time_s) << "," << r.joints.broken << "," << r.joint_count << ","
          << csv_number(r.energy_balance_error_relative) << "," << time_integration_csv(jobs[i].def) << ","
          << csv_number(r.wall_s) << "," << fq::csv_text(r.output_folder.string()) << "\n";
      md << " | " << fixed(r.first_joint_failure_time_s, 3) << " | " << r.joints.broken << " / " << r.joint_count
         << " | " << scientific(r.energy_balance_error_relative) << " | " << fixed(r.wall_s, 1) << " |\n";
    } else {
      // first_joint_failure_s .. energy_balance_error_relative, wall_s and
      // output empty; the integrator and time step are the case's.
      csv << ",,,,," << time_integration_csv(jobs[i].def) << ",,\n";
      md << " | - | - | - | - |\n";
    }
  }
  // The limits of each case: one sentence when they all share them, else
  // one per case (the first case's limits were given for all, contradicting
  // the rows of a case with its own; workflow probe).
  std::vector<std::size_t> assessed;
  for (std::size_t i = 0; i < outcomes.size(); ++i)
    if (outcomes[i].ok) assessed.push_back(i);
  if (!assessed.empty()) {
    // Six significant digits, and limits compared exactly: two limits
    // that printed alike at four decimals were merged while one row said
    // damaged and the other standing at the same printed peak
    // (new-features probe).
    auto limits_text = [](const fq::AssessmentDef& a) {
      std::ostringstream t;
      t << std::setprecision(6) << "collapsed = peak storey drift ratio >= " << a.collapse_drift_ratio_rad
        << " rad, damaged = above " << a.safety_drift_ratio_rad << " rad, standing otherwise";
      return t.str();
    };
    const fq::AssessmentDef& a0 = outcomes[assessed.front()].report.assessment;
    const std::string first = limits_text(a0);
    const bool shared = std::all_of(assessed.begin(), assessed.end(), [&](std::size_t i) {
      const fq::AssessmentDef& a = outcomes[i].report.assessment;
      return a.safety_drift_ratio_rad == a0.safety_drift_ratio_rad &&
             a.collapse_drift_ratio_rad == a0.collapse_drift_ratio_rad;
    });
    md << "\nVerdicts: ";
    if (shared) {
      md << first;
    } else {
      for (std::size_t k = 0; k < assessed.size(); ++k)
        md << (k ? "; " : "") << jobs[assessed[k]].label << ": " << limits_text(outcomes[assessed[k]].report.assessment);
    }
    md << " (cases/README.md, `assessment`). Drift ratios are magnitudes of the x-y drift vector over the storey "
          "height (given in rad as is usual; a storey whose columns lie flat reaches 1, the sine of their tilt); "
          "times are simulated seconds.\n";
    // Where each frame first failed: the weak point a retrofit should
    // address (workflow probe), with the joint's name as events.csv and the
    // frames give it, which a case's joint numbering does not keep.
    std::string firsts;
    for (std::size_t i : assessed) {
      const fq::CaseRunReport& r = outcomes[i].report;
      if (r.first_joint_failure.empty()) continue;
      firsts += "\n- " + jobs[i].label + ": " + r.first_joint_failure;
      if (!r.first_joint_failure_name.empty()) firsts += ", joint " + r.first_joint_failure_name;
      firsts += first_failure_outcome(r, [](double t_s) { return fixed(t_s, 3); });
      // A blow-up tears joints apart: not a weak point (error probe).
      if (r.result.status == fq::RunStatus::Unstable)
        firsts += " (the run became unstable: this may be the blow-up's doing)";
    }
    if (!firsts.empty()) md << "\nFirst joint to fail:" << firsts << "\n";
    std::vector<LabelledReport> labelled;
    for (std::size_t i = 0; i < jobs.size(); ++i)
      labelled.emplace_back(jobs[i].label, outcomes[i].ok ? &outcomes[i].report : nullptr);
    std::vector<LabelledContactModel> contact_models;
    for (const fq::BatchJob& job : jobs)
      contact_models.emplace_back(job.label,
                                  job.def.contact ? fq::intact_node_contact_name(job.def.contact->intact_nodes) : "");
    std::vector<CaseTimeIntegration> time_integration;
    for (const fq::BatchJob& job : jobs)
      time_integration.push_back({job.label, fq::integrator_name(job.def.time.integrator), job.def.time.dt_s});
    std::vector<CaseGroundMotion> motions;
    for (std::size_t i = 0; i < jobs.size(); ++i)
      motions.push_back({jobs[i].label, ground_motion_text(jobs[i].def, false), ground_motion_text(jobs[i].def, true),
                         outcomes[i].ok && outcomes[i].report.result.status == fq::RunStatus::Completed
                             ? outcomes[i].report.peak_ground_acceleration_mps2
                             : std::numeric_limits<double>::quiet_NaN()});
    md << ground_motion_note(motions) << time_integration_note(time_integration) << contact_model_note(contact_models)
       << collapse_order_note(labelled) << warnings_note(labelled);
    // A shortened window can miss the record's strongest part, and with
    // it a verdict (workflow probe: B standing at --window-length 8,
    // damaged over its whole window).
    md << window_length_note(args, window_uses, "the verdicts");
  }
  // Under a heading of their own, as sweep's (a line after the warnings
  // read as one of them; studies probe).
  // A run stopped by Ctrl-C or gone unstable ran but did not finish either
  // (input probe, stop 41: a stopped run was missing from this list).
  std::string not_finished;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    if (!outcomes[i].ok) {
      not_finished += "\n- " + jobs[i].label + ": " + outcomes[i].error;
      continue;
    }
    const fq::RunResult& run = outcomes[i].report.result;
    if (run.status == fq::RunStatus::Completed) continue;
    not_finished += "\n- " + jobs[i].label + ": " + fq::run_status_name(run.status) + " at t = " +
                    fixed(run.simulated_s, 3) + " s" +
                    (run.status == fq::RunStatus::Stopped ? " (its row's figures are those up to then)"
                                                          : " (not assessed)");
  }
  if (!not_finished.empty()) md << "\nRuns that did not finish:" << not_finished << "\n";

  if (!write_text(args.out / "comparison.csv", csv.str()) || !write_text(args.out / "comparison.md", md.str()))
    return kExitOutputFailed;
  std::cout << md.str();
  std::cout << "framequake: table in " << (args.out / "comparison.md").string() << " and comparison.csv\n";
  return finish_with_figure(args, outcomes, "compare", "first_storey_drift.png");
}

int command_sweep(int argc, char** argv, const std::atomic<bool>* stop_requested) {
  const StudyArgs args = parse_study_args(argc, argv, kSweepHelp, true);
  std::vector<fq::BatchJob> jobs;
  struct JobKey {
    std::string case_name, record;
    double scale;
  };
  std::vector<JobKey> keys;
  std::vector<std::string> case_order, record_order;
  std::vector<WindowUse> window_uses;  // with --window-length: what each case runs of each record
  std::string record_cuts;             // windows a --record's end cut, a line each
  try {
    std::vector<fq::CaseDef> defs = load_cases(args.cases);
    std::vector<fq::AccelerationRecord> records;
    for (const std::string& r : args.records) {
      try {
        records.push_back(fq::read_peer_at2(r));
      } catch (const fq::InputError& e) {
        // A two-column file read as a PEER record fails on its header, which
        // did not say that --record reads PEER files only (studies probe).
        throw fq::InputError(e.file(), e.line(), e.field(),
                             e.message() + " (--record reads PEER .AT2 records; a record in another format goes "
                                           "in the case file, ground_motion.components)");
      }
    }
    // Runs are named by the record's file name: two records of one name
    // would write into one folder.
    for (std::size_t i = 0; i < args.records.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (fs::path(args.records[i]).stem() == fs::path(args.records[j]).stem())
          throw fq::InputError(args.records[i], 0, "--record",
                               "has the file name of '" + args.records[j] +
                                   "', and a sweep names its runs by it; copy one of them under another name");
    std::set<std::string> names;
    for (fq::CaseDef& def : defs) {
      if (!names.insert(def.name).second)
        throw fq::InputError(def.source_file.string(), name_line(def), "name",
                             "two cases are named '" + def.name + "'; each case needs its own output folders");
      if (!def.ground_motion)
        throw fq::InputError(def.source_file.string(), 0, "ground_motion", "a sweep needs a case with a ground motion");
      const UnshortenedWindow before = unshortened_window(def);
      if (args.window_length_s) shorten_window(def, *args.window_length_s, records.empty());
      check_runnable(def, args);
      case_order.push_back(def.name);
      // Variants of the motion: the case's own record, or each --record.
      std::vector<std::pair<std::string, fq::CaseDef>> variants;
      if (records.empty()) {
        variants.emplace_back(fs::path(def.ground_motion->components.front().file).stem().string(), def);
      } else {
        if (def.ground_motion->components.size() != 1)
          throw fq::InputError(def.source_file.string(), 0, "ground_motion.components",
                               "--record replaces the record of a case with exactly one component; this case has " +
                                   std::to_string(def.ground_motion->components.size()));
        for (std::size_t r = 0; r < records.size(); ++r) {
          fq::CaseDef v = def;
          fq::GroundMotionDef& gm = *v.ground_motion;
          fq::GroundMotionComponentDef& c = gm.components.front();
          c.record = records[r];
          c.file = args.records[r];
          c.resolved_file = args.records[r];
          c.format = fq::RecordFormat::PeerAt2;
          if (gm.window_start_s >= c.record.duration_s()) {
            const auto line = def.section_line.find("ground_motion");
            throw fq::InputError(def.source_file.string(), line == def.section_line.end() ? 0 : line->second,
                                 "ground_motion.window_start_s",
                                 "the window starts at " + std::to_string(gm.window_start_s) +
                                     " s, after the end of --record " + args.records[r] + " (" +
                                     std::to_string(c.record.duration_s()) + " s)");
          }
          // The case's window (its own record's) cut by this record's end:
          // said under the tables, since this record's runs then cover less
          // of the shaking than the others' (workflow probe: 1.98 of a 4 s
          // window ran, said only in summary.json).
          const double case_window_s = gm.window_length_s;
          gm.window_length_s = std::min(gm.window_length_s, c.record.duration_s() - gm.window_start_s);
          if (std::isfinite(case_window_s) && gm.window_length_s < case_window_s) {
            std::ostringstream cut;
            cut << "\n- " << def.name << " with " << fs::path(args.records[r]).filename().string() << ": the record ends "
                << c.record.duration_s() << " s in, so the window from " << gm.window_start_s << " s ran "
                << gm.window_length_s << " record seconds of the " << case_window_s << " s asked for";
            record_cuts += cut.str();
          }
          // A case that runs for its window (no duration_s) would run for
          // less than a step: refused here, before any run, naming the
          // record (review probe: it ended the sweep as an internal error,
          // exit 4, after the other runs had started).
          if (!v.time.duration_s && gm.window_length_s * gm.time_scale < v.time.dt_s) {
            std::ostringstream why;
            why << "expected at least one time step: with this record, '" << def.name << "' runs for its window of "
                << gm.window_length_s << " record s at the time scale " << gm.time_scale << ", "
                << gm.window_length_s * gm.time_scale << " s, less than its dt_s = " << v.time.dt_s
                << " s (the record ends " << c.record.duration_s() << " s in)";
            throw fq::InputError(args.records[r], 0, "--record", why.str());
          }
          variants.emplace_back(fs::path(args.records[r]).stem().string(), std::move(v));
        }
      }
      for (auto& [record_name, variant] : variants) {
        if (std::find(record_order.begin(), record_order.end(), record_name) == record_order.end())
          record_order.push_back(record_name);
        if (args.window_length_s) {
          window_uses.push_back(window_use(def.name + ", record " + record_name, variant, before));
          // shorten_window's note spoke of the case's own record, not this one.
          if (!records.empty() && !window_uses.back().cut())
            std::cerr << "framequake: note: --window-length " << *args.window_length_s
                      << " s is not shorter than the window of '" << def.name << "' with --record " << record_name
                      << " (" << window_uses.back().applied_s << " record s); its whole window is used\n";
        }
        for (double scale : args.scales) {
          fq::BatchJob job;
          job.def = variant;
          for (fq::GroundMotionComponentDef& c : job.def.ground_motion->components) {
            c.amplitude_scale *= scale;
            // Refused before any run, as the case file refuses such an
            // amplitude_scale (io/accelerogram.h).
            if (const std::string why = fq::scaled_record_problem(c.record, c.amplitude_scale); !why.empty())
              throw fq::InputError(def.source_file.string(), 0, "--scales",
                                   "'" + def.name + "' with " + fs::path(c.resolved_file).filename().string() + ": " + why);
          }
          // The scale in its shortest form that reads back as itself:
          // scales that differ in the 7th digit get folders of their own.
          job.label = def.name + "_" + record_name + "_x" + exact_text(scale);
          job.output_folder = args.out / job.label;
          jobs.push_back(std::move(job));
          keys.push_back({def.name, record_name, scale});
        }
      }
    }
  } catch (const fq::InputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  }
  {
    // Every run needs a folder of its own (a case named like another's
    // case and record, "a_b" + "c" and "a" + "b_c", would share one).
    std::set<fs::path> folders;
    for (const fq::BatchJob& job : jobs)
      if (!folders.insert(job.output_folder).second) {
        std::cerr << "framequake: error: two runs of the sweep would write into " << job.output_folder.string()
                  << "; rename a case or a record\n";
        return kExitBadInput;
      }
  }
  fq::FolderLock lock;  // held until the figure is drawn
  std::vector<fq::BatchOutcome> outcomes;
  if (!run_jobs(args, jobs, stop_requested, "sweep of " + std::to_string(jobs.size()) + " run(s)",
                {"sweep.csv", "collapse_scales.csv", "collapse_scales.md", "sweep.png"}, lock, outcomes))
    return kExitOutputFailed;

  const std::size_t storeys = max_storeys(outcomes);
  std::ostringstream csv;
  csv << sweep_csv_header(storeys) << "\n";
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const fq::BatchOutcome& o = outcomes[i];
    csv << fq::csv_text(keys[i].case_name) << "," << fq::csv_text(keys[i].record) << "," << exact_text(keys[i].scale)
        << ",";
    if (!o.ok) {
      csv << ",," << outcome_status(o);
      for (std::size_t k = 0; k < storeys; ++k) csv << ",,";
      // collapsed .. energy_balance_error_relative, wall_s and output empty.
      csv << ",,,,,," << time_integration_csv(jobs[i].def) << ",,\n";
      continue;
    }
    const fq::CaseRunReport& r = o.report;
    bool collapsed = false;
    csv << csv_number(r.peak_ground_acceleration_mps2) << ","
        << csv_number(r.peak_ground_acceleration_mps2 / fq::kStandardGravity_mps2) << ","
        << fq::run_status_name(r.result.status);
    for (std::size_t k = 0; k < storeys; ++k) {
      if (k < r.storeys.size()) {
        csv << "," << csv_number(r.storeys[k].drift.peak_ratio_rad) << "," << verdict_csv(r, r.storeys[k]);
        collapsed = collapsed || r.storeys[k].verdict == fq::StoreyVerdict::Collapsed;
      } else {
        csv << ",,";
      }
    }
    // Empty for an unstable run: not assessed (verdict_text).
    csv << "," << (r.result.status == fq::RunStatus::Unstable ? "" : collapsed ? "1" : "0") << ","
        << csv_number(r.first_joint_failure_time_s) << "," << r.joints.broken
        << "," << r.joint_count << "," << csv_number(r.energy_balance_error_relative) << ","
        << time_integration_csv(jobs[i].def) << "," << csv_number(r.wall_s) << "," << fq::csv_text(r.output_folder.string())
        << "\n";
  }

  // Collapse scale per case and record: the smallest scale with a collapsed
  // storey, and the largest scale below it that stood, from the runs that
  // completed: a run stopped by Ctrl-C did not see the whole motion, and an
  // unstable one says nothing about the structure (both are listed under
  // the table).
  std::ostringstream cs, md;
  cs << kCollapseCsvHeader << "\n";
  // PGA in m/s² and in g: the figure's axis is in g (workflow probe).
  md << "| case | record | largest scale without collapse | smallest scale with collapse | PGA there (m/s², g) | "
        "storeys collapsed there |\n|---|---|---|---|---|---|\n";
  std::string not_monotonic;
  for (const std::string& record : record_order)
    for (const std::string& name : case_order) {
      bool ran = false;
      std::vector<ScaleRun> completed;
      for (std::size_t i = 0; i < jobs.size(); ++i) {
        if (keys[i].case_name != name || keys[i].record != record) continue;
        ran = true;
        if (!outcomes[i].ok) continue;
        const fq::CaseRunReport& r = outcomes[i].report;
        if (r.result.status != fq::RunStatus::Completed) continue;
        ScaleRun run{keys[i].scale, r.peak_ground_acceleration_mps2, ""};
        for (const fq::StoreyOutcome& s : r.storeys)
          if (s.verdict == fq::StoreyVerdict::Collapsed)
            run.collapsed_storeys += (run.collapsed_storeys.empty() ? "" : " ") + std::to_string(s.number);
        completed.push_back(std::move(run));
      }
      if (!ran) continue;
      const CollapseBracket b = bracket_collapse(std::move(completed));
      const double stood = b.largest_stood, fell = b.smallest_collapse, pga = b.pga_at_collapse_mps2,
                   largest_completed = b.largest_completed;
      const std::string& which = b.storeys_at_collapse;
      cs << fq::csv_text(name) << "," << fq::csv_text(record) << "," << csv_number(stood) << "," << csv_number(fell)
         << "," << csv_number(pga) << "," << which << "," << stood_above_collapse_csv(b) << "\n";
      md << "| " << name << " | " << record << " | "
         << (std::isnan(largest_completed) ? std::string("-") : std::isnan(stood) ? std::string("none") : table_scale_text(stood))
         << " | "
         << (!std::isnan(fell)                ? table_scale_text(fell) + (b.stood_above_collapse.empty() ? "" : " (not monotonic)")
             : std::isnan(largest_completed) ? std::string("no run completed")
                                             : "none up to " + table_scale_text(largest_completed))
         << " | " << (std::isnan(pga) ? std::string("-") : fixed(pga, 2) + " (" + fixed(pga / fq::kStandardGravity_mps2, 3) + " g)")
         << " | " << (which.empty() ? "-" : which) << " |\n";
      if (const std::string note = non_monotonic_note(name, record, b); !note.empty()) not_monotonic += "\n" + note;
    }
  // A scale that stood above the smallest collapse: the pair of columns
  // would read as a threshold (acceptance probe).
  if (!not_monotonic.empty())
    md << "\nNot monotonic (a larger scale stood after a smaller one collapsed):" << not_monotonic << "\n";
  {
    std::string skipped;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      const fq::BatchOutcome& o = outcomes[i];
      if (o.ok && o.report.result.status == fq::RunStatus::Completed) continue;
      skipped += "\n- " + jobs[i].label + ": " +
                 (o.ok ? std::string(fq::run_status_name(o.report.result.status)) : o.error);
    }
    if (!skipped.empty()) md << "\nNot counted above (the run did not complete):" << skipped << "\n";
  }
  {
    // The PGA columns are horizontal peaks: a vertical record alone gives 0
    // at every scale (input probe, stop 41); said, and the figure is drawn
    // against the scale.
    std::vector<std::string> vertical_only;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      const fq::BatchOutcome& o = outcomes[i];
      if (!o.ok || o.report.result.status != fq::RunStatus::Completed || o.report.peak_ground_acceleration_mps2 > 0.0)
        continue;
      const std::string label = keys[i].case_name + ", record " + keys[i].record;
      if (std::find(vertical_only.begin(), vertical_only.end(), label) == vertical_only.end())
        vertical_only.push_back(label);
    }
    if (!vertical_only.empty()) {
      md << "\nNo horizontal ground motion (PGA, here and in sweep.csv, is the horizontal peak, 0 for these; "
            "sweep.png draws them against the amplitude scale):";
      for (const std::string& label : vertical_only) md << "\n- " << label;
      md << "\n";
    }
  }
  if (!record_cuts.empty())
    md << "\nWindows cut by a --record's end (each such run applied less of the shaking than the case's window "
          "asks for; the collapse scales hold for that part):"
       << record_cuts << "\n";
  md << window_length_note(args, window_uses, "the collapse scales");
  if (!write_text(args.out / "sweep.csv", csv.str()) || !write_text(args.out / "collapse_scales.csv", cs.str()) ||
      !write_text(args.out / "collapse_scales.md", md.str()))
    return kExitOutputFailed;
  std::cout << md.str();
  std::cout << "framequake: tables in " << (args.out / "sweep.csv").string() << " and collapse_scales.md\n";
  return finish_with_figure(args, outcomes, "sweep", "sweep.png");
}

const char* compare_help() { return kCompareHelp; }
const char* sweep_help() { return kSweepHelp; }

}  // namespace fq_app
