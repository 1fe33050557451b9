#include "io/point_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace fq {

namespace {
constexpr double kMaxCellsPerAxis = 1.0e6;
}

PointGrid::PointGrid(std::vector<Vec3> points, double cell_m) : points_(std::move(points)) {
  lo_ = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi_ = -lo_;
  bool any = false;
  for (const Vec3& p : points_)
    if (p.allFinite()) {
      lo_ = lo_.cwiseMin(p);
      hi_ = hi_.cwiseMax(p);
      any = true;
    }
  if (!any) lo_ = hi_ = Vec3::Zero();
  // Cell indices then stay far inside int64 whatever the coordinates.
  const double extent = (hi_ - lo_).maxCoeff();
  cell_m_ = std::isfinite(cell_m) && cell_m > 0.0 ? cell_m : 1.0;
  cell_m_ = std::max(cell_m_, extent / kMaxCellsPerAxis);
  if (!(cell_m_ > 0.0) || !std::isfinite(cell_m_)) cell_m_ = 1.0;
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Vec3& p = points_[i];
    if (!p.allFinite()) {
      unplaced_.push_back(int(i));
      continue;
    }
    cells_[{cell_of(p.x(), 0), cell_of(p.y(), 1), cell_of(p.z(), 2)}].push_back(int(i));
  }
}

std::size_t PointGrid::KeyHash::operator()(const Key& k) const {
  // Large odd multipliers spread neighbouring cells over the table.
  const std::uint64_t h = std::uint64_t(k.x) * 0x9E3779B97F4A7C15ull ^ std::uint64_t(k.y) * 0xC2B2AE3D27D4EB4Full ^
                          std::uint64_t(k.z) * 0x165667B19E3779F9ull;
  return std::size_t(h ^ (h >> 29));
}

// Cell index along one axis, counted from the points' low corner. Called
// with values clamped to the points' bounds, so it is finite and small.
std::int64_t PointGrid::cell_of(double v, int axis) const {
  return std::int64_t(std::floor((v - lo_[axis]) / cell_m_));
}

void PointGrid::candidates(const Vec3& lo, const Vec3& hi, std::vector<int>& out, std::size_t* examined) const {
  const std::size_t first = out.size();
  std::size_t looked = unplaced_.size();
  out.insert(out.end(), unplaced_.begin(), unplaced_.end());
  // A box with a NaN bound is treated as unbounded: only the exact test,
  // which the caller applies, may rule its points out.
  Vec3 qlo, qhi;
  bool empty = cells_.empty();
  for (int k = 0; k < 3; ++k) {
    qlo[k] = std::isnan(lo[k]) ? lo_[k] : std::max(lo[k], lo_[k]);
    qhi[k] = std::isnan(hi[k]) ? hi_[k] : std::min(hi[k], hi_[k]);
    if (qlo[k] > qhi[k]) empty = true;
  }
  if (!empty) {
    const Key a{cell_of(qlo.x(), 0), cell_of(qlo.y(), 1), cell_of(qlo.z(), 2)};
    const Key b{cell_of(qhi.x(), 0), cell_of(qhi.y(), 1), cell_of(qhi.z(), 2)};
    const double box_cells = double(b.x - a.x + 1) * double(b.y - a.y + 1) * double(b.z - a.z + 1);
    if (box_cells <= double(cells_.size())) {
      for (std::int64_t x = a.x; x <= b.x; ++x)
        for (std::int64_t y = a.y; y <= b.y; ++y)
          for (std::int64_t z = a.z; z <= b.z; ++z)
            if (const auto it = cells_.find({x, y, z}); it != cells_.end()) {
              out.insert(out.end(), it->second.begin(), it->second.end());
              looked += it->second.size();
            }
    } else {
      // A box wider than the occupied cells: visit those instead.
      for (const auto& [key, in_cell] : cells_)
        if (key.x >= a.x && key.x <= b.x && key.y >= a.y && key.y <= b.y && key.z >= a.z && key.z <= b.z) {
          out.insert(out.end(), in_cell.begin(), in_cell.end());
          looked += in_cell.size();
        }
    }
  }
  std::sort(out.begin() + std::ptrdiff_t(first), out.end());
  if (examined) *examined = looked;
}

}  // namespace fq
