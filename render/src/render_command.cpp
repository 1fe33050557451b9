#include "render/render_command.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "render/headless_display.h"
#include "render/renderer.h"
#include "render/run_data.h"

namespace fq::render {

const char* const kRenderHelp =
    "Usage: framequake render OUT_DIR [options]\n"
    "       framequake render --compare OUT_A OUT_B [OUT_C ...] [options]\n"
    "\n"
    "Animates finished runs (output folders of `framequake run`) with VTK's own\n"
    "offscreen rendering: members as boxes coloured by damage state (wood intact,\n"
    "orange yielded, red a joint broken, violet detached), broken joints as magenta\n"
    "markers, the ground, the time and the ground acceleration with a cursor.\n"
    "--compare puts the runs side by side, synchronised in time, with one camera.\n"
    "Without an X display (DISPLAY unset) a private Xvfb is started (package xvfb).\n"
    "\n"
    "Options:\n"
    "  --to FILE        animation file, .gif or .mp4 (mp4 needs ffmpeg on PATH)\n"
    "                   (default OUT_DIR/animation.gif; with --compare ./compare.gif)\n"
    "  --png            also write every frame as PNG, into FILE's folder /\n"
    "                   <FILE stem>_frames/frame_NNNNNN.png\n"
    "  --png-dir DIR    write the PNG frames into DIR instead (implies --png)\n"
    "  --fps N          frames per second of the animation (default 10)\n"
    "  --every N        use every N-th output frame, and the last (default 1: all)\n"
    "  --size WxH       pixels of each run's panel (default 800x600)\n"
    "  --help           this text\n"
    "\n"
    "Exit codes: 0 done, 2 bad usage or run folder (an .mp4 without ffmpeg on PATH included;\n"
    "nothing written), 3 output or display failed, 130 stopped by Ctrl-C (143 by SIGTERM,\n"
    "129 by SIGHUP; the unfinished animation is removed).\n";

namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr int kExitOutputFailed = 3;
constexpr int kExitInterrupted = 130;  // the command line makes it 143 for SIGTERM

struct Args {
  std::vector<std::filesystem::path> runs;
  bool compare = false;
  std::optional<std::filesystem::path> to;
  bool png = false;
  std::optional<std::filesystem::path> png_dir;
  RenderOptions options;
};

struct UsageError {
  std::string message;
};

// Decimal digits only, as the case file's whole numbers and the other
// commands' options (std::from_chars; strtol also took " 4" and "+4").
int parse_int(const std::string& option, const std::string& v, int lo, int hi) {
  long n = 0;
  const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
  if (v.empty() || ec != std::errc() || end != v.data() + v.size() || n < lo || n > hi)
    throw UsageError{option + " expects a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                     ", got '" + v + "'"};
  return int(n);
}

// A word written as an option name ("--png"): the rule of the other
// commands (apps/usage_error.h, looks_like_option; render does not link the
// command line's own code). "--to --png" rendered into a file named "--png".
bool looks_like_option(const std::string& word) {
  if (word.size() < 3 || word.compare(0, 2, "--") != 0 || !std::isalpha(static_cast<unsigned char>(word[2])))
    return false;
  return std::all_of(word.begin() + 3, word.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-'; });
}

Args parse(int argc, char** argv, int first, const std::function<std::string(const std::string&)>& unknown_option) {
  Args a;
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) throw UsageError{std::string(name) + " needs a value"};
      if (argv[i + 1][0] == '\0') throw UsageError{std::string(name) + " needs a value, got an empty one"};
      if (looks_like_option(argv[i + 1]))
        throw UsageError{std::string(name) + " needs a value, got the option '" + argv[i + 1] +
                         "' (a file or folder whose name starts with '--' is written ./" + argv[i + 1] + ")"};
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << kRenderHelp;
      std::exit(kExitOk);
    } else if (arg == "--compare") {
      a.compare = true;
    } else if (arg == "--to") {
      a.to = value("--to");
    } else if (arg == "--png") {
      a.png = true;
    } else if (arg == "--png-dir") {
      a.png = true;
      a.png_dir = value("--png-dir");
    } else if (arg == "--fps") {
      a.options.frames_per_second = parse_int("--fps", value("--fps"), 1, 100);
    } else if (arg == "--every") {
      a.options.every = parse_int("--every", value("--every"), 1, 1000000);
    } else if (arg == "--size") {
      const std::string v = value("--size");
      const auto x = v.find('x');
      if (x == std::string::npos) throw UsageError{"--size expects WxH, e.g. 800x600, got '" + v + "'"};
      a.options.panel_width_px = parse_int("--size (width)", v.substr(0, x), 64, 4096);
      a.options.panel_height_px = parse_int("--size (height)", v.substr(x + 1), 64, 4096);
    } else if (!arg.empty() && arg[0] == '-') {
      throw UsageError{unknown_option ? unknown_option(arg) : "unknown option '" + arg + "'"};
    } else {
      a.runs.emplace_back(arg);
    }
  }
  if (a.runs.empty()) throw UsageError{"missing OUT_DIR (the output folder of `framequake run`)"};
  if (!a.compare && a.runs.size() > 1)
    throw UsageError{"several run folders given: use --compare to show them side by side"};
  if (a.compare && a.runs.size() < 2) throw UsageError{"--compare needs at least two run folders"};
  if (a.compare && a.runs.size() > 6) throw UsageError{"--compare shows at most six runs side by side"};
  a.options.animation = a.to ? *a.to : (a.compare ? std::filesystem::path("compare.gif") : a.runs[0] / "animation.gif");
  if (a.png) {
    if (a.png_dir) {
      a.options.png_folder = *a.png_dir;
    } else {
      std::filesystem::path dir = a.options.animation.parent_path();
      a.options.png_folder = dir / (a.options.animation.stem().string() + "_frames");
    }
    // A file where the frames' folder should be is the user's to move,
    // refused as bad usage before anything is drawn (it failed later,
    // exit 3; workflow probe).
    std::error_code ec;
    if (std::filesystem::exists(*a.options.png_folder, ec) && !std::filesystem::is_directory(*a.options.png_folder, ec))
      throw UsageError{"the PNG frames' folder '" + a.options.png_folder->string() + "' exists and is not a folder"};
  }
  return a;
}

}  // namespace

int render_command(int argc, char** argv, int first, const std::atomic<bool>* stop_requested,
                   const std::function<std::string(const std::string&)>& unknown_option) {
  Args args;
  try {
    args = parse(argc, argv, first, unknown_option);
    args.options.stop_requested = stop_requested;
  } catch (const UsageError& e) {
    std::cerr << "framequake: error: " << e.message << "\n\n" << kRenderHelp;
    return kExitBadInput;
  }
  std::vector<RunData> runs;
  try {
    for (const auto& folder : args.runs) runs.push_back(load_run(folder));
  } catch (const RenderInputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  }
  HeadlessDisplay display;
  std::string display_error;
  if (!display.ensure(display_error)) {
    std::cerr << "framequake: error: " << display_error << "\n";
    return kExitOutputFailed;
  }
  // Progress on stderr every 5 s of a long render (a render of three full
  // runs was silent for a minute; workflow probe), and nothing for a short one.
  RenderOptions options = args.options;
  const auto started = std::chrono::steady_clock::now();
  auto last_said = started;
  options.on_frame = [&](int done, int total) {
    const auto now = std::chrono::steady_clock::now();
    if (done == total || now - last_said < std::chrono::seconds(5)) return;
    last_said = now;
    std::fprintf(stderr, "framequake render: %d of %d frames (%.0f s)\n", done, total,
                 std::chrono::duration<double>(now - started).count());
  };
  RenderReport report;
  try {
    report = render_runs(runs, options);
  } catch (const RenderStopped& e) {
    std::cerr << "framequake: render " << e.what() << "\n";
    return kExitInterrupted;
  } catch (const RenderInputError& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::runtime_error& e) {
    std::cerr << "framequake: error: " << e.what() << "\n";
    return kExitOutputFailed;
  }
  const double per_frame_ms = report.frames > 0 ? 1e3 * report.wall_s / report.frames : 0.0;
  std::cout << std::fixed << std::setprecision(1) << "framequake: rendered " << report.frames << " frames of "
            << report.width_px << "x" << report.height_px << " px in " << report.wall_s << " s (" << per_frame_ms
            << " ms per frame: read " << 1e3 * report.read_s / std::max(1, report.frames) << ", draw "
            << 1e3 * report.draw_s / std::max(1, report.frames) << ", encode "
            << 1e3 * report.encode_s / std::max(1, report.frames) << "; CPU "
            << 1e3 * report.cpu_s / std::max(1, report.frames) << ")\n";
  if (!args.options.animation.empty()) std::cout << "framequake: animation " << args.options.animation.string() << "\n";
  if (args.options.png_folder) std::cout << "framequake: PNG frames in " << args.options.png_folder->string() << "\n";
  return kExitOk;
}

}  // namespace fq::render
