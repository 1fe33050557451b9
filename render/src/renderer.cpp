#include "render/renderer.h"

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCoordinate.h>
#include <vtkDataArray.h>
#include <vtkGlyph3D.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <iomanip>
#include <string>

#include "render/gif_writer.h"

// Whether the build has AddressSanitizer, under GCC or clang (the same test
// as dem_core/address_sanitizer.h; render depends on no other module).
#if defined(__SANITIZE_ADDRESS__)
#define FQ_RENDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FQ_RENDER_ASAN 1
#endif
#endif
#ifndef FQ_RENDER_ASAN
#define FQ_RENDER_ASAN 0
#endif

#if FQ_RENDER_ASAN
#include <sanitizer/lsan_interface.h>
#endif

namespace fq::render {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kMemberKindGround = 4;  // fq::MemberKind::Ground (dem_core/body_store.h)

// The PNG image of animation frame `index` (RenderOptions::png_folder).
std::string png_frame_name(std::size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06zu.png", index);
  return name;
}
constexpr double kPi = 3.14159265358979323846;
// Camera: looking at the structure from the front-left (-y side, so frames
// built in the x-z plane shake across the picture), slightly from above.
constexpr double kAzimuthDeg = 30.0;
constexpr double kElevationDeg = 18.0;
constexpr double kViewAngleDeg = 30.0;
constexpr double kFrameMargin = 1.08;  // fraction of the view the structure may fill, inverted

// Pauses LeakSanitizer's tracking of new allocations in sanitized builds.
#if FQ_RENDER_ASAN
struct LeakCheckPause {
  LeakCheckPause() { __lsan_disable(); }
  ~LeakCheckPause() { __lsan_enable(); }
};
#else
struct LeakCheckPause {
  LeakCheckPause() = default;
};
#endif

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void set_colour(vtkProperty* p, const std::array<std::uint8_t, 3>& c) {
  p->SetColor(c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
}

vtkSmartPointer<vtkUnstructuredGrid> read_vtu(const fs::path& file) {
  // VTK's own messages about a damaged file (a dozen coloured lines from
  // its XML parser, reader and pipeline) are kept off the terminal while
  // it reads: the error below names the file and says what it should be
  // (they came before it, a CLI probe found them hard to read).
  struct QuietVtk {
    const int before = vtkObject::GetGlobalWarningDisplay();
    QuietVtk() { vtkObject::GlobalWarningDisplayOff(); }
    ~QuietVtk() { vtkObject::SetGlobalWarningDisplay(before); }
  } quiet;
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
  if (reader->GetErrorCode() != 0 || !grid || grid->GetNumberOfCells() == 0)
    throw RenderInputError("'" + file.string() +
                           "' is not a readable framequake frame (VTK XML unstructured grid): it is cut short, "
                           "damaged or empty");
  return grid;
}

vtkDataArray* int_array(vtkUnstructuredGrid* grid, const char* name) { return grid->GetCellData()->GetArray(name); }

struct Bounds {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};
  bool valid() const { return lo[0] <= hi[0]; }
  void add(const double p[3]) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  double diagonal() const {
    return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  }
};

// One frame turned into things to draw.
struct FrameScene {
  vtkNew<vtkPolyData> members;  // quads, colour per cell
  vtkNew<vtkPolyData> ground;
  vtkNew<vtkPolyData> broken_joints;  // one point per broken joint
  bool has_damage_state = false;
};

// VTK_HEXAHEDRON faces (vtkHexahedron's point order).
constexpr int kHexFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

void build_scene(vtkUnstructuredGrid* grid, FrameScene& out) {
  vtkDataArray* body_id = int_array(grid, "body_id");
  vtkDataArray* kind = int_array(grid, "member_kind");
  vtkDataArray* damage = int_array(grid, "damage_state");
  vtkDataArray* joint_id = int_array(grid, "joint_id");
  vtkDataArray* joint_broken = int_array(grid, "joint_broken");
  if (!body_id || !kind) throw RenderInputError("frame has no body_id / member_kind cell arrays (not a framequake frame)");
  out.has_damage_state = damage != nullptr;

  vtkNew<vtkPoints> member_pts, ground_pts;
  vtkNew<vtkCellArray> member_quads, ground_quads;
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetName("colour");
  colours->SetNumberOfComponents(3);
  std::map<int, std::pair<std::array<double, 3>, int>> broken;  // joint id -> (sum of midpoints, count)

  vtkNew<vtkIdList> ids;
  const vtkIdType n = grid->GetNumberOfCells();
  for (vtkIdType c = 0; c < n; ++c) {
    const int type = grid->GetCellType(c);
    if (type == VTK_HEXAHEDRON && body_id->GetTuple1(c) >= 0) {
      grid->GetCellPoints(c, ids);
      if (ids->GetNumberOfIds() != 8) continue;
      const bool is_ground = int(kind->GetTuple1(c)) == kMemberKindGround;
      vtkPoints* pts = is_ground ? ground_pts.Get() : member_pts.Get();
      vtkCellArray* quads = is_ground ? ground_quads.Get() : member_quads.Get();
      const vtkIdType base = pts->GetNumberOfPoints();
      for (int k = 0; k < 8; ++k) pts->InsertNextPoint(grid->GetPoint(ids->GetId(k)));
      int state = damage ? int(damage->GetTuple1(c)) : 0;
      state = std::clamp(state, 0, 3);
      for (const auto& f : kHexFaces) {
        const vtkIdType q[4] = {base + f[0], base + f[1], base + f[2], base + f[3]};
        quads->InsertNextCell(4, q);
        if (!is_ground) {
          const auto& col = kDamageColour[std::size_t(state)];
          colours->InsertNextTuple3(col[0], col[1], col[2]);
        }
      }
    } else if (type == VTK_LINE && joint_id && joint_broken && joint_broken->GetTuple1(c) > 0.5) {
      grid->GetCellPoints(c, ids);
      if (ids->GetNumberOfIds() != 2) continue;
      double a[3], b[3];
      grid->GetPoint(ids->GetId(0), a);
      grid->GetPoint(ids->GetId(1), b);
      auto& [sum, count] = broken[int(joint_id->GetTuple1(c))];
      for (int k = 0; k < 3; ++k) sum[std::size_t(k)] += 0.5 * (a[k] + b[k]);
      ++count;
    }
  }
  out.members->Initialize();
  out.members->SetPoints(member_pts);
  out.members->SetPolys(member_quads);
  out.members->GetCellData()->SetScalars(colours);
  out.ground->Initialize();
  out.ground->SetPoints(ground_pts);
  out.ground->SetPolys(ground_quads);
  vtkNew<vtkPoints> marker_pts;
  for (const auto& [id, acc] : broken) {
    const auto& [sum, count] = acc;
    marker_pts->InsertNextPoint(sum[0] / count, sum[1] / count, sum[2] / count);
  }
  out.broken_joints->Initialize();
  out.broken_joints->SetPoints(marker_pts);
}

// Members' bounds over every frame (the ground body excluded), and the top of the ground.
void scan_bounds(const RunData& run, Bounds& io_bounds, double& io_ground_top_m, bool& io_has_ground) {
  vtkNew<vtkIdList> ids;
  for (const RunFrame& f : run.frames) {
    const auto grid = read_vtu(f.file);
    vtkDataArray* body_id = int_array(grid, "body_id");
    vtkDataArray* kind = int_array(grid, "member_kind");
    if (!body_id || !kind)
      throw RenderInputError("'" + f.file.string() + "' has no body_id / member_kind cell arrays (not a framequake frame)");
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
      if (grid->GetCellType(c) != VTK_HEXAHEDRON || body_id->GetTuple1(c) < 0) continue;
      grid->GetCellPoints(c, ids);
      const bool is_ground = int(kind->GetTuple1(c)) == kMemberKindGround;
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
        const double* p = grid->GetPoint(ids->GetId(k));
        if (is_ground) {
          io_ground_top_m = io_has_ground ? std::max(io_ground_top_m, p[2]) : p[2];
          io_has_ground = true;
        } else {
          io_bounds.add(p);
        }
      }
    }
  }
}

// Places the camera so that every corner of `b` is inside the view with a margin.
void frame_camera(vtkCamera* cam, const Bounds& b, double aspect) {
  const double az = kAzimuthDeg * kPi / 180.0, el = kElevationDeg * kPi / 180.0;
  const double dir[3] = {std::cos(el) * std::sin(az), -std::cos(el) * std::cos(az), std::sin(el)};  // to the camera
  // right = forward x z_up with forward = -dir; up = right x forward.
  double right[3] = {-dir[1], dir[0], 0.0};
  const double rn = std::hypot(right[0], right[1]);
  right[0] /= rn, right[1] /= rn;
  // up = right x forward = right x (-dir) = dir x right
  const double up[3] = {-(right[1] * dir[2]), right[0] * dir[2], right[1] * dir[0] - right[0] * dir[1]};
  const double c[3] = {0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1]), 0.5 * (b.lo[2] + b.hi[2])};
  const double tan_y = std::tan(0.5 * kViewAngleDeg * kPi / 180.0), tan_x = tan_y * aspect;
  double distance = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    double rel[3];
    for (int k = 0; k < 3; ++k) rel[k] = ((corner >> k) & 1 ? b.hi[k] : b.lo[k]) - c[k];
    const double x = rel[0] * right[0] + rel[1] * right[1] + rel[2] * right[2];
    const double y = rel[0] * up[0] + rel[1] * up[1] + rel[2] * up[2];
    const double z = rel[0] * dir[0] + rel[1] * dir[1] + rel[2] * dir[2];
    distance = std::max({distance, z + kFrameMargin * std::abs(x) / tan_x, z + kFrameMargin * std::abs(y) / tan_y});
  }
  distance = std::max(distance, 1e-3);
  cam->SetViewAngle(kViewAngleDeg);
  cam->SetFocalPoint(c);
  cam->SetPosition(c[0] + distance * dir[0], c[1] + distance * dir[1], c[2] + distance * dir[2]);
  cam->SetViewUp(up);
}

std::string time_label(double t) {
  std::ostringstream s;
  s << "t = " << std::fixed << std::setprecision(3) << t << " s";
  return s.str();
}

vtkSmartPointer<vtkTextActor> make_text(vtkRenderer* ren, const std::string& text, double x, double y, int size,
                                        const std::array<std::uint8_t, 3>& colour, bool right = false, bool top = true) {
  auto actor = vtkSmartPointer<vtkTextActor>::New();
  actor->SetInput(text.c_str());
  actor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  actor->GetPositionCoordinate()->SetValue(x, y);
  vtkTextProperty* tp = actor->GetTextProperty();
  tp->SetFontSize(size);
  tp->SetColor(colour[0] / 255.0, colour[1] / 255.0, colour[2] / 255.0);
  tp->SetFontFamilyToArial();
  if (right) tp->SetJustificationToRight();
  if (top) tp->SetVerticalJustificationToTop();
  ren->AddActor2D(actor);
  return actor;
}

vtkSmartPointer<vtkActor2D> make_polyline_2d(vtkRenderer* ren, vtkPolyData* data, const std::array<std::uint8_t, 3>& colour,
                                             float width) {
  vtkNew<vtkCoordinate> coord;
  coord->SetCoordinateSystemToNormalizedViewport();
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(data);
  mapper->SetTransformCoordinate(coord);
  auto actor = vtkSmartPointer<vtkActor2D>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(colour[0] / 255.0, colour[1] / 255.0, colour[2] / 255.0);
  actor->GetProperty()->SetLineWidth(width);
  ren->AddActor2D(actor);
  return actor;
}

// Trace plot area inside the trace viewport (normalised viewport coordinates).
constexpr double kPlotX0 = 0.06, kPlotX1 = 0.97, kPlotY0 = 0.08, kPlotY1 = 0.62;

struct Panel {
  const RunData* run = nullptr;
  std::size_t shown = std::numeric_limits<std::size_t>::max();  // index of the frame drawn
  vtkNew<vtkRenderer> scene, trace;
  vtkNew<vtkRenderer> overlay;  // layer 1 over `scene`, same camera: markers never hidden
  FrameScene frame;
  vtkNew<vtkPolyData> cursor;
  vtkSmartPointer<vtkTextActor> time_text;
  vtkSmartPointer<vtkActor> broken_actor;
};

void set_cursor(vtkPolyData* cursor, double x) {
  vtkNew<vtkPoints> p;
  p->InsertNextPoint(x, kPlotY0 - 0.04, 0);
  p->InsertNextPoint(x, kPlotY1 + 0.02, 0);
  vtkNew<vtkCellArray> l;
  const vtkIdType ids[2] = {0, 1};
  l->InsertNextCell(2, ids);
  cursor->Initialize();
  cursor->SetPoints(p);
  cursor->SetLines(l);
}

std::vector<double> merged_times(const std::vector<RunData>& runs, int every) {
  std::vector<double> all;
  for (const RunData& r : runs)
    for (const RunFrame& f : r.frames) all.push_back(f.time_s);
  std::sort(all.begin(), all.end());
  std::vector<double> unique;
  for (const double t : all)
    if (unique.empty() || t - unique.back() > 1e-9) unique.push_back(t);
  std::vector<double> kept;
  for (std::size_t i = 0; i < unique.size(); i += std::size_t(every)) kept.push_back(unique[i]);
  if (!unique.empty() && kept.back() != unique.back() && every > 1) kept.push_back(unique.back());
  return kept;
}

// Pipe of raw RGB frames into ffmpeg for MP4 output.
class FfmpegPipe {
 public:
  FfmpegPipe(const fs::path& file, int w, int h, double fps) : file_(file), temp_(fs::path(file).concat(".part")) {
    std::ostringstream cmd;
    cmd << "ffmpeg -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgb24 -s " << w << "x" << h << " -r " << fps
        << " -i - -c:v libx264 -pix_fmt yuv420p -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -f mp4 '" << temp_.string() << "'";
    // A dead ffmpeg must give a write error and a message, not kill us with SIGPIPE.
    old_sigpipe_ = std::signal(SIGPIPE, SIG_IGN);
    pipe_ = popen(cmd.str().c_str(), "w");
    if (!pipe_) throw std::runtime_error("cannot start ffmpeg for '" + file.string() + "'");
  }
  ~FfmpegPipe() {
    if (pipe_) pclose(pipe_);
    std::signal(SIGPIPE, old_sigpipe_);
    std::error_code ec;
    if (!done_) fs::remove(temp_, ec);
  }
  void add(const std::vector<std::uint8_t>& rgb) {
    if (std::fwrite(rgb.data(), 1, rgb.size(), pipe_) != rgb.size())
      throw std::runtime_error("ffmpeg stopped while writing '" + file_.string() + "'");
  }
  void finish() {
    const int rc = pclose(pipe_);
    pipe_ = nullptr;
    if (rc != 0) throw std::runtime_error("ffmpeg failed writing '" + file_.string() + "' (exit status " + std::to_string(rc) + ")");
    std::error_code ec;
    fs::rename(temp_, file_, ec);
    if (ec) throw std::runtime_error("cannot rename '" + temp_.string() + "' to '" + file_.string() + "'");
    done_ = true;
  }

 private:
  fs::path file_, temp_;
  FILE* pipe_ = nullptr;
  bool done_ = false;
  void (*old_sigpipe_)(int) = SIG_DFL;
};

bool ffmpeg_available() { return std::system("ffmpeg -version >/dev/null 2>&1") == 0; }

std::string lower_extension(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return e;
}

}  // namespace

RenderReport render_runs(const std::vector<RunData>& runs, const RenderOptions& options) {
  const auto t_start = Clock::now();
  const std::clock_t cpu_start = std::clock();
  if (runs.empty()) throw RenderInputError("no run to render");
  if (options.panel_width_px < 64 || options.panel_height_px < 64 || options.panel_width_px > 4096 ||
      options.panel_height_px > 4096)
    throw RenderInputError("--size: each side must be 64..4096 pixels");
  if (!(options.frames_per_second > 0.0 && options.frames_per_second <= 100.0))
    throw RenderInputError("--fps must be in (0, 100]");
  if (options.every < 1) throw RenderInputError("--every must be a whole number >= 1");
  if (options.animation.empty() && !options.png_folder) throw RenderInputError("nothing to write: no animation file and no --png");
  bool mp4 = false;
  if (!options.animation.empty()) {
    const std::string ext = lower_extension(options.animation);
    if (ext == ".mp4") {
      if (options.animation.string().find('\'') != std::string::npos)
        throw RenderInputError("'" + options.animation.string() + "': an MP4 path must not contain a single quote");
      if (!ffmpeg_available())
        throw RenderInputError("'" + options.animation.string() +
                               "': MP4 needs ffmpeg on PATH (apt-get install ffmpeg); write a .gif instead");
      mp4 = true;
    } else if (ext != ".gif") {
      throw RenderInputError("'" + options.animation.string() + "': the animation must end in .gif or .mp4");
    }
    // A missing folder is made, as run, compare and sweep make theirs (it
    // was refused: workflow probe); a file in its place is refused.
    const fs::path parent = options.animation.parent_path();
    if (!parent.empty() && !fs::is_directory(parent)) {
      std::error_code ec;
      if (fs::exists(parent, ec))
        throw RenderInputError("'" + parent.string() + "' (folder of the animation file) is a file, not a folder");
      fs::create_directories(parent, ec);
      if (ec)
        throw RenderInputError("'" + parent.string() + "' (folder of the animation file) cannot be made: " +
                               ec.message());
    }
  }

  RenderReport report;
  const int n_runs = int(runs.size());
  const int W = options.panel_width_px * n_runs, H = options.panel_height_px;
  report.width_px = W;
  report.height_px = H;

  // Camera and scales common to all panels.
  Bounds bounds;
  double ground_top = 0.0;
  bool has_ground = false;
  auto t0 = Clock::now();
  for (const RunData& r : runs) scan_bounds(r, bounds, ground_top, has_ground);
  report.read_s += seconds_since(t0);
  if (!bounds.valid()) throw RenderInputError("the runs' frames hold no members to draw");
  if (has_ground) bounds.lo[2] = std::min(bounds.lo[2], ground_top);
  const double marker_radius_m = 0.02 * bounds.diagonal();

  // Ground acceleration: the component with the largest peak over all runs.
  int axis = -1;
  double peak = 0.0;
  for (const RunData& r : runs)
    for (int k = 0; k < 3; ++k)
      for (const double a : r.ground_accel_mps2[k])
        if (std::abs(a) > peak) peak = std::abs(a), axis = k;
  const std::vector<double> times = merged_times(runs, options.every);
  double t_end = times.back();
  for (const RunData& r : runs)
    if (!r.history_time_s.empty()) t_end = std::max(t_end, r.history_time_s.back());
  const double t_begin = std::min(0.0, times.front());
  const double t_span = std::max(t_end - t_begin, 1e-12);
  const auto plot_x = [&](double t) { return kPlotX0 + (kPlotX1 - kPlotX0) * (t - t_begin) / t_span; };

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);  // exact colours: no blending along edges
  window->SetSize(W, H);
  window->SetNumberOfLayers(2);
  window->SetAlphaBitPlanes(0);

  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(marker_radius_m);
  sphere->SetThetaResolution(16);
  sphere->SetPhiResolution(12);

  std::vector<std::unique_ptr<Panel>> panels;
  for (int i = 0; i < n_runs; ++i) {
    auto p = std::make_unique<Panel>();
    p->run = &runs[std::size_t(i)];
    const double x0 = double(i) / n_runs, x1 = double(i + 1) / n_runs;
    p->scene->SetViewport(x0, kTraceHeightFraction, x1, 1.0);
    p->trace->SetViewport(x0, 0.0, x1, kTraceHeightFraction);
    p->scene->SetBackground(kSkyColour[0] / 255.0, kSkyColour[1] / 255.0, kSkyColour[2] / 255.0);
    p->trace->SetBackground(kTraceBackground[0] / 255.0, kTraceBackground[1] / 255.0, kTraceBackground[2] / 255.0);
    p->overlay->SetViewport(x0, kTraceHeightFraction, x1, 1.0);
    p->overlay->SetLayer(1);
    p->overlay->SetActiveCamera(p->scene->GetActiveCamera());
    window->AddRenderer(p->scene);
    window->AddRenderer(p->trace);
    window->AddRenderer(p->overlay);

    // Members: flat-shaded boxes coloured per cell, with dark edges.
    vtkNew<vtkPolyDataMapper> members_mapper;
    members_mapper->SetInputData(p->frame.members);
    members_mapper->SetScalarModeToUseCellData();
    members_mapper->SetColorModeToDirectScalars();
    vtkNew<vtkActor> members;
    members->SetMapper(members_mapper);
    members->GetProperty()->SetAmbient(0.35);
    members->GetProperty()->SetDiffuse(0.65);
    members->GetProperty()->SetSpecular(0.0);
    members->GetProperty()->SetEdgeVisibility(1);
    members->GetProperty()->SetEdgeColor(0.1, 0.1, 0.1);
    p->scene->AddActor(members);

    vtkNew<vtkPolyDataMapper> ground_mapper;
    ground_mapper->SetInputData(p->frame.ground);
    ground_mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> ground;
    ground->SetMapper(ground_mapper);
    set_colour(ground->GetProperty(), kGroundColour);
    // Mostly ambient: the headlight grazes the ground, which would turn dark.
    ground->GetProperty()->SetAmbient(0.7);
    ground->GetProperty()->SetDiffuse(0.3);
    p->scene->AddActor(ground);

    // Broken joints: unlit spheres, so the marker colour is exact in every
    // pixel, drawn in the overlay layer so that members never hide them.
    vtkNew<vtkGlyph3D> glyphs;
    glyphs->SetInputData(p->frame.broken_joints);
    glyphs->SetSourceConnection(sphere->GetOutputPort());
    glyphs->ScalingOff();
    glyphs->OrientOff();
    vtkNew<vtkPolyDataMapper> broken_mapper;
    broken_mapper->SetInputConnection(glyphs->GetOutputPort());
    broken_mapper->ScalarVisibilityOff();
    p->broken_actor = vtkSmartPointer<vtkActor>::New();
    p->broken_actor->SetMapper(broken_mapper);
    set_colour(p->broken_actor->GetProperty(), kBrokenJointColour);
    p->broken_actor->GetProperty()->LightingOff();
    p->overlay->AddActor(p->broken_actor);

    frame_camera(p->scene->GetActiveCamera(), bounds, double(options.panel_width_px) / ((1.0 - kTraceHeightFraction) * H));
    // The ground box is large: clip planes come from the members' bounds.
    {
      double lo[3], hi[3];
      for (int k = 0; k < 3; ++k) lo[k] = bounds.lo[k], hi[k] = bounds.hi[k];
      const double d = bounds.diagonal();
      p->scene->ResetCameraClippingRange(lo[0] - 4 * d, hi[0] + 4 * d, lo[1] - 4 * d, hi[1] + 4 * d, lo[2] - d, hi[2] + d);
    }

    // Text sizes are chosen for the default 800 px panel; a narrower panel
    // scales them down (to half at most, 7 pt at least, which stays
    // legible) so that the label row and the legend still fit side by side
    // (at 320 px wide the full sizes ran into the next panel).
    const double text_scale = std::clamp(options.panel_width_px / 800.0, 0.5, 1.0);
    const auto font = [&](int size_pt) { return std::max(7, int(std::lround(size_pt * text_scale))); };
    p->time_text = make_text(p->scene, time_label(times.front()), 0.02, 0.97, font(20), {0, 0, 0});
    // The time stamp takes about 200 px at the full size, a glyph about
    // 12 px: the folder's name gets the rest of the row.
    const std::size_t label_chars =
        std::size_t(std::max(8.0, (0.96 * options.panel_width_px - 200.0 * text_scale) / (12.0 * text_scale)));
    make_text(p->scene, shortened_label(p->run->label, label_chars), 0.98, 0.97, font(20), {0, 0, 0}, true);

    // Acceleration trace, common scale over the panels.
    const std::array<std::uint8_t, 3> light{220, 220, 220};
    vtkNew<vtkPolyData> axis_line;
    {
      vtkNew<vtkPoints> pts;
      const double y_zero = 0.5 * (kPlotY0 + kPlotY1);
      pts->InsertNextPoint(kPlotX0, y_zero, 0);
      pts->InsertNextPoint(kPlotX1, y_zero, 0);
      vtkNew<vtkCellArray> l;
      const vtkIdType ids[2] = {0, 1};
      l->InsertNextCell(2, ids);
      axis_line->SetPoints(pts);
      axis_line->SetLines(l);
    }
    make_polyline_2d(p->trace, axis_line, {90, 90, 110}, 1.0f);
    std::ostringstream label;
    if (axis >= 0) {
      const std::vector<double>& a = p->run->ground_accel_mps2[axis];
      const std::vector<double>& t = p->run->history_time_s;
      vtkNew<vtkPolyData> trace_line;
      vtkNew<vtkPoints> pts;
      const std::size_t n = std::min(a.size(), t.size());
      // At most ~4 samples per pixel column: thinner gains nothing on screen.
      const std::size_t stride = std::max<std::size_t>(1, n / std::size_t(4 * options.panel_width_px));
      for (std::size_t k = 0; k < n; k += stride)
        pts->InsertNextPoint(plot_x(t[k]), 0.5 * (kPlotY0 + kPlotY1) + 0.5 * (kPlotY1 - kPlotY0) * a[k] / peak, 0);
      vtkNew<vtkCellArray> line;
      line->InsertNextCell(int(pts->GetNumberOfPoints()));
      for (vtkIdType k = 0; k < pts->GetNumberOfPoints(); ++k) line->InsertCellPoint(k);
      trace_line->SetPoints(pts);
      trace_line->SetLines(line);
      make_polyline_2d(p->trace, trace_line, light, 1.5f);
      double own_peak = 0.0;
      for (const double v : a) own_peak = std::max(own_peak, std::abs(v));
      label << "ground acceleration " << "xyz"[axis] << " (m/s^2), peak " << std::setprecision(3) << own_peak
            << "; full scale +-" << std::setprecision(3) << peak;
    } else {
      label << "no ground motion (zero or absent in history.csv)";
    }
    make_text(p->trace, label.str(), 0.02, 0.97, font(13), light);
    // Legend of the damage colours, right-aligned, on the row below the
    // label. Laid out from the right edge with an estimated glyph width
    // (Arial is at most about 2/3 of its point size wide per character:
    // 8 px at 12 pt) and a gap of 16 px at 12 pt.
    static const char* names[5] = {"intact", "yielded", "damaged", "detached", "* broken joint"};
    const int legend_pt = font(12);
    double x = 0.98;
    for (int s = 4; s >= 0; --s) {
      const auto& colour = s == 4 ? kBrokenJointColour : kDamageColour[std::size_t(s)];
      make_text(p->trace, names[s], x, 0.80, legend_pt, colour, true);
      x -= (legend_pt / 12.0) * (8.0 * double(std::char_traits<char>::length(names[s])) + 16.0) /
           options.panel_width_px;
    }
    make_polyline_2d(p->trace, p->cursor, {255, 204, 0}, 2.0f);
    set_cursor(p->cursor, plot_x(times.front()));
    panels.push_back(std::move(p));
  }

  {
    // The first render creates the OpenGL context, before any file is
    // opened: VTK aborts the process when it cannot, and nothing must be
    // left half written then. Mesa loads its driver with dlopen and keeps a
    // few allocations for the life of the process (LeakSanitizer reports
    // them from an unloaded module); they are not ours to free, so they are
    // not tracked. Allocations of every later render are.
    [[maybe_unused]] const LeakCheckPause pause;
    window->Render();
  }

  std::unique_ptr<GifWriter> gif;
  std::unique_ptr<FfmpegPipe> ffmpeg;
  if (!options.animation.empty()) {
    const int delay_cs = std::max(1, int(std::lround(100.0 / options.frames_per_second)));
    if (mp4)
      ffmpeg = std::make_unique<FfmpegPipe>(options.animation, W, H, options.frames_per_second);
    else
      gif = std::make_unique<GifWriter>(options.animation, W, H, delay_cs);
  }
  if (options.png_folder) {
    std::error_code ec;
    fs::create_directories(*options.png_folder, ec);
    if (ec) throw std::runtime_error("cannot create '" + options.png_folder->string() + "': " + ec.message());
    // An earlier render's frames beyond this one's count would stay beside
    // the new ones and be taken for them (workflow probe: 5 new frames
    // among 123 old). Only files named as this writes them are removed.
    std::vector<fs::path> stale;
    for (const fs::directory_entry& e : fs::directory_iterator(*options.png_folder, ec)) {
      const std::string n = e.path().filename().string();
      if (n.size() == 16 && n.compare(0, 6, "frame_") == 0 && n.compare(12, 4, ".png") == 0 &&
          std::all_of(n.begin() + 6, n.begin() + 12, [](char c) { return c >= '0' && c <= '9'; }) &&
          e.is_regular_file())
        stale.push_back(e.path());
    }
    if (ec) throw std::runtime_error("cannot read '" + options.png_folder->string() + "': " + ec.message());
    for (const fs::path& f : stale)
      if (!fs::remove(f, ec) && ec)
        throw std::runtime_error("cannot remove the earlier frame '" + f.string() + "': " + ec.message());
  }

  bool warned_no_damage = false;
  std::vector<std::uint8_t> rgb(std::size_t(W) * std::size_t(H) * 3);
  vtkNew<vtkUnsignedCharArray> pixels;
  for (std::size_t fi = 0; fi < times.size(); ++fi) {
    // Unwinding removes the animation's .part file (GifWriter, FfmpegPipe).
    if (options.stop_requested && options.stop_requested->load()) {
      // The PNG images already written stay, and are said to (a probe's
      // stopped render left 13 of them unmentioned).
      std::string what = "stopped on request (Ctrl-C, SIGTERM or SIGHUP) after " + std::to_string(fi) + " of " +
                         std::to_string(times.size()) + " frames";
      if (!options.animation.empty()) what += "; no animation was written";
      if (options.png_folder)
        what += fi == 0 ? std::string("; no PNG image was written")
                        : "; the PNG images of the first " + std::to_string(fi) + " frames stay in '" +
                              options.png_folder->string() + "' (frame_000000.png to " +
                              png_frame_name(fi - 1) + ")";
      throw RenderStopped(what);
    }
    const double t = times[fi];
    t0 = Clock::now();
    for (auto& p : panels) {
      // Last frame of this run at or before t (the first one before it starts).
      const auto& frames = p->run->frames;
      std::size_t k = 0;
      while (k + 1 < frames.size() && frames[k + 1].time_s <= t + 1e-9) ++k;
      if (k != p->shown) {
        const auto grid = read_vtu(frames[k].file);
        build_scene(grid, p->frame);
        if (!p->frame.has_damage_state && !warned_no_damage) {
          std::fprintf(stderr, "framequake render: warning: '%s' has no damage_state array (written by an older framequake); "
                               "members are drawn in the intact colour\n", frames[k].file.string().c_str());
          warned_no_damage = true;
        }
        p->frame.members->Modified();
        p->frame.ground->Modified();
        p->frame.broken_joints->Modified();
        p->shown = k;
      }
      p->time_text->SetInput(time_label(t).c_str());
      set_cursor(p->cursor, plot_x(t));
    }
    report.read_s += seconds_since(t0);

    t0 = Clock::now();
    window->Render();
    pixels->SetNumberOfComponents(3);
    window->GetPixelData(0, 0, W - 1, H - 1, 0, pixels, 0);
    report.draw_s += seconds_since(t0);

    t0 = Clock::now();
    // OpenGL rows run bottom to top; images top to bottom.
    const std::uint8_t* src = pixels->GetPointer(0);
    const std::size_t row = std::size_t(W) * 3;
    for (int y = 0; y < H; ++y)
      std::copy(src + std::size_t(H - 1 - y) * row, src + std::size_t(H - y) * row, rgb.begin() + std::ptrdiff_t(std::size_t(y) * row));
    if (gif) gif->add_frame(rgb);
    if (ffmpeg) ffmpeg->add(rgb);
    if (options.png_folder) {
      vtkNew<vtkImageData> image;
      image->SetDimensions(W, H, 1);
      image->GetPointData()->SetScalars(pixels);
      const fs::path file = *options.png_folder / png_frame_name(fi);
      vtkNew<vtkPNGWriter> png;
      png->SetInputData(image);
      png->SetFileName(file.c_str());
      png->Write();
      if (png->GetErrorCode() != 0) throw std::runtime_error("cannot write '" + file.string() + "'");
    }
    report.encode_s += seconds_since(t0);
    report.frame_time_s.push_back(t);
    ++report.frames;
    if (options.on_frame) options.on_frame(report.frames, int(times.size()));
  }
  t0 = Clock::now();
  if (gif) gif->finish();
  if (ffmpeg) ffmpeg->finish();
  report.encode_s += seconds_since(t0);
  report.wall_s = seconds_since(t_start);
  report.cpu_s = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  return report;
}

std::string shortened_label(const std::string& label, std::size_t max_chars) {
  if (label.size() <= max_chars || max_chars < 5) return label;
  const std::size_t keep = max_chars - 3;
  std::size_t head = (keep + 1) / 2, tail_from = label.size() - (keep - head);
  // Bytes, not characters: no cut inside a UTF-8 character (a folder
  // named in Japanese), whose continuation bytes are 10xxxxxx.
  const auto continuation = [&](std::size_t i) { return (static_cast<unsigned char>(label[i]) & 0xC0) == 0x80; };
  while (head > 0 && continuation(head)) --head;
  while (tail_from < label.size() && continuation(tail_from)) ++tail_from;
  return label.substr(0, head) + "..." + label.substr(tail_from);
}

}  // namespace fq::render
