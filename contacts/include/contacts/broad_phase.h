// Broad phase: candidate pairs of boxes that may touch, rebuilt only when
// some body has moved farther than the skin allows.
//
// Method: a uniform grid keyed by cell. Each box's world AABB, enlarged by
// half the skin on every side, is entered in every cell it overlaps; pairs
// are tested within each cell and reported only by the cell that holds the
// lower corner of their AABB intersection, so each pair appears once. The
// cell edge is the mean AABB size (so a typical box spans 1-2 cells per axis
// and a slender beam a few); it is doubled if the entries would exceed 8 per
// box. Build cost O(N log N) (one sort of the entries), pair search O(N) for
// spread-out scenes. Pairs come out sorted by (a, b), a < b, so the narrow
// phase and the contact history see the same order for any thread count.
//
// Skin rule (LAMMPS neighbor skin): at a rebuild each box's pose is saved.
// A point of box i has since moved at most |x - x0| + r_i theta, where r_i is
// the half-diagonal and theta the rotation angle since the rebuild. While this
// bound is below skin/2 for every box, every box lies inside its enlarged
// AABB, so no touching pair can be missing. Otherwise (or when the set of
// bonded pairs changed) the next update rebuilds.
//
// Excluded: bodies marked as not participating (the Ground member kind),
// fixed-fixed pairs, pairs held by an intact joint (BondedPairs).
#pragma once

#include <cstdint>
#include <vector>

#include "dem_core/body_store.h"
#include "dem_core/bonded_pairs.h"

namespace fq {

class StateWriter;  // dem_core/state_io.h
class StateReader;

struct BodyPair {
  BodyId a = kNoBody;  // a < b
  BodyId b = kNoBody;
};

class BroadPhase {
 public:
  // skin_m > 0 (m); participates[i] = 0 excludes body i from every pair.
  void configure(double skin_m, std::vector<std::uint8_t> participates);
  // Rebuilds when needed (or when `force`); returns true when it did.
  bool update(const BodyStore& bodies, const BondedPairs* bonded, bool force = false);
  const std::vector<BodyPair>& pairs() const { return pairs_; }
  std::int64_t rebuild_count() const { return rebuilds_; }
  double skin_m() const { return skin_m_; }
  double cell_size_m() const { return cell_m_; }
  // Checkpoints (dem_core/state_io.h): the candidate pairs and the poses
  // saved at the last rebuild, so a resumed run rebuilds at the same steps
  // as an uninterrupted one. load_state expects configure() done as before.
  void save_state(StateWriter& out) const;
  void load_state(StateReader& in);

 private:
  bool needs_rebuild(const BodyStore& bodies, const BondedPairs* bonded) const;
  void rebuild(const BodyStore& bodies, const BondedPairs* bonded);
  void sort_entries(std::uint64_t cell_count, std::size_t body_count);

  double skin_m_ = 0.0;
  double cell_m_ = 0.0;
  std::vector<std::uint8_t> participates_;
  std::vector<BodyPair> pairs_;
  std::int64_t rebuilds_ = 0;
  bool built_ = false;
  std::size_t bonded_size_at_build_ = 0;
  // Saved at the last rebuild.
  std::vector<Vec3> position0_m_;
  std::vector<Quat> orientation0_;
  std::vector<double> half_diagonal_m_;
  // Scratch, kept between rebuilds so its capacity is reused.
  struct Entry {
    std::uint64_t cell;
    BodyId body;
  };
  std::vector<Entry> entries_;
  std::vector<Vec3> lo_m_, hi_m_;
  std::vector<std::uint64_t> keys_, key_scratch_;
};

}  // namespace fq
