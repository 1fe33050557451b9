// Points hashed into a uniform grid of cubic cells, for "which points may lie
// in this box" queries during set-up. The geometry warnings used to test
// every member against every node, which made set-up quadratic in the case's
// size (100k bodies: 90 s); a query here touches only the cells the box
// covers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "dem_core/types.h"

namespace fq {

class PointGrid {
 public:
  // cell_m: edge of a cell (m); about the size of the boxes queried keeps
  // both the cells and the points per cell of a query few. A cell that is
  // not positive and finite, or that would cut the points' extent into more
  // than about a million cells per axis, is enlarged.
  PointGrid(std::vector<Vec3> points, double cell_m);

  // Appends to `out`, in ascending order, the indices of a superset of the
  // points p with lo <= p <= hi (componentwise): every point in the box and
  // possibly others near it, so the caller applies its exact test. Points
  // with a non-finite coordinate are in every answer (no cell holds them).
  // `examined`, if given, receives the number of points looked at: a check
  // that the query stays local.
  void candidates(const Vec3& lo, const Vec3& hi, std::vector<int>& out, std::size_t* examined = nullptr) const;

  std::size_t size() const { return points_.size(); }

 private:
  struct Key {
    std::int64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  std::int64_t cell_of(double v, int axis) const;

  std::vector<Vec3> points_;
  double cell_m_ = 1.0;
  Vec3 lo_ = Vec3::Zero(), hi_ = Vec3::Zero();  // bounds of the finite points
  std::unordered_map<Key, std::vector<int>, KeyHash> cells_;
  std::vector<int> unplaced_;  // points with a non-finite coordinate
};

}  // namespace fq
