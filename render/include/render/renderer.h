// Offscreen animation of one or several framequake runs with VTK's own
// rendering (OpenGL through an X display; see headless_display.h when no
// display is attached).
//
// Each run gets a panel: a 3-D view on top (members as boxes coloured by
// damage state, broken joints marked, the ground, a time stamp and the run's
// name) and the ground acceleration trace below it with a cursor at the
// current time. Several runs are shown side by side, synchronised in time,
// with one camera and one acceleration scale so they compare at a glance.
// The camera is fixed for the whole animation and frames the members over
// all frames of all runs (so a collapse stays in view).
#pragma once

#include <array>
#include <stdexcept>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <optional>
#include <vector>

#include "render/run_data.h"

namespace fq::render {

// Colours (r, g, b bytes). The damage colours are multiples of 51, so the
// GIF palette (gif_writer.h) reproduces them exactly where a face is fully lit.
// damage_state (written per body by io/src/scene_output.cpp):
//   0 intact: all of the member's joints are elastic (or it has none)
//   1 yielded: at least one joint yielded, none broken
//   2 damaged: at least one joint broken, at least one still holding
//   3 detached: every joint of the member is broken (it is debris)
inline constexpr std::array<std::array<std::uint8_t, 3>, 4> kDamageColour{{
    {204, 153, 102},  // intact: wood
    {255, 153, 0},    // yielded: orange
    {204, 0, 0},      // damaged: red
    {102, 51, 153},   // detached: violet
}};
inline constexpr std::array<std::uint8_t, 3> kBrokenJointColour{255, 0, 255};  // marker, drawn unlit
inline constexpr std::array<std::uint8_t, 3> kGroundColour{153, 153, 102};
inline constexpr std::array<std::uint8_t, 3> kSkyColour{204, 221, 238};
inline constexpr std::array<std::uint8_t, 3> kTraceBackground{34, 34, 51};
// Share of a panel's height taken by the acceleration trace (bottom).
inline constexpr double kTraceHeightFraction = 0.25;

struct RenderOptions {
  // Animation file: .gif (written by GifWriter) or .mp4 (piped to ffmpeg,
  // which must be on PATH). Empty: no animation (PNG frames only).
  std::filesystem::path animation;
  // When set, frame_NNNNNN.png of every animation frame go into this folder.
  std::optional<std::filesystem::path> png_folder;
  int panel_width_px = 800;
  int panel_height_px = 600;
  double frames_per_second = 10.0;
  int every = 1;  // use every n-th output frame
  // Checked before each frame; when it reads true, render_runs throws
  // RenderStopped and the unfinished animation file is removed (Ctrl-C,
  // SIGTERM). PNG frames already written stay.
  const std::atomic<bool>* stop_requested = nullptr;
  // Called after each frame with the frames done and their total (a
  // progress display); may be empty.
  std::function<void(int done, int total)> on_frame;
};

// `label` cut in its middle to at most `max_chars` characters ("abc...xyz"),
// so that a long run folder's name, drawn at a panel's top right, leaves
// the time stamp at its top left readable (workflow probe: a 128-character
// case name ran across it). Unchanged when it fits.
std::string shortened_label(const std::string& label, std::size_t max_chars);

// render_runs was stopped through RenderOptions::stop_requested.
class RenderStopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RenderReport {
  int frames = 0;                   // animation frames written
  std::vector<double> frame_time_s; // simulated time of each animation frame
  double wall_s = 0.0;              // whole render
  double read_s = 0.0, draw_s = 0.0, encode_s = 0.0;  // split of wall_s
  double cpu_s = 0.0;  // processor time of this process (all threads, Mesa's included)
  int width_px = 0, height_px = 0;
};

// Renders the runs (at least one) into options.animation and/or PNG frames.
// Animation frame times: the output frame times of all runs merged (times
// closer than 1e-9 s are one), every options.every-th kept, and the last; each run shows its
// last frame at or before that time (its first before it starts).
// Throws RenderInputError for unusable runs or options, std::runtime_error
// when an output file cannot be written (nothing half written is left).
RenderReport render_runs(const std::vector<RunData>& runs, const RenderOptions& options);

}  // namespace fq::render
