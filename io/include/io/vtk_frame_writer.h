// One output frame: a VTK unstructured grid (.vtu) of the scene at the time
// of the current poses, written with VTK's own XML writer (appended binary,
// zlib-compressed, by default; ASCII on request).
//
// A frame is a sequence of cell blocks in one grid. The first block is the
// bodies (one VTK_HEXAHEDRON per box); later issues append their own blocks
// (springs as VTK_LINE cells, contact points as VTK_VERTEX cells) with
// add_cell_block(): a callback that receives the simulation and a
// VtkFrameBuilder, adds points and cells, and declares and fills its own cell
// arrays. Because a VTK grid has one value per cell for every cell array,
// cells of other blocks get the array's fill value (e.g. body_id = -1 on a
// spring cell, spring_force_N = NaN on a body cell). Every frame also gets
//   cell data  cell_block (int): index of the block a cell belongs to
//   field data cell_block_names (strings), TimeValue (s, ParaView's name)
// so a viewer can Threshold on cell_block to show one kind of cell.
//
// Bodies block (arrays, one tuple per body):
//   body_id (int)                   index in the BodyStore
//   member_kind (int)               fq::MemberKind value; names in field data member_kind_names
//   velocity_mps (3, m/s)           world frame; with central difference (the
//                                   default) the mid-step v(t - dt/2) of the
//                                   leapfrog (the state holds no other), with
//                                   the other integrators v(t)
//   angular_velocity_radps (3, rad/s) world frame, at the same instant as velocity_mps
//   state (int)                     0 free, 1 fixed
//   damage_state (int)              0 intact; raised by the springs block
//                                   (scene_output.h): 1 yielded, 2 damaged, 3 detached
//   field data body_names (strings, one per body)
//
// VTK types stay out of this header (VTK is a private dependency of fq_io):
// point and cell indices are plain 64-bit integers and the cell types are
// VTK's numbers.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dem_core/simulation.h"

namespace fq {

// The numbers are VTK's (vtkCellType.h), checked in the source.
enum class VtkCellType : std::uint8_t { Vertex = 1, Line = 3, Hexahedron = 12 };

enum class VtkArrayType : std::uint8_t { Int32, Float64 };

// Collects one frame's points, cells and arrays; given to cell-block callbacks.
class VtkFrameBuilder {
 public:
  using Index = std::int64_t;
  struct ArrayId {
    std::size_t index;
  };

  Index add_point(const Vec3& p_m);
  // Point ids are frame-global indices returned by add_point. Returns the cell's index.
  Index add_cell(VtkCellType type, std::span<const Index> point_ids);
  Index add_cell(VtkCellType type, std::initializer_list<Index> point_ids) {
    return add_cell(type, std::span<const Index>(point_ids.begin(), point_ids.size()));
  }

  // Declares a cell array (or returns the existing one with that name, whose
  // type and component count must match). Cells that never receive a value
  // hold `fill` in every component. Names should carry units like history
  // columns (velocity_mps, force_N); ids and flags have none.
  ArrayId cell_array(std::string_view name, VtkArrayType type, int components, double fill);
  void set(ArrayId array, Index cell, double value) { set(array, cell, 0, value); }
  void set(ArrayId array, Index cell, int component, double value);
  void set(ArrayId array, Index cell, const Vec3& v);  // array of 3 components

  // Field data (whole-frame values).
  void add_field(std::string name, double value);
  void add_field(std::string name, std::vector<std::string> values);

  Index point_count() const { return Index(points_m_.size() / 3); }
  Index cell_count() const { return Index(cell_types_.size()); }

 private:
  friend class VtkFrameWriter;
  struct CellArray {
    std::string name;
    VtkArrayType type;
    int components;
    double fill;
    std::vector<double> values;  // components per cell, grown on demand
  };
  struct StringField {
    std::string name;
    std::vector<std::string> values;
  };
  void clear();

  std::vector<double> points_m_;  // x, y, z per point
  std::vector<Index> connectivity_;
  std::vector<Index> offsets_{0};  // cell c uses connectivity_[offsets_[c], offsets_[c+1])
  std::vector<std::uint8_t> cell_types_;
  std::vector<CellArray> arrays_;
  std::vector<std::pair<std::string, double>> double_fields_;
  std::vector<StringField> string_fields_;
  std::vector<std::int32_t> cell_block_;  // block index per cell
  std::int32_t current_block_ = 0;
};

// Appends one block of cells to a frame. Runs once per frame, after the
// blocks registered before it, with poses at sim.time_s().
using VtkCellBlock = std::function<void(const Simulation& sim, VtkFrameBuilder& frame)>;

class VtkFrameWriter {
 public:
  VtkFrameWriter();  // registers the "bodies" block
  ~VtkFrameWriter();
  VtkFrameWriter(VtkFrameWriter&&) noexcept;
  VtkFrameWriter& operator=(VtkFrameWriter&&) noexcept;

  void add_cell_block(std::string name, VtkCellBlock block);
  const std::vector<std::string>& block_names() const { return names_; }

  // Builds the frame of `sim` and writes it to `file`: first under a
  // temporary name in the same folder, then renamed, so `file` is complete
  // whenever it exists. Throws std::runtime_error naming the file on failure.
  void write(const Simulation& sim, const std::filesystem::path& file, bool binary);
  // An upper bound on the size of the last frame written, and of any frame
  // with as many points, cells and names, whatever their values: its arrays
  // at full width (binary: their bytes plus zlib's worst case; ASCII: the
  // longest text of each value) and an allowance for the XML. The file's own
  // size is no guide: a frame of zero velocities and forces (frame 0)
  // compresses 4.5-5 times better than later ones (scale probe). 0 before
  // the first frame.
  std::uint64_t last_frame_bound_bytes() const { return last_bound_bytes_; }

  // The body-block callback (also usable to build a frame without writing).
  static void add_bodies(const Simulation& sim, VtkFrameBuilder& frame);

 private:
  std::vector<std::string> names_;
  std::vector<VtkCellBlock> blocks_;
  VtkFrameBuilder builder_;  // reused from frame to frame
  std::uint64_t last_bound_bytes_ = 0;
};

}  // namespace fq
