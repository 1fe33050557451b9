// `framequake render` end to end, with no display attached (the command must
// start its own Xvfb): a short run whose joint breaks at a time read from its
// events.csv is rendered, and the PNG frames (read with vtkPNGReader) and the
// GIF (read with Pillow) are checked.
//
// The scene is cases/demo_breaking_cantilever.yaml: a column and an arm whose
// weak joint yields and then breaks under gravity (the case file argues why
// and roughly when). The test does not rely on those estimates: it reads the
// yield and break times from the run's events.csv.
#include <gtest/gtest.h>
#include <fstream>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkDataArray.h>

#include <array>
#include <thread>
#include <csignal>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "../apps/app_process.h"
#include "render/gif_writer.h"
#include "render/renderer.h"
#include "render_test_util.h"

namespace {

namespace fs = std::filesystem;
using Rgb = std::array<std::uint8_t, 3>;

// The shared scene (cases/demo_breaking_cantilever.yaml argues the break);
// the test only changes the frame interval.
std::string case_text(const std::string& frame_interval, const std::string& duration = "0.25") {
  std::string text = fq_test::read_text(fs::path(FQ_SOURCE_DIR) / "cases" / "demo_breaking_cantilever.yaml");
  const std::string key = "frame_interval_s: 0.01";
  const auto at = text.find(key);
  if (at == std::string::npos) throw std::runtime_error("demo_breaking_cantilever.yaml has no '" + key + "'");
  text.replace(at, key.size(), "frame_interval_s: " + frame_interval);
  const std::string dkey = "duration_s: 0.25";
  const auto d = text.find(dkey);
  if (d == std::string::npos) throw std::runtime_error("demo_breaking_cantilever.yaml has no '" + dkey + "'");
  text.replace(d, dkey.size(), "duration_s: " + duration);
  return text;
}

int run_app(const std::vector<std::string>& args, const fs::path& io_dir, std::string* out = nullptr,
            std::string* err = nullptr, const char* display = nullptr) {
  // No display by default: the render command has to provide its own (as in CI).
  if (display)
    setenv("DISPLAY", display, 1);
  else
    unsetenv("DISPLAY");
  fq_test::AppProcess p(args, io_dir);
  const int code = p.wait();
  if (out) *out = fq_test::read_text(io_dir / "stdout.txt");
  if (err) *err = fq_test::read_text(io_dir / "stderr.txt");
  return code;
}

fs::path run_case(const fs::path& dir, const std::string& name, const std::string& frame_interval,
                  const std::string& duration = "0.25") {
  const std::string text = case_text(frame_interval, duration);
  const fs::path yaml = dir / (name + ".yaml");
  std::ofstream(yaml) << text;
  const fs::path out = dir / name;
  std::string err;
  EXPECT_EQ(run_app({"run", yaml.string(), "--out", out.string(), "--quiet"}, dir, nullptr, &err), 0) << err;
  return out;
}

std::vector<double> pvd_times(const fs::path& run) {
  const std::string doc = fq_test::read_text(run / "case.pvd");
  std::vector<double> t;
  const std::string key = "timestep=\"";
  for (auto at = doc.find(key); at != std::string::npos; at = doc.find(key, at + 1))
    t.push_back(std::stod(doc.substr(at + key.size(), doc.find('"', at + key.size()) - at - key.size())));
  return t;
}

// First time of an event kind in events.csv (+inf when none).
double first_event(const fs::path& run, const std::string& kind) {
  std::ifstream in(run / "events.csv");
  std::string line;
  std::getline(in, line);  // header: time_s,step,kind,...
  while (std::getline(in, line)) {
    const auto c1 = line.find(','), c2 = line.find(',', c1 + 1), c3 = line.find(',', c2 + 1);
    if (line.substr(c2 + 1, c3 - c2 - 1) == kind) return std::stod(line.substr(0, c1));
  }
  return std::numeric_limits<double>::infinity();
}

struct Image {
  int w = 0, h = 0;
  std::vector<std::uint8_t> rgb;  // rows bottom to top (VTK's image order)
  Rgb at(int x, int y) const {
    const std::size_t o = 3 * (std::size_t(y) * std::size_t(w) + std::size_t(x));
    return {rgb[o], rgb[o + 1], rgb[o + 2]};
  }
};

Image read_png(const fs::path& file) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkImageData* img = reader->GetOutput();
  Image im;
  int dims[3];
  img->GetDimensions(dims);
  im.w = dims[0];
  im.h = dims[1];
  vtkDataArray* a = img->GetPointData()->GetScalars();
  const int nc = a ? a->GetNumberOfComponents() : 0;
  if (!a || nc < 3) return im;
  im.rgb.resize(std::size_t(im.w) * std::size_t(im.h) * 3);
  for (vtkIdType i = 0; i < vtkIdType(im.w) * im.h; ++i)
    for (int c = 0; c < 3; ++c) im.rgb[std::size_t(3 * i + c)] = std::uint8_t(a->GetComponent(i, c));
  return im;
}

// A lit face of colour `base` shows base * s with s = ambient + diffuse *
// cos(angle) in [0.35, 1] (renderer.cpp: ambient 0.35, diffuse 0.65, no
// specular); allow a few levels of rounding and blending.
bool shaded(const Rgb& p, const Rgb& base) {
  double pb = 0, bb = 0;
  for (int c = 0; c < 3; ++c) pb += double(p[std::size_t(c)]) * base[std::size_t(c)], bb += double(base[std::size_t(c)]) * base[std::size_t(c)];
  const double s = pb / bb;
  if (s < 0.3 || s > 1.02) return false;
  for (int c = 0; c < 3; ++c)
    if (std::abs(double(p[std::size_t(c)]) - s * base[std::size_t(c)]) > 8.0) return false;
  return true;
}

bool exact(const Rgb& p, const Rgb& c) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(int(p[std::size_t(k)]) - int(c[std::size_t(k)])) > 2) return false;
  return true;
}

struct Counts {
  int marker = 0;
  int state[4] = {0, 0, 0, 0};
  int xmin = 1 << 30, xmax = -1, ymin = 1 << 30, ymax = -1;  // bounding box of member pixels
  int pixels = 0;
};

// Counts over the 3-D view of one panel: columns [x0, x1), rows above the trace.
Counts count(const Image& im, int x0, int x1) {
  Counts c;
  const int y0 = int(std::ceil(fq::render::kTraceHeightFraction * im.h));
  for (int y = y0; y < im.h; ++y)
    for (int x = x0; x < x1; ++x) {
      const Rgb p = im.at(x, y);
      ++c.pixels;
      if (exact(p, fq::render::kBrokenJointColour)) ++c.marker;
      for (int s = 0; s < 4; ++s)
        if (shaded(p, fq::render::kDamageColour[std::size_t(s)])) {
          ++c.state[s];
          c.xmin = std::min(c.xmin, x), c.xmax = std::max(c.xmax, x);
          c.ymin = std::min(c.ymin, y), c.ymax = std::max(c.ymax, y);
        }
    }
  return c;
}

fs::path png(const fs::path& folder, std::size_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06zu.png", k);
  return folder / name;
}

TEST(RenderRun, MembersMarkersAndFramesOfARunWithAJointBreak) {
  fq_test::TempDir dir;
  const fs::path run = run_case(dir.path(), "cantilever", "0.01");
  const std::vector<double> times = pvd_times(run);
  const double t_yield = first_event(run, "spring_yielded");
  const double t_break = first_event(run, "joint_broken");
  ASSERT_EQ(times.size(), 26u);  // 0 to 0.25 s every 0.01 s
  // The scene must yield and break mid-run for the checks below to mean anything.
  ASSERT_GT(t_yield, 0.02);
  ASSERT_GT(t_break, t_yield + 0.02);
  ASSERT_LT(t_break, 0.2);

  // An earlier render's frame beyond this one's count, and a file of the
  // user's, in the frames' folder: the first is removed (it would be taken
  // for a frame of this render), the second kept.
  fs::create_directories(run / "animation_frames");
  std::ofstream(png(run / "animation_frames", 99)) << "old frame";
  std::ofstream(run / "animation_frames" / "notes.txt") << "mine";
  std::string out, err;
  ASSERT_EQ(run_app({"render", run.string(), "--png", "--size", "400x300"}, dir.path(), &out, &err), 0) << out << err;
  EXPECT_NE(out.find("rendered 26 frames"), std::string::npos) << out;
  const fs::path frames = run / "animation_frames";
  const fs::path gif = run / "animation.gif";
  ASSERT_TRUE(fs::exists(gif));
  ASSERT_TRUE(fs::exists(png(frames, times.size() - 1)));
  EXPECT_FALSE(fs::exists(png(frames, times.size()))) << "one PNG per output frame";
  EXPECT_FALSE(fs::exists(png(frames, 99))) << "an earlier render's frame";
  EXPECT_TRUE(fs::exists(frames / "notes.txt"));

  // The animation: as many frames as the run has output frames (Pillow's count).
  if (fq_test::pil_available()) {
    const fq_test::GifInfo info = fq_test::read_gif_with_pil(gif, dir.path());
    EXPECT_EQ(info.n_frames, int(times.size())) << info.json;
    EXPECT_EQ(info.width, 400);
    EXPECT_EQ(info.height, 300);
    // Each GIF frame is its PNG frame mapped to the palette, pixel for pixel.
    for (const std::size_t k : {std::size_t(0), times.size() - 1}) {
      const Image im = read_png(png(frames, k));
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06zu.rgb", k);
      const auto decoded = fq_test::read_bytes(dir.path() / name);
      ASSERT_EQ(decoded.size(), im.rgb.size());
      const auto& pal = fq::render::gif_palette_rgb();
      int mismatches = 0;
      for (int y = 0; y < im.h; ++y)
        for (int x = 0; x < im.w; ++x) {
          const Rgb p = im.at(x, y);
          const int i = fq::render::gif_palette_index(p[0], p[1], p[2]);
          const std::size_t o = 3 * (std::size_t(im.h - 1 - y) * std::size_t(im.w) + std::size_t(x));
          for (int c = 0; c < 3; ++c) mismatches += decoded[o + std::size_t(c)] != pal[std::size_t(3 * i + c)];
        }
      EXPECT_EQ(mismatches, 0) << "frame " << k;
    }
  }

  for (std::size_t k = 0; k < times.size(); ++k) {
    const Image im = read_png(png(frames, k));
    ASSERT_EQ(im.w, 400);
    ASSERT_EQ(im.h, 300);
    const Counts c = count(im, 0, im.w);
    const double t = times[k];
    SCOPED_TRACE("frame " + std::to_string(k) + " at t = " + std::to_string(t) + " s");
    if (t < t_break) {
      EXPECT_EQ(c.marker, 0) << "no broken-joint marker before the break";
    } else {
      // A sphere of radius 2 % of the scene diagonal is several pixels across.
      EXPECT_GE(c.marker, 10) << "broken-joint marker after the break";
    }
    if (t < t_yield) {
      EXPECT_GT(c.state[0], 0);
      EXPECT_EQ(c.state[1] + c.state[2] + c.state[3], 0) << "only intact members before the first yield";
    } else if (t < t_break) {
      EXPECT_GT(c.state[1], 0);
      EXPECT_EQ(c.state[0] + c.state[2] + c.state[3], 0) << "both members touch the yielded joint";
    } else {
      // The column keeps its support (damaged: one joint broken, one holding);
      // the arm lost its only joint (detached).
      EXPECT_GT(c.state[2], 0);
      EXPECT_GT(c.state[3], 0);
      EXPECT_EQ(c.state[0] + c.state[1], 0);
    }
    if (k == 0) {
      // Structure in view: slender members (10-20 mm wide, ~0.3 m long) in a
      // view fitted to the ~0.3 m scene cover a few per cent of the picture,
      // and the 0.29 m column spans most of the view's height (the camera
      // fits the scene's bounds, whose height is the column's).
      const int members = c.state[0];
      const double fraction = double(members) / c.pixels;
      EXPECT_GT(fraction, 0.005);
      EXPECT_LT(fraction, 0.25);
      const int view_h = im.h - int(std::ceil(fq::render::kTraceHeightFraction * im.h));
      EXPECT_GT(c.xmin, 0);
      EXPECT_LT(c.xmax, im.w - 1);
      EXPECT_GT(c.ymin, im.h - view_h);
      EXPECT_LT(c.ymax, im.h - 1);
      EXPECT_GT(double(c.ymax - c.ymin), 0.5 * view_h) << "the camera frames the structure";
    }
  }
}

TEST(RenderRun, CompareShowsRunsSideBySideInStep) {
  // One run written every 0.01 s, and a copy of it whose case.pvd lists only
  // every other frame (as if written every 0.02 s; the renderer reads only
  // what case.pvd lists, and one simulation is cheaper than two under the
  // sanitizers). The animation runs on the merged times and each panel shows
  // its run's last frame at or before the animation time, so the second
  // panel shows the break one 0.01 s frame later when the break falls in an
  // odd interval.
  fq_test::TempDir dir;
  // 0.15 s is enough: the break comes near 0.09 s (the case file's estimate).
  const fs::path fine = run_case(dir.path(), "fine", "0.01", "0.15");
  const fs::path coarse = dir.path() / "coarse";
  fs::copy(fine, coarse, fs::copy_options::recursive);
  {
    const std::string doc = fq_test::read_text(fine / "case.pvd");
    std::string kept;
    std::size_t index = 0, pos = 0;
    for (std::size_t nl; (nl = doc.find('\n', pos)) != std::string::npos; pos = nl + 1) {
      const std::string line = doc.substr(pos, nl + 1 - pos);
      if (line.find("<DataSet") != std::string::npos && index++ % 2 == 1) continue;
      kept += line;
    }
    std::ofstream(coarse / "case.pvd", std::ios::trunc) << kept;
  }
  const std::vector<double> t_fine = pvd_times(fine), t_coarse = pvd_times(coarse);
  ASSERT_EQ(t_fine.size(), 16u);  // 0 to 0.14 s every 0.01 s, and the last state at 0.15 s
  ASSERT_EQ(t_coarse.size(), 8u);  // 0 to 0.14 s every 0.02 s
  const double break_fine = first_event(fine, "joint_broken"), break_coarse = break_fine;
  ASSERT_TRUE(std::isfinite(break_fine));
  ASSERT_LT(break_fine, 0.14);

  const fs::path gif = dir.path() / "cmp.gif";
  std::string out, err;
  ASSERT_EQ(run_app({"render", "--compare", fine.string(), coarse.string(), "--to", gif.string(), "--png", "--size",
                     "240x180"},
                    dir.path(), &out, &err),
            0)
      << out << err;
  if (fq_test::pil_available()) {
    const fq_test::GifInfo info = fq_test::read_gif_with_pil(gif);
    EXPECT_EQ(info.n_frames, 16) << info.json;
    EXPECT_EQ(info.width, 480);
    EXPECT_EQ(info.height, 180);
  }
  const fs::path frames = dir.path() / "cmp_frames";
  int frames_where_only_left_shows_break = 0;
  for (std::size_t k = 0; k < t_fine.size(); ++k) {
    const Image im = read_png(png(frames, k));
    ASSERT_EQ(im.w, 480);
    const double t = t_fine[k];
    double shown_coarse = t_coarse.front();
    for (const double tc : t_coarse)
      if (tc <= t + 1e-9) shown_coarse = tc;
    SCOPED_TRACE("frame " + std::to_string(k) + " at t = " + std::to_string(t) + " s");
    const Counts left = count(im, 0, 240), right = count(im, 240, 480);
    EXPECT_EQ(left.marker > 0, t >= break_fine);
    EXPECT_EQ(right.marker > 0, shown_coarse >= break_coarse);
    frames_where_only_left_shows_break += (left.marker > 0) != (right.marker > 0);
    EXPECT_GT(left.state[0] + left.state[1] + left.state[2] + left.state[3], 0);
    EXPECT_GT(right.state[0] + right.state[1] + right.state[2] + right.state[3], 0);
  }
  EXPECT_LE(frames_where_only_left_shows_break, 1);
}

// A long run folder's name is cut in its middle to the room the panel's
// top row leaves beside the time stamp, never inside a UTF-8 character.
TEST(RenderLabel, ALongFolderNameIsCutInItsMiddle) {
  using fq::render::shortened_label;
  EXPECT_EQ(shortened_label("frame_B", 40), "frame_B");
  const std::string long_name = std::string(60, 'a') + "_retrofit_" + std::string(60, 'z');
  const std::string cut = shortened_label(long_name, 40);
  EXPECT_EQ(cut.size(), 40u);
  EXPECT_EQ(cut, std::string(19, 'a') + "..." + std::string(18, 'z'));
  // "\u5efa" (3 bytes) repeated: the cut falls between characters.
  std::string kanji;
  for (int k = 0; k < 30; ++k) kanji += "\xe5\xbb\xba";
  const std::string k_cut = shortened_label(kanji, 20);
  EXPECT_LE(k_cut.size(), 20u);
  const std::size_t dots = k_cut.find("...");
  ASSERT_NE(dots, std::string::npos);
  EXPECT_EQ(dots % 3, 0u) << "head cut inside a character";
  EXPECT_EQ((k_cut.size() - dots - 3) % 3, 0u) << "tail cut inside a character";
}

TEST(RenderRun, BadUsageEndsWithAClearMessageAndWritesNothing) {
  fq_test::TempDir dir;
  std::string out, err;
  EXPECT_EQ(run_app({"render", (dir.path() / "nope").string()}, dir.path(), &out, &err), 2);
  EXPECT_NE(err.find("nope"), std::string::npos) << err;

  const fs::path empty = dir.path() / "empty";
  fs::create_directory(empty);
  EXPECT_EQ(run_app({"render", empty.string()}, dir.path(), &out, &err), 2);
  EXPECT_NE(err.find("case.pvd"), std::string::npos) << err;

  EXPECT_EQ(run_app({"render", "--compare", empty.string()}, dir.path(), &out, &err), 2);
  EXPECT_NE(err.find("--compare needs at least two"), std::string::npos) << err;
  EXPECT_EQ(run_app({"render", empty.string(), "--fps", "0"}, dir.path(), &out, &err), 2);
  EXPECT_NE(err.find("--fps"), std::string::npos) << err;
  EXPECT_EQ(run_app({"render", empty.string(), "--size", "800"}, dir.path(), &out, &err), 2);
  EXPECT_NE(err.find("--size"), std::string::npos) << err;

  // A real run but an animation format the command cannot write.
  const fs::path run = run_case(dir.path(), "r", "0.01", "0.05");
  EXPECT_EQ(run_app({"render", run.string(), "--to", (dir.path() / "a.avi").string()}, dir.path(), &out, &err), 2);
  EXPECT_NE(err.find(".gif or .mp4"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir.path() / "a.avi"));
  EXPECT_FALSE(fs::exists(run / "animation.gif"));
  // A file where the animation's folder should be is named as a file (it
  // was said not to exist; CLI probe).
  std::ofstream(dir.path() / "afile") << "x";
  EXPECT_EQ(run_app({"render", run.string(), "--to", (dir.path() / "afile" / "r.gif").string()}, dir.path(), &out,
                    &err),
            2);
  EXPECT_NE(err.find("(folder of the animation file) is a file, not a folder"), std::string::npos) << err;
  // So is a file where the PNG frames' folder should be, before anything
  // is drawn (it failed at the first frame, exit 3; workflow probe).
  EXPECT_EQ(run_app({"render", run.string(), "--png-dir", (dir.path() / "afile").string()}, dir.path(), &out, &err), 2);
  EXPECT_NE(err.find("the PNG frames' folder '" + (dir.path() / "afile").string() + "' exists and is not a folder"),
            std::string::npos)
      << err;
  EXPECT_FALSE(fs::exists(run / "animation.gif"));
  // A folder that is not there yet is made, as run, compare and sweep make
  // theirs (it was refused; workflow probe).
  EXPECT_EQ(run_app({"render", run.string(), "--to", (dir.path() / "new" / "deeper" / "r.gif").string()}, dir.path(),
                    &out, &err),
            0)
      << err;
  EXPECT_TRUE(fs::is_regular_file(dir.path() / "new" / "deeper" / "r.gif"));
  // A frame cut short: one line naming it, without VTK's own dozen lines
  // of parser and pipeline errors before it (CLI probe), and no animation.
  const fs::path frame = run / "frames" / "frame_000001.vtu";
  const std::string text = fq_test::read_text(frame);
  std::ofstream(frame, std::ios::binary | std::ios::trunc) << text.substr(0, text.size() / 2);
  EXPECT_EQ(run_app({"render", run.string()}, dir.path(), &out, &err), 2);
  EXPECT_NE(err.find("frame_000001.vtu' is not a readable framequake frame"), std::string::npos) << err;
  EXPECT_EQ(err.find("vtkXML"), std::string::npos) << err;
  EXPECT_EQ(err.find("ERR|"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(run / "animation.gif"));
}

// Ctrl-C (or SIGTERM) during a render stops it between frames: exit 130
// (143), and the unfinished animation's FILE.part is removed (a probe found
// it left, 710 KB, and the private Xvfb killed by the same Ctrl-C before
// the render could clean up). 1001 frames take seconds at any size, so the
// signal 1 s in comes before the end.
TEST(RenderRun, CtrlCStopsARenderAndLeavesNoUnfinishedAnimation) {
  fq_test::TempDir dir;
  const fs::path run = run_case(dir.path(), "many", "0.001", "1.0");
  const fs::path gif = dir.path() / "stopped.gif";
  fq_test::AppProcess app({"render", run.string(), "--to", gif.string(), "--size", "160x120"}, dir.path());
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  app.signal(SIGINT);
  ASSERT_EQ(app.wait(), 130) << app.err();
  EXPECT_NE(app.err().find("no animation was written"), std::string::npos) << app.err();
  EXPECT_FALSE(fs::exists(gif));
  EXPECT_FALSE(fs::exists(fs::path(gif).concat(".part")));
  // With --png the images written before the stop stay, and the message
  // says how many and where (a probe's 13 were left unmentioned).
  const fs::path with_png = dir.path() / "with_png.gif";
  fq_test::AppProcess png_app({"render", run.string(), "--to", with_png.string(), "--size", "160x120", "--png"},
                              dir.path());
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  png_app.signal(SIGINT);
  ASSERT_EQ(png_app.wait(), 130) << png_app.err();
  const fs::path images = dir.path() / "with_png_frames";
  std::size_t count = 0;
  if (fs::is_directory(images))
    for (const fs::directory_entry& e : fs::directory_iterator(images)) count += e.path().extension() == ".png";
  std::string said;
  if (count == 0) {
    said = "no PNG image was written";
  } else {
    said = "the PNG images of the first " + std::to_string(count) + " frames stay in '";
    said += images.string();
  }
  EXPECT_NE(png_app.err().find(said), std::string::npos) << png_app.err();
  EXPECT_FALSE(fs::exists(with_png));
}

TEST(RenderRun, Mp4ThroughFfmpegHasOneFramePerOutputFrame) {
  // Optional output: only when Debian's ffmpeg (with ffprobe) is installed.
  if (std::system("ffprobe -version > /dev/null 2>&1") != 0) GTEST_SKIP() << "ffmpeg/ffprobe not installed";
  fq_test::TempDir dir;
  const fs::path run = run_case(dir.path(), "r", "0.01", "0.05");
  const std::size_t frames = pvd_times(run).size();
  const fs::path mp4 = dir.path() / "r.mp4";
  std::string out, err;
  ASSERT_EQ(run_app({"render", run.string(), "--to", mp4.string(), "--size", "320x240"}, dir.path(), &out, &err), 0)
      << out << err;
  const std::string cmd = "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                          "stream=nb_read_frames,width,height -of csv=p=0 '" + mp4.string() + "' > '" +
                          (dir.path() / "probe.txt").string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_EQ(fq_test::read_text(dir.path() / "probe.txt"), "320,240," + std::to_string(frames) + "\n");
  EXPECT_FALSE(fs::exists(dir.path() / "r.mp4.part"));
}

TEST(RenderRun, ADisplayThatDoesNotOpenFallsBackToAPrivateXvfb) {
  // VTK aborts on a DISPLAY it cannot open; the command checks it first.
  fq_test::TempDir dir;
  const fs::path run = run_case(dir.path(), "r", "0.01", "0.05");
  std::string out, err;
  ASSERT_EQ(run_app({"render", run.string(), "--size", "160x120"}, dir.path(), &out, &err, ":59999"), 0) << out << err;
  EXPECT_NE(err.find("cannot open X display ':59999'"), std::string::npos) << err;
  EXPECT_TRUE(fs::exists(run / "animation.gif"));
}

}  // namespace
