// framequake command line.
//
//   framequake run CASE [--out DIR] [--quiet] [--force] [--threads N] [--integrator NAME]
//                       [--checkpoint-every S]
//   framequake resume DIR [--quiet] [--threads N]
//   framequake info CASE [--integrator NAME] [--joints]
//   framequake compare CASE... [--out DIR] [--jobs N] [--window-length S]
//   framequake sweep CASE... [--scales LIST] [--record FILE]... [--out DIR]
//   framequake render OUT_DIR [--compare ...]   (render/render_command.h)
//   framequake --help | --version
//
// Exit codes: 0 run completed; 1 the run became unstable (output kept up to
// the last good frame); 2 bad input or usage (nothing written); 3 output
// could not be written (summary.json, where the disk allows it, says
// output_failed); 130 interrupted by SIGINT, 143 by SIGTERM, 129 by SIGHUP (final frame
// and summary written).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dem_core/lane_isa.h"
#include "fq_config.h"
#include "io/case_file.h"
#include "io/checkpoint.h"
#include "io/case_runner.h"
#include "io/input_error.h"
#include "io/name_hint.h"
#include "option_number.h"
#include "progress_display.h"
#include "run_outcome.h"
#include "study_commands.h"
#include "usage_error.h"
#include "render/render_command.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace {

constexpr int kExitOk = 0;
constexpr int kExitUnstable = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitOutputFailed = 3;
constexpr int kExitInterrupted = 130;  // 128 + SIGINT; a SIGTERM ends with 143

std::atomic<bool> g_stop_requested{false};
// The first stop signal received (SIGINT, SIGTERM or SIGHUP), for the exit code.
std::atomic<int> g_stop_signal{0};

extern "C" void on_stop_signal(int signal_number) {
  int none = 0;
  g_stop_signal.compare_exchange_strong(none, signal_number);
  g_stop_requested.store(true);
}

// Ctrl-C (SIGINT), a polite kill (SIGTERM: `kill`, `timeout`, a batch
// scheduler at its time limit) and a closed terminal or SSH session
// (SIGHUP, whose default action ended a run with no summary and no final
// frame: CLI probe) all stop a run at the end of its step, with its final
// frame and summary written.
void install_stop_handlers() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  std::signal(SIGHUP, on_stop_signal);
}

// The exit code of an interrupted run: 128 + the signal's number, as a
// shell reports a process the signal ended (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP).
int interrupted_exit_code() {
  const int s = g_stop_signal.load();
  return s > 0 ? 128 + s : kExitInterrupted;
}

const char* kMainHelp =
    "framequake - discrete-element simulation of wooden frames in earthquakes\n"
    "\n"
    "Usage:\n"
    "  framequake run CASE [options]   run a case file, write VTK frames, history and summary\n"
    "  framequake resume DIR           continue a run from DIR/checkpoint.bin (run --checkpoint-every)\n"
    "  framequake info CASE            describe a case: bodies, mass, joints, storeys, time step, output plan\n"
    "  framequake compare CASE...      run cases side by side; table of storey drifts and verdicts, figure\n"
    "  framequake sweep CASE...        run cases over amplitude scales (and records); collapse scales, figure\n"
    "  framequake render OUT_DIR       animate a finished run (GIF/MP4, PNG frames); --compare for several\n"
    "  framequake --help               this text;  framequake COMMAND --help (or help COMMAND) for a command\n"
    "  framequake --version            print the version\n"
    "\n"
    "Options may also be written --option=value; \"--\" ends the options (for a file\n"
    "whose name starts with '-').\n"
    "\n"
    "Case files are YAML; cases/README.md documents every key and its unit.\n";

const char* kRunHelp =
    "Usage: framequake run CASE [options]\n"
    "\n"
    "Runs the case and writes into the output folder:\n"
    "  case.pvd, frames/frame_NNNNNN.vtu   time series for ParaView\n"
    "  history.csv                         time histories (units in headers)\n"
    "  events.csv                          yields, deletions, breaks\n"
    "  summary.json                        status, energy balance, timing\n"
    "\n"
    "Options:\n"
    "  --out DIR      output folder (default: output.folder of the case, else out/<case name>)\n"
    "  --quiet        no progress display\n"
    "  --force        run even if dt_s exceeds the estimated stable time step\n"
    "  --threads N    OpenMP threads (default: OMP_NUM_THREADS or all cores)\n"
    "  --integrator NAME  time integrator, overrides time.integrator: central_difference (default),\n"
    "                 velocity_verlet, symplectic_euler, rk4, forward_euler, gsl_rk8pd\n"
    "  --checkpoint-every S\n"
    "                 write DIR/checkpoint.bin every S simulated seconds and when\n"
    "                 stopped, so `framequake resume DIR` can continue the run\n"
    "                 (central_difference only)\n"
    "  --help         this text\n"
    "Every option also takes the form --option=value.\n"
    "\n"
    "Exit codes: 0 completed, 1 unstable, 2 bad input, 3 output failed, 130 interrupted\n"
    "(Ctrl-C), 143 stopped by SIGTERM, 129 by SIGHUP (terminal closed).\n";

const char* kResumeHelp =
    "Usage: framequake resume DIR [options]\n"
    "\n"
    "Continues the run whose output folder DIR holds checkpoint.bin (written by\n"
    "`framequake run CASE --checkpoint-every S`, e.g. after the run was killed or\n"
    "stopped). The case file named in the checkpoint is loaded again and must be\n"
    "unchanged (as must its ground-motion records). The run continues exactly as\n"
    "it would have without the interruption (bitwise the same state): history.csv\n"
    "and events.csv are cut back to the checkpoint and continued, frames after\n"
    "it are written again, summary.json is written at the end, and checkpoints\n"
    "continue at the same interval.\n"
    "\n"
    "Options:\n"
    "  --case FILE    the case file's place now, if it was moved (with its records)\n"
    "                 since the run began; it must be unchanged\n"
    "  --quiet        no progress display\n"
    "  --threads N    OpenMP threads (results do not depend on it)\n"
    "  --help         this text\n"
    "\n"
    "Exit codes as for run; 2 also when the checkpoint is missing, damaged,\n"
    "truncated, of another format version, or the case changed since, and when\n"
    "the run had completed (nothing to resume); 3 also when its events.csv has\n"
    "the columns of an earlier framequake.\n";

const char* kInfoHelp =
    "Usage: framequake info CASE [--integrator NAME] [--joints]\n"
    "\n"
    "Loads and checks the case without running it, and prints the bodies, total\n"
    "mass, joints, storeys (over which drifts and verdicts are taken), time step\n"
    "and its stable limit, duration, ground motion and output plan, and warns as run\n"
    "does of a node lying inside or on a member without being one of its ends, of end\n"
    "nodes a few mm apart that are not one node, of members no joint holds, of members\n"
    "1000 times longer than thick (coordinates in mm?), of a record applied along the\n"
    "wrong kind of axis and of bodies overlapping at the start. Each reason run would\n"
    "refuse the case (an integrator the scene's laws cannot serve, a time step above\n"
    "the stable limit without --force) is one line of the description; the exit code\n"
    "is 0 whenever the case could be described.\n"
    "\n"
    "Options:\n"
    "  --integrator NAME  describe the case as `run --integrator NAME` would run it\n"
    "                 (its stable limit, whether run would refuse it)\n"
    "  --joints       end with a list of the joints: id, name (as in events.csv's\n"
    "                 joint_name and the frames' joint_names), node, members, type\n"
    "  --help         this text\n";

struct RunArgs {
  std::string case_file;
  std::optional<std::filesystem::path> out;
  bool quiet = false;
  bool force = false;
  int threads = 0;
  std::optional<fq::Integrator> integrator;
  std::optional<double> checkpoint_every_s;
  bool list_joints = false;  // info --joints
};

using fq_app::unknown_option;
using fq_app::usage_error;

// run_options: run's options (--out, --quiet, --force, --threads,
// --checkpoint-every); --integrator is also info's; info_options: info's --joints.
RunArgs parse_run_args(int argc, char** argv, int first, const char* help, bool run_options,
                       bool integrator_option, bool info_options = false) {
  RunArgs a;
  std::vector<std::string> seen;  // options that take a value, given once each
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    auto need_value = [&](const char* name) -> std::string {
      // "--integrator rk4 ... --integrator verlet": which one was meant is
      // not for us to guess (the last one used to win silently).
      if (std::find(seen.begin(), seen.end(), name) != seen.end())
        usage_error(std::string(name) + " is given twice; give it once", help);
      seen.push_back(name);
      std::string value = fq_app::option_value(name, argc, argv, i, help);
      ++i;
      return value;
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << help;
      std::exit(kExitOk);
    } else if (run_options && arg == "--out") {
      a.out = need_value("--out");
    } else if (run_options && arg == "--quiet") {
      a.quiet = true;
    } else if (run_options && arg == "--force") {
      a.force = true;
    } else if (run_options && arg == "--threads") {
      a.threads = fq_app::whole_number_option("--threads", need_value("--threads"), 1, 1024, help);
    } else if (integrator_option && arg == "--integrator") {
      const std::string v = need_value("--integrator");
      fq::Integrator m;
      if (!fq::parse_integrator(v, m)) {
        usage_error("--integrator expects one of " + fq::integrator_names_list() + ", got '" + v + "'" +
                        fq::did_you_mean(fq::nearest_name(v, fq::integrator_names())),
                    help);
      }
      a.integrator = m;
    } else if (info_options && arg == "--joints") {
      a.list_joints = true;
    } else if (run_options && arg == "--checkpoint-every") {
      const std::string v = need_value("--checkpoint-every");
      double s = 0.0;
      if (!fq_app::read_decimal_number(v, s) || !(s > 0.0))
        usage_error("--checkpoint-every expects a positive number of simulated seconds, got '" + v + "'", help);
      a.checkpoint_every_s = s;
    } else if (!arg.empty() && arg[0] == '-') {
      unknown_option(arg, help);
    } else if (a.case_file.empty()) {
      a.case_file = arg;
    } else {
      usage_error("unexpected argument '" + arg + "' (one case file per run)", help);
    }
  }
  if (a.case_file.empty()) usage_error("missing CASE (a YAML case file)", help);
  return a;
}

// A run's warnings (io/case_runner.h, the kWarn* checks) as they arise; they are
// also in summary.json.
void print_warning(const std::string& text) { std::cerr << "framequake: warning: " << text << "\n"; }
void print_note(const std::string& text) { std::cerr << "framequake: note: " << text << "\n"; }

// Too many threads for the cores slow every parallel region down (a CLI
// probe's 5000-block run: 17.7 s with 1000 threads, 3.1 s with the
// default); results are the same for any count. `given` names the setting.
void warn_if_too_many_threads(long threads, const std::string& given) {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  if (threads > 4 * long(cores))
    std::cerr << "framequake: warning: " << given << " is far more than the " << cores
              << " logical cores: the parallel stages will run slower, not faster (results do not depend on it)\n";
}

int command_run(int argc, char** argv) {
  const RunArgs args = parse_run_args(argc, argv, 2, kRunHelp, true, true);
  if (args.threads > 0) warn_if_too_many_threads(args.threads, "--threads " + std::to_string(args.threads));
#if defined(_OPENMP)
  if (args.threads > 0) omp_set_num_threads(args.threads);
#endif
  fq::CaseDef def;
  try {
    def = fq::load_case_file(args.case_file);
  } catch (const fq::InputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  }

  install_stop_handlers();
  fq::CaseRunOptions options;
  options.output_folder = args.out;
  options.allow_unstable_time_step = args.force;
  options.integrator = args.integrator;
  options.stop_requested = &g_stop_requested;
  options.checkpoint_every_s = args.checkpoint_every_s;
  options.on_warning = print_warning;
  options.on_note = print_note;
  std::optional<fq::ProgressDisplay> progress;
  if (!args.quiet) {
    progress.emplace(def.name, stderr, isatty(fileno(stderr)) != 0);
    options.progress = &*progress;
  }
  fq::CaseRunReport report;
  try {
    report = fq::run_case(def, options);
  } catch (const fq::InputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const fq::OutputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitOutputFailed;
  }
  const fq::RunResult& r = report.result;
  std::cout << "framequake: " << def.name << ": " << fq::run_status_name(r.status) << " after " << r.steps
            << " steps, t = " << r.simulated_s << " s, wall " << r.wall_s << " s\n"
            << "framequake: output in " << report.output_folder.string() << " (open case.pvd in ParaView)\n";
  fq_app::print_run_outcome(report, std::cout);
  switch (r.status) {
    case fq::RunStatus::Completed: return kExitOk;
    case fq::RunStatus::Stopped: return interrupted_exit_code();
    case fq::RunStatus::Unstable:
      std::cerr << "framequake: error: the run became unstable: " << r.message << "\n";
      return kExitUnstable;
  }
  return kExitOk;
}

// framequake resume DIR: its own small parser, so that the run options
// (case file, --out, --force) are not offered where they mean nothing.
int command_resume(int argc, char** argv) {
  std::string folder;
  std::optional<std::filesystem::path> case_file;  // --case: where the case file is now
  bool quiet = false;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kResumeHelp;
      return kExitOk;
    } else if (arg == "--quiet") {
      quiet = true;
    } else if (arg == "--case") {
      if (case_file) usage_error("--case is given twice; give it once", kResumeHelp);
      case_file = fq_app::option_value("--case", argc, argv, i, kResumeHelp);
      ++i;
    } else if (arg == "--threads") {
      [[maybe_unused]] const int n = fq_app::whole_number_option(
          "--threads", fq_app::option_value("--threads", argc, argv, i, kResumeHelp), 1, 1024, kResumeHelp);
      ++i;
      warn_if_too_many_threads(n, "--threads " + std::to_string(n));
#if defined(_OPENMP)
      omp_set_num_threads(n);
#endif
    } else if (!arg.empty() && arg[0] == '-') {
      unknown_option(arg, kResumeHelp);
    } else if (folder.empty()) {
      folder = arg;
    } else {
      usage_error("unexpected argument '" + arg + "' (one output folder)", kResumeHelp);
    }
  }
  if (folder.empty()) usage_error("missing DIR (the output folder of a run with --checkpoint-every)", kResumeHelp);

  install_stop_handlers();
  fq::CaseRunOptions options;
  options.stop_requested = &g_stop_requested;
  options.on_warning = print_warning;
  options.on_note = print_note;
  std::optional<fq::ProgressDisplay> progress;
  if (!quiet) {
    progress.emplace(std::filesystem::path(folder).filename().string(), stderr, isatty(fileno(stderr)) != 0);
    options.progress = &*progress;
  }
  fq::CaseRunReport report;
  try {
    report = fq::resume_case(folder, options, case_file);
  } catch (const fq::CheckpointError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const fq::InputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const fq::OutputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitOutputFailed;
  }
  const fq::RunResult& r = report.result;
  std::cout << "framequake: resumed " << folder << ": " << fq::run_status_name(r.status) << " after " << r.steps
            << " steps, t = " << r.simulated_s << " s, wall " << r.wall_s << " s\n";
  fq_app::print_run_outcome(report, std::cout);
  switch (r.status) {
    case fq::RunStatus::Completed: return kExitOk;
    case fq::RunStatus::Stopped: return interrupted_exit_code();
    case fq::RunStatus::Unstable:
      std::cerr << "framequake: error: the run became unstable: " << r.message << "\n";
      return kExitUnstable;
  }
  return kExitOk;
}

int command_info(int argc, char** argv) {
  const RunArgs args = parse_run_args(argc, argv, 2, kInfoHelp, false, true, true);
  try {
    const fq::CaseDef def = fq::load_case_file(args.case_file);
    fq::describe_case(def, std::cout, args.integrator, args.list_joints);
  } catch (const fq::InputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  }
  return kExitOk;
}

// Offscreen animation of finished runs: everything lives in render/.
int command_render(int argc, char** argv) {
  install_stop_handlers();
  const int code = fq::render::render_command(argc, argv, 2, &g_stop_requested, [](const std::string& option) {
    return fq::unknown_option_message(option, fq::render::kRenderHelp);
  });
  return code == kExitInterrupted ? interrupted_exit_code() : code;
}

// The usage a usage error of COMMAND prints: its own, or the top-level one
// for an unknown command.
const char* command_help(const std::string& command) {
  if (command == "run") return kRunHelp;
  if (command == "resume") return kResumeHelp;
  if (command == "info") return kInfoHelp;
  if (command == "compare") return fq_app::compare_help();
  if (command == "sweep") return fq_app::sweep_help();
  if (command == "render") return fq::render::kRenderHelp;
  return kMainHelp;
}

}  // namespace

static int dispatch(int argc, char** argv) {
  if (argc < 2) usage_error("missing command", kMainHelp);
  // Every command reads `--option=value` as `--option value` (the two forms
  // users type); a value may itself contain '='.
  std::vector<std::string> words;
  bool options_ended = false;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    const std::size_t eq = arg.find('=');
    // "--" ends the options (the usual convention): every word after it is
    // a path, and one starting with '-' is passed as "./-name", which names
    // the same file and which no command reads as an option.
    if (i >= 2 && !options_ended && arg == "--") {
      options_ended = true;
      continue;
    }
    if (options_ended) {
      words.push_back(arg.rfind('-', 0) == 0 ? "./" + arg : arg);
    } else if (i >= 2 && arg.rfind("--", 0) == 0 && eq != std::string::npos && eq > 2) {
      // Options that take no value (every command's flags).
      for (const char* flag : {"--help", "--quiet", "--force", "--no-figure", "--compare", "--png", "--joints"})
        if (arg.compare(0, eq, flag) == 0)
          usage_error(std::string("option ") + flag + " takes no value, got '" + arg + "'",
                      command_help(argv[1]));
      words.push_back(arg.substr(0, eq));
      // "--out=--name" is a value by its form: passed as ./--name, which
      // names the same path and is not taken for an option below.
      const std::string value = arg.substr(eq + 1);
      words.push_back(fq_app::looks_like_option(value) ? "./" + value : value);
    } else {
      words.push_back(arg);
    }
  }
  // "framequake help run" (or --help run, -h run): the command's own help.
  // Nothing may follow the command, and nothing may follow --version: extra
  // words were ignored with exit 0 ("--version --bogus", "--help run x y";
  // CLI probe), as no command ignores them.
  if (words.size() >= 3 && (words[1] == "help" || words[1] == "--help" || words[1] == "-h")) {
    if (words[2].rfind('-', 0) == 0)
      usage_error("unexpected argument '" + words[2] + "' after " + words[1] + " (give a command, e.g. " + words[1] +
                      " run)",
                  kMainHelp);
    if (words.size() > 3)
      usage_error("unexpected argument '" + words[3] + "' after " + words[1] + " " + words[2] +
                      " (one command's help at a time)",
                  kMainHelp);
    words = {words[0], words[2], "--help"};
  }
  if (words.size() >= 3 && words[1] == "--version")
    usage_error("unexpected argument '" + words[2] + "' after --version (it takes none)", kMainHelp);
  std::vector<char*> split_argv;
  for (std::string& w : words) split_argv.push_back(w.data());
  split_argv.push_back(nullptr);
  argc = int(words.size());
  argv = split_argv.data();
  const std::string command = argv[1];
  try {
    if (command == "--help" || command == "-h" || command == "help") {
      std::cout << kMainHelp;
      return kExitOk;
    }
    if (command == "--version") {
      std::cout << "framequake " << FQ_VERSION_STRING << "\n";
      return kExitOk;
    }
    // The SIMD form of the lane kernels, which FRAMEQUAKE_SIMD may set
    // (dem_core/lane_isa.h): a bad value is bad input, refused before any work.
    try {
      (void)fq::active_lane_isa();
    } catch (const std::invalid_argument& e) {
      std::cerr << "framequake: error: " << e.what() << "\n";
      return kExitBadInput;
    }
    // OMP_NUM_THREADS: libgomp only warns of a value it cannot read and
    // goes on with its default.
    if (const char* threads = std::getenv("OMP_NUM_THREADS"); threads != nullptr && *threads != '\0') {
      const std::string text = threads;
      const std::string first = text.substr(0, text.find(','));  // a nesting list "4,2" is valid
      char* end = nullptr;
      const long n = std::strtol(first.c_str(), &end, 10);
      if (end == first.c_str() || *end != '\0' || n < 1) {
        std::cerr << "framequake: error: OMP_NUM_THREADS='" << text
                  << "' is not a positive whole number of threads; unset it or give e.g. OMP_NUM_THREADS=2\n";
        return kExitBadInput;
      }
      warn_if_too_many_threads(n, "OMP_NUM_THREADS=" + std::to_string(n));
    }
    if (command == "run") return command_run(argc, argv);
    if (command == "info") return command_info(argc, argv);
    if (command == "compare" || command == "sweep") {
      install_stop_handlers();
      const int code = command == "compare" ? fq_app::command_compare(argc, argv, &g_stop_requested)
                                            : fq_app::command_sweep(argc, argv, &g_stop_requested);
      return code == kExitInterrupted ? interrupted_exit_code() : code;
    }
    if (command == "resume") return command_resume(argc, argv);
    if (command == "render") return command_render(argc, argv);
  } catch (const std::exception& e) {
    // Anything not foreseen above still ends in a message and a non-zero code.
    std::cerr << "framequake: internal error: " << e.what() << "\n";
    return 4;
  }
  usage_error("unknown command '" + command + "'", kMainHelp);
}

int main(int argc, char** argv) {
  const int code = dispatch(argc, argv);
  // What a command printed (info's description, compare's table, a help
  // text) must have reached its reader: `framequake info case > /dev/full`
  // ended with exit 0 and nothing written (CLI probe).
  std::cout.flush();
  if (!std::cout) {
    std::cerr << "framequake: error: cannot write to standard output (a full disk, or a pipe whose reader "
                 "has gone)\n";
    return code == kExitOk ? kExitOutputFailed : code;
  }
  return code;
}
