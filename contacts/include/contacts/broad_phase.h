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
//
// Threads (scenes of at least parallel_min_bodies bodies; smaller ones never
// enter the OpenMP runtime): every stage of a rebuild works per body or per
// fixed block of entries and writes only its own slots: boxes and cell
// counts per body, entries per body at offsets from a prefix sum, an LSD
// radix sort with per-block digit counts, and the pair search per body --
// body i collects its partners j > i from the cells it is entered in, sorts
// them, and the per-chunk lists are joined in body order. The pair list is
// fully determined by the boxes (every overlapping pair, once, sorted), and
// the cell size is summed over bodies in body order, so a rebuild gives the
// same bits on any number of threads and the same as the former serial
// per-cell search.
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
  // Scenes with at least this many bodies use OpenMP threads in the skin
  // check and the rebuild (default 4096; tests lower it to force threads).
  void set_parallel_min_bodies(std::int64_t bodies) { parallel_min_bodies_ = bodies; }
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
  // Sorts the entries by (cell, entry index) into sorted_cell_ and
  // sorted_body_ (the entry index grows with the body, so this is the
  // (cell, body) order), and notes each entry's place in entry_pos_.
  void sort_entries(int cell_bits, bool parallel);

  double skin_m_ = 0.0;
  double cell_m_ = 0.0;
  std::int64_t parallel_min_bodies_ = 4096;
  std::vector<std::uint8_t> participates_;
  std::vector<BodyPair> pairs_;
  std::int64_t rebuilds_ = 0;
  bool built_ = false;
  std::size_t bonded_size_at_build_ = 0;
  // Saved at the last rebuild.
  std::vector<Vec3> position0_m_;
  std::vector<Quat> orientation0_;
  std::vector<double> half_diagonal_m_;
  // Scratch, kept between rebuilds so its capacity is reused (no
  // allocation once the scene's sizes have been seen). Entries are numbered
  // body by body (body i owns entry_begin_[i] .. entry_begin_[i+1]-1, its
  // cells in increasing linear index).
  std::vector<Vec3> lo_m_, hi_m_;                // enlarged box per body (m)
  std::vector<double> body_size_m_;              // its largest edge (m): mean cell size
  std::vector<std::uint32_t> entry_begin_;       // per body, then the total
  std::vector<std::uint64_t> entry_cell_;        // per entry: linear cell index
  std::vector<BodyId> entry_body_;               // per entry: its body
  std::vector<std::uint32_t> entry_pos_;         // per entry: its place in the sorted order
  std::vector<std::uint64_t> sorted_cell_;       // sorted entries: cell
  std::vector<BodyId> sorted_body_;              // sorted entries: body
  std::vector<std::uint64_t> keys_, key_scratch_;  // radix sort: cell << bits | entry
  std::vector<std::size_t> block_counts_;        // radix sort: digit counts per block
  std::vector<std::uint64_t> chunk_sizes_;       // per body chunk: entries, then pairs
  std::vector<std::vector<BodyPair>> chunk_pairs_;  // per body chunk: its pairs
};

}  // namespace fq
