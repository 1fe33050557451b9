#include "io/vtk_frame_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <stdexcept>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "io/atomic_file.h"

namespace fq {

static_assert(static_cast<int>(VtkCellType::Vertex) == VTK_VERTEX);
static_assert(static_cast<int>(VtkCellType::Line) == VTK_LINE);
static_assert(static_cast<int>(VtkCellType::Hexahedron) == VTK_HEXAHEDRON);

namespace {
constexpr int kMaxComponents = 9;  // a 3x3 tensor is the largest thing a cell carries

// Removes the L2-norm range caches VTK's writer puts into the XML as
// <InformationKey> elements. They are not data (the reader recomputes them),
// and for an array holding NaN (the fill value on the cells of other blocks)
// VTK writes one that its own reader cannot parse, logging an error per
// array. Only the XML before <AppendedData> is touched; the appended
// offsets count from the start of that section, so they stay right.
std::string without_range_caches(std::string xml) {
  const std::size_t end_of_xml = std::min(xml.find("<AppendedData"), xml.size());
  std::string out;
  out.reserve(xml.size());
  std::size_t pos = 0;
  for (;;) {
    std::size_t key = xml.find("<InformationKey name=\"L2_NORM", pos);
    if (key == std::string::npos || key >= end_of_xml) break;
    const std::size_t close = xml.find("</InformationKey>", key);
    if (close == std::string::npos || close >= end_of_xml) break;
    std::size_t from = key;  // from the start of its line
    while (from > pos && (xml[from - 1] == ' ' || xml[from - 1] == '\t')) --from;
    std::size_t to = close + std::string_view("</InformationKey>").size();
    if (to < xml.size() && xml[to] == '\n') ++to;
    out.append(xml, pos, from - pos);
    pos = to;
  }
  out.append(xml, pos, std::string::npos);
  return out;
}
}  // namespace

// ---- VtkFrameBuilder ---------------------------------------------------------

void VtkFrameBuilder::clear() {
  points_m_.clear();
  connectivity_.clear();
  offsets_.assign(1, 0);
  cell_types_.clear();
  arrays_.clear();
  double_fields_.clear();
  string_fields_.clear();
  cell_block_.clear();
  current_block_ = 0;
}

VtkFrameBuilder::Index VtkFrameBuilder::add_point(const Vec3& p_m) {
  points_m_.insert(points_m_.end(), {p_m.x(), p_m.y(), p_m.z()});
  return point_count() - 1;
}

VtkFrameBuilder::Index VtkFrameBuilder::add_cell(VtkCellType type, std::span<const Index> point_ids) {
  const Index n_points = point_count();
  for (const Index id : point_ids)
    if (id < 0 || id >= n_points) throw std::out_of_range("VtkFrameBuilder::add_cell: point id out of range");
  connectivity_.insert(connectivity_.end(), point_ids.begin(), point_ids.end());
  offsets_.push_back(Index(connectivity_.size()));
  cell_types_.push_back(static_cast<std::uint8_t>(type));
  cell_block_.push_back(current_block_);
  return cell_count() - 1;
}

VtkFrameBuilder::ArrayId VtkFrameBuilder::cell_array(std::string_view name, VtkArrayType type, int components,
                                                      double fill) {
  if (components < 1 || components > kMaxComponents)
    throw std::invalid_argument("cell array '" + std::string(name) + "': component count must be 1.." +
                                std::to_string(kMaxComponents));
  if (name == "cell_block") throw std::invalid_argument("cell array name 'cell_block' is reserved");
  for (std::size_t a = 0; a < arrays_.size(); ++a) {
    if (arrays_[a].name == name) {
      if (arrays_[a].type != type || arrays_[a].components != components)
        throw std::invalid_argument("cell array '" + std::string(name) +
                                    "' declared twice with different type or component count");
      return {a};
    }
  }
  arrays_.push_back({std::string(name), type, components, fill, {}});
  return {arrays_.size() - 1};
}

void VtkFrameBuilder::set(ArrayId array, Index cell, int component, double value) {
  CellArray& a = arrays_.at(array.index);
  if (cell < 0 || cell >= cell_count()) throw std::out_of_range("cell array '" + a.name + "': cell index out of range");
  if (component < 0 || component >= a.components)
    throw std::out_of_range("cell array '" + a.name + "': component out of range");
  const std::size_t at = std::size_t(cell) * std::size_t(a.components) + std::size_t(component);
  if (a.values.size() <= at) a.values.resize(std::size_t(cell + 1) * std::size_t(a.components), a.fill);
  a.values[at] = value;
}

void VtkFrameBuilder::set(ArrayId array, Index cell, const Vec3& v) {
  for (int k = 0; k < 3; ++k) set(array, cell, k, v[k]);
}

void VtkFrameBuilder::add_field(std::string name, double value) { double_fields_.emplace_back(std::move(name), value); }

void VtkFrameBuilder::add_field(std::string name, std::vector<std::string> values) {
  string_fields_.push_back({std::move(name), std::move(values)});
}

// ---- VtkFrameWriter ----------------------------------------------------------

namespace {
// VTK runs some of its array work (value ranges for the XML writer) on its
// SMP backend, which on Debian is TBB: a pool of worker threads that spin
// and yield between calls. A frame holds a few hundred points, so the pool
// gains nothing, while its threads take CPU from the engine's own OpenMP
// threads and from the other runs of `compare --jobs`. The frame writer
// therefore asks for VTK's sequential backend through VTK's own variable,
// which VTK reads when it first uses the backend (vtkSMPToolsAPI), unless
// the user has set that variable. (vtkSMPTools::SetBackend would say the
// same, but VTK 9.1's vtkSMPTools.h does not compile as C++20.)
void select_sequential_vtk_backend_once() {
  static const bool selected = [] { return ::setenv("VTK_SMP_BACKEND_IN_USE", "Sequential", 0) == 0; }();
  (void)selected;
}

// Writing one frame, VTK allocates and frees some forty blocks (among them
// the per-thread buffers of every SMP backend it was built with, made for
// each array's value range). With glibc's default trim threshold the freed
// top of the heap went back to the kernel after most frames and was faulted
// in again by the next: a run of frame B made 25 482 brk calls, and its
// page faults and brk calls took about 8 % of the run's samples (perf,
// 2026-11-27). A trim threshold of 256 MiB keeps the freed pages for the
// next frame (13 brk calls; the run's peak resident set stays 32 MB). The
// main heap still returns a free top above 256 MiB; the heaps glibc gives
// other threads (compare and sweep run each case on one) are at most
// 64 MiB each and now keep what they freed, for the next case on that
// thread. Setting the threshold ends glibc's own adjustment of the mmap
// threshold, so that one is set to 32 MiB, the highest value glibc
// accepts and its adjustment could reach on 64-bit, and blocks below it
// keep coming from the heap. A user who sets glibc's MALLOC_TRIM_THRESHOLD_
// or MALLOC_MMAP_THRESHOLD_, or any glibc.malloc tunable in GLIBC_TUNABLES,
// keeps glibc's allocator as they set it.
void keep_freed_heap_once() {
#if defined(__GLIBC__)
  static const bool set = [] {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (std::getenv("MALLOC_TRIM_THRESHOLD_") || std::getenv("MALLOC_MMAP_THRESHOLD_") ||
        (tunables && std::strstr(tunables, "glibc.malloc.") != nullptr))
      return false;
    return ::mallopt(M_TRIM_THRESHOLD, 256 << 20) == 1 && ::mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1;
  }();
  (void)set;
#endif
}
}  // namespace

VtkFrameWriter::VtkFrameWriter() {
  select_sequential_vtk_backend_once();
  keep_freed_heap_once();
  add_cell_block("bodies", &VtkFrameWriter::add_bodies);
}
VtkFrameWriter::~VtkFrameWriter() = default;
VtkFrameWriter::VtkFrameWriter(VtkFrameWriter&&) noexcept = default;
VtkFrameWriter& VtkFrameWriter::operator=(VtkFrameWriter&&) noexcept = default;

void VtkFrameWriter::add_cell_block(std::string name, VtkCellBlock block) {
  if (!block) throw std::invalid_argument("cell block '" + name + "' has no callback");
  names_.push_back(std::move(name));
  blocks_.push_back(std::move(block));
}

void VtkFrameWriter::add_bodies(const Simulation& sim, VtkFrameBuilder& frame) {
  const BodyStore& b = sim.bodies();
  const std::size_t n = b.size();
  const auto id = frame.cell_array("body_id", VtkArrayType::Int32, 1, -1.0);
  const auto kind = frame.cell_array("member_kind", VtkArrayType::Int32, 1, -1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto vel = frame.cell_array("velocity_mps", VtkArrayType::Float64, 3, nan);
  const auto omega = frame.cell_array("angular_velocity_radps", VtkArrayType::Float64, 3, nan);
  const auto state = frame.cell_array("state", VtkArrayType::Int32, 1, -1.0);
  // Damage of the member: 0 here; the springs block raises it from its joints
  // (io/src/scene_output.cpp), so a scene without joints still carries it.
  // The ground keeps the fill, -1.
  const auto damage = frame.cell_array("damage_state", VtkArrayType::Int32, 1, -1.0);

  // VTK_HEXAHEDRON order: bottom face 0-1-2-3 counter-clockwise seen from
  // the top face 4-5-6-7 (4 above 0, ...). In body coordinates (signs of the
  // half extents) this is the right-handed order, and a proper rotation keeps
  // it right-handed, so every cell has a positive volume.
  static const double corner_sign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                           {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  std::vector<std::string> names;
  names.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const BodyId body = BodyId(i);
    const Vec3& h = b.half_extents_m[i];
    VtkFrameBuilder::Index corner[8];
    for (int c = 0; c < 8; ++c) {
      const Vec3 local(corner_sign[c][0] * h.x(), corner_sign[c][1] * h.y(), corner_sign[c][2] * h.z());
      corner[c] = frame.add_point(b.to_world(body, local));
    }
    const auto cell = frame.add_cell(VtkCellType::Hexahedron, std::span<const VtkFrameBuilder::Index>(corner, 8));
    frame.set(id, cell, double(i));
    frame.set(kind, cell, double(static_cast<int>(b.info[i].kind)));
    frame.set(vel, cell, b.velocity_mps[i]);
    frame.set(omega, cell, b.angular_velocity_radps[i]);
    frame.set(state, cell, b.is_fixed[i] ? 1.0 : 0.0);
    if (b.info[i].kind != MemberKind::Ground) frame.set(damage, cell, 0.0);  // the ground is no member: -1
    names.push_back(b.info[i].name);
  }
  frame.add_field("body_names", std::move(names));
  std::vector<std::string> kinds;
  for (int k = 0; k <= static_cast<int>(MemberKind::Other); ++k)
    kinds.emplace_back(member_kind_name(static_cast<MemberKind>(k)));
  frame.add_field("member_kind_names", std::move(kinds));
}

namespace {
// What one array of `count` values of `width` bytes each (binary) or of at
// most `text` characters each, separators and line breaks included (ASCII),
// can take in a frame: zlib's worst case on its 32 KiB blocks (compressBound:
// n + n/4096 + n/16384 + 13 a block) and VTK's 64-bit block headers, and
// 512 bytes for the array's XML element.
std::uint64_t array_bound_bytes(std::uint64_t count, std::uint64_t width, std::uint64_t text, bool binary) {
  constexpr std::uint64_t kXmlPerArray = 512;
  if (!binary) return count * text + kXmlPerArray;
  const std::uint64_t n = count * width;
  const std::uint64_t blocks = n / 32768 + 1;
  return n + n / 4096 + n / 16384 + 13 * blocks + 8 * (3 + blocks) + kXmlPerArray;
}
}  // namespace

void VtkFrameWriter::write(const Simulation& sim, const std::filesystem::path& file, bool binary) {
  VtkFrameBuilder& f = builder_;
  f.clear();
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    f.current_block_ = std::int32_t(k);
    blocks_[k](sim, f);
  }
  f.add_field("TimeValue", sim.time_s());
  f.add_field("cell_block_names", names_);

  const vtkIdType n_cells = vtkIdType(f.cell_count());
  {
    // ASCII widths: a double takes at most 24 characters ("-2.2250738585072014e-308"),
    // an int 11, an id 20, a byte 3, and a string's character is written as
    // its code; 3 more each for separators and indentation.
    const auto cells = std::uint64_t(n_cells);
    std::uint64_t bound = 4096;  // the file's XML outside the arrays
    bound += array_bound_bytes(f.points_m_.size(), 8, 27, binary);
    bound += array_bound_bytes(f.connectivity_.size(), 8, 23, binary);
    bound += array_bound_bytes(f.offsets_.size(), 8, 23, binary);
    bound += array_bound_bytes(cells, 1, 6, binary);   // types
    bound += array_bound_bytes(cells, 4, 14, binary);  // cell_block
    for (const VtkFrameBuilder::CellArray& a : f.arrays_)
      bound += array_bound_bytes(cells * std::uint64_t(a.components), a.type == VtkArrayType::Int32 ? 4 : 8,
                                 a.type == VtkArrayType::Int32 ? 14 : 27, binary);
    bound += f.double_fields_.size() * array_bound_bytes(1, 8, 27, binary);
    for (const auto& field : f.string_fields_) {
      std::uint64_t chars = 0;
      for (const std::string& s : field.values) chars += s.size() + 1;  // and its terminator
      bound += array_bound_bytes(chars, 1, 6, binary);
    }
    last_bound_bytes_ = bound;
  }
  vtkNew<vtkUnstructuredGrid> grid;

  vtkNew<vtkDoubleArray> coords;
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(vtkIdType(f.point_count()));
  std::copy(f.points_m_.begin(), f.points_m_.end(), coords->GetPointer(0));
  vtkNew<vtkPoints> points;
  points->SetData(coords);
  grid->SetPoints(points);

  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(vtkIdType(f.offsets_.size()));
  std::copy(f.offsets_.begin(), f.offsets_.end(), offsets->GetPointer(0));
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(vtkIdType(f.connectivity_.size()));
  std::copy(f.connectivity_.begin(), f.connectivity_.end(), connectivity->GetPointer(0));
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  vtkNew<vtkUnsignedCharArray> types;
  types->SetNumberOfTuples(n_cells);
  std::copy(f.cell_types_.begin(), f.cell_types_.end(), types->GetPointer(0));
  grid->SetCells(types, cells);

  vtkNew<vtkIntArray> block;
  block->SetName("cell_block");
  block->SetNumberOfTuples(n_cells);
  std::copy(f.cell_block_.begin(), f.cell_block_.end(), block->GetPointer(0));
  grid->GetCellData()->AddArray(block);

  for (VtkFrameBuilder::CellArray& a : f.arrays_) {
    a.values.resize(std::size_t(n_cells) * std::size_t(a.components), a.fill);
    if (a.type == VtkArrayType::Int32) {
      vtkNew<vtkIntArray> arr;
      arr->SetName(a.name.c_str());
      arr->SetNumberOfComponents(a.components);
      arr->SetNumberOfTuples(n_cells);
      int* dst = arr->GetPointer(0);
      for (std::size_t k = 0; k < a.values.size(); ++k) dst[k] = static_cast<int>(std::lround(a.values[k]));
      grid->GetCellData()->AddArray(arr);
    } else {
      vtkNew<vtkDoubleArray> arr;
      arr->SetName(a.name.c_str());
      arr->SetNumberOfComponents(a.components);
      arr->SetNumberOfTuples(n_cells);
      std::copy(a.values.begin(), a.values.end(), arr->GetPointer(0));
      grid->GetCellData()->AddArray(arr);
    }
  }

  for (const auto& [name, value] : f.double_fields_) {
    vtkNew<vtkDoubleArray> arr;
    arr->SetName(name.c_str());
    arr->SetNumberOfTuples(1);
    arr->SetValue(0, value);
    grid->GetFieldData()->AddArray(arr);
  }
  for (const auto& field : f.string_fields_) {
    vtkNew<vtkStringArray> arr;
    arr->SetName(field.name.c_str());
    arr->SetNumberOfValues(vtkIdType(field.values.size()));
    for (std::size_t k = 0; k < field.values.size(); ++k) arr->SetValue(vtkIdType(k), field.values[k]);
    grid->GetFieldData()->AddArray(arr);
  }

  // The writer fills a string that is then written with one write() call.
  // Writing to the file itself, VTK makes ~60 small writes and seeks back
  // to patch offsets; the string route measured ~15 % faster per frame
  // (1.3 vs 1.5 ms for a 5-box grid on the loaded 2-core build machine).
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetInputData(grid);
  writer->WriteToOutputStringOn();
  writer->SetHeaderTypeToUInt64();
  if (binary) {
    // Raw appended data with zlib compression: the smallest files ParaView
    // reads directly.
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToZLib();
  } else {
    writer->SetDataModeToAscii();
    writer->SetCompressorTypeToNone();
  }
  if (writer->Write() != 1 || writer->GetErrorCode() != 0)
    throw std::runtime_error("VTK could not build frame '" + file.string() + "'");
  detail::write_file_atomically(file, without_range_caches(writer->GetOutputString()));
}

}  // namespace fq
