#include "contacts/broad_phase.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "dem_core/parallel_for.h"

namespace fq {

namespace {
// At most this many cells per axis (the grid is coarsened beyond).
constexpr std::int64_t kMaxCells = (std::int64_t(1) << 20) - 1;
constexpr double kPi = 3.14159265358979323846;
// Bodies per chunk of the rebuild's per-body passes (entry counts, pair
// lists): fixed, so the chunk sums and lists do not depend on the threads.
constexpr std::size_t kBodyChunk = 1024;

int bit_width(std::uint64_t v) {
  int b = 0;
  while (v) {
    ++b;
    v >>= 1;
  }
  return b;
}
}  // namespace

// Entries sorted by (cell, entry index). The key of entry k is
// cell << entry_bits | k; as the entries are made in increasing k, a stable
// LSD radix sort on the cell bits alone orders them by (cell, k), in
// ceil(cell_bits / 11) passes of digits up to 11 bits wide. Each pass counts
// the digits per fixed block of keys, forms every (digit, block) start in
// one serial prefix over the counts, and scatters each block from its own
// starts: stable, and the same result whether the blocks run on one thread
// or many. When the key does not fit in 64 bits (never in practice: 2^64
// cells x entries), a plain sort of (cell, k).
void BroadPhase::sort_entries(int cell_bits, bool parallel) {
  const std::size_t m = entry_cell_.size();
  sorted_cell_.resize(m);
  sorted_body_.resize(m);
  entry_pos_.resize(m);
  const int entry_bits = std::max(1, bit_width(m));
  if (entry_bits + cell_bits > 64) {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(m);
    for (std::size_t k = 0; k < m; ++k) order[k] = {entry_cell_[k], std::uint32_t(k)};
    std::sort(order.begin(), order.end());
    for (std::size_t p = 0; p < m; ++p) {
      sorted_cell_[p] = order[p].first;
      sorted_body_[p] = entry_body_[order[p].second];
      entry_pos_[order[p].second] = std::uint32_t(p);
    }
    return;
  }
  constexpr std::size_t kBlock = std::size_t(1) << 14;  // keys per block (128 KiB)
  const std::size_t blocks = (m + kBlock - 1) / kBlock;
  const int passes = (cell_bits + 10) / 11;
  const int digit_bits = (cell_bits + passes - 1) / passes;
  const std::size_t radix = std::size_t(1) << digit_bits;
  const std::uint64_t digit_mask = radix - 1;
  keys_.resize(m);
  key_scratch_.resize(m);
  block_counts_.resize(blocks * radix);
  parallel_for_static(std::int64_t(m), parallel, [&](std::int64_t k) {
    keys_[std::size_t(k)] = (entry_cell_[std::size_t(k)] << entry_bits) | std::uint64_t(k);
  });
  for (int pass = 0; pass < passes; ++pass) {
    const int shift = entry_bits + pass * digit_bits;
    parallel_for_static(std::int64_t(blocks), parallel, [&](std::int64_t b) {
      std::size_t* count = block_counts_.data() + std::size_t(b) * radix;
      std::fill(count, count + radix, std::size_t(0));
      const std::size_t end = std::min(m, std::size_t(b + 1) * kBlock);
      for (std::size_t k = std::size_t(b) * kBlock; k < end; ++k) ++count[(keys_[k] >> shift) & digit_mask];
    });
    std::size_t start = 0;
    for (std::size_t d = 0; d < radix; ++d) {
      for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t c = block_counts_[b * radix + d];
        block_counts_[b * radix + d] = start;
        start += c;
      }
    }
    parallel_for_static(std::int64_t(blocks), parallel, [&](std::int64_t b) {
      std::size_t* next = block_counts_.data() + std::size_t(b) * radix;
      const std::size_t end = std::min(m, std::size_t(b + 1) * kBlock);
      for (std::size_t k = std::size_t(b) * kBlock; k < end; ++k)
        key_scratch_[next[(keys_[k] >> shift) & digit_mask]++] = keys_[k];
    });
    keys_.swap(key_scratch_);
  }
  const std::uint64_t entry_mask = (std::uint64_t(1) << entry_bits) - 1;
  parallel_for_static(std::int64_t(m), parallel, [&](std::int64_t bp) {
    const auto p = std::size_t(bp);
    const auto k = std::size_t(keys_[p] & entry_mask);
    sorted_cell_[p] = keys_[p] >> entry_bits;
    sorted_body_[p] = entry_body_[k];
    entry_pos_[k] = std::uint32_t(p);
  });
}

void BroadPhase::configure(double skin_m, std::vector<std::uint8_t> participates) {
  if (!(skin_m > 0.0) || !std::isfinite(skin_m))
    throw std::invalid_argument("contact skin must be a positive number of metres");
  skin_m_ = skin_m;
  participates_ = std::move(participates);
  built_ = false;
}

bool BroadPhase::update(const BodyStore& bodies, const BondedPairs* bonded, bool force) {
  if (force || !built_ || needs_rebuild(bodies, bonded)) {
    rebuild(bodies, bonded);
    return true;
  }
  return false;
}

bool BroadPhase::needs_rebuild(const BodyStore& bodies, const BondedPairs* bonded) const {
  if (bonded && bonded->size() != bonded_size_at_build_) return true;
  if (bodies.size() != position0_m_.size()) return true;
  const double limit = 0.5 * skin_m_;
  const std::int64_t n = std::int64_t(bodies.size());
  auto exceeds = [&](std::int64_t i) {
    if (!participates_[i] || bodies.is_fixed[i]) return false;
    const double moved = (bodies.position_m[i] - position0_m_[i]).norm();
    // Rotation angle since the rebuild: 2 asin |vec(q0^-1 q)|.
    const double s = std::min(1.0, (orientation0_[i].conjugate() * bodies.orientation[i]).vec().norm());
    // asin(s) <= (pi / 2) s on [0, 1]: while that bound, with a relative
    // margin far above round-off, stays below the limit, so does the exact
    // one below, and the asin is not needed (same answer, cheaper).
    if ((moved + half_diagonal_m_[i] * kPi * s) * (1.0 + 1e-12) <= limit) return false;
    const double bound = moved + half_diagonal_m_[i] * 2.0 * std::asin(s);
    return bound > limit;
  };
  // Small scenes never enter the OpenMP runtime (dem_core/parallel_for.h)
  // and stop at the first body that moved too far.
  if (n < parallel_min_bodies_) {
    for (std::int64_t i = 0; i < n; ++i)
      if (exceeds(i)) return true;
    return false;
  }
  int exceeded = 0;
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) reduction(max : exceeded)
#endif
  for (std::int64_t i = 0; i < n; ++i)
    if (exceeds(i)) exceeded = 1;
  return exceeded != 0;
}

void BroadPhase::rebuild(const BodyStore& bodies, const BondedPairs* bonded) {
  ++rebuilds_;
  built_ = true;
  bonded_size_at_build_ = bonded ? bonded->size() : 0;
  const std::size_t n = bodies.size();
  if (participates_.size() != n) participates_.resize(n, 1);
  const bool parallel = std::int64_t(n) >= parallel_min_bodies_;
  const std::size_t chunks = (n + kBodyChunk - 1) / kBodyChunk;
  auto chunk_end = [&](std::size_t c) { return std::min(n, (c + 1) * kBodyChunk); };
  position0_m_.resize(n);
  orientation0_.resize(n);
  half_diagonal_m_.resize(n);
  lo_m_.resize(n);
  hi_m_.resize(n);
  body_size_m_.resize(n);
  pairs_.clear();

  // Saved poses and enlarged boxes, per body.
  const double margin = 0.5 * skin_m_;
  parallel_for_static(std::int64_t(n), parallel, [&](std::int64_t bi) {
    const auto i = std::size_t(bi);
    position0_m_[i] = bodies.position_m[i];
    orientation0_[i] = bodies.orientation[i];
    const Vec3& h = bodies.half_extents_m[i];
    half_diagonal_m_[i] = h.norm();
    if (!participates_[i]) return;
    const Vec3 e = bodies.rotation[i].cwiseAbs() * h + Vec3::Constant(margin);
    lo_m_[i] = bodies.position_m[i] - e;
    hi_m_[i] = bodies.position_m[i] + e;
    body_size_m_[i] = 2.0 * e.maxCoeff();
  });
  // Scene bounds and the mean box size, in body order (one short pass).
  Vec3 scene_lo = Vec3::Constant(HUGE_VAL), scene_hi = Vec3::Constant(-HUGE_VAL);
  double size_sum = 0.0;
  std::size_t active = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!participates_[i]) continue;
    scene_lo = scene_lo.cwiseMin(lo_m_[i]);
    scene_hi = scene_hi.cwiseMax(hi_m_[i]);
    size_sum += body_size_m_[i];
    ++active;
  }
  if (active < 2) return;

  double cell = size_sum / double(active);
  const Vec3 extent = scene_hi - scene_lo;
  cell = std::max(cell, extent.maxCoeff() / double(kMaxCells));
  auto cell_of = [&](double coord, int axis, double c) { return int(std::floor((coord - scene_lo[axis]) / c)); };
  // Keep the entry count near-linear: a box spanning many cells makes many
  // entries, so coarsen the grid until there are at most 8 per box. Cells
  // per body, then per chunk, then in total (integers: exact in any order).
  entry_begin_.resize(n + 1);
  chunk_sizes_.resize(chunks);
  std::uint64_t total = 0;
  for (;;) {
    parallel_for_static(std::int64_t(chunks), parallel, [&](std::int64_t ci) {
      std::uint64_t sum = 0;
      for (std::size_t i = std::size_t(ci) * kBodyChunk; i < chunk_end(std::size_t(ci)); ++i) {
        std::uint64_t cells = 0;
        if (participates_[i]) {
          cells = 1;
          for (int k = 0; k < 3; ++k)
            cells *= std::uint64_t(cell_of(hi_m_[i][k], k, cell) - cell_of(lo_m_[i][k], k, cell) + 1);
        }
        entry_begin_[i] = std::uint32_t(std::min<std::uint64_t>(cells, 0xFFFFFFFFull));
        sum += cells;
      }
      chunk_sizes_[std::size_t(ci)] = sum;
    });
    total = 0;
    for (std::size_t c = 0; c < chunks; ++c) total += chunk_sizes_[c];
    if (total <= 8 * active) break;
    cell *= 2.0;
  }
  if (total > 0xFFFFFFFFull) throw std::length_error("broad phase: more than 2^32 grid entries");
  cell_m_ = cell;
  // Compact linear cell index over the scene's grid.
  std::uint64_t dims[3];
  for (int k = 0; k < 3; ++k) dims[k] = std::uint64_t(cell_of(scene_hi[k], k, cell)) + 1;
  auto linear = [&](int x, int y, int z) {
    return (std::uint64_t(x) * dims[1] + std::uint64_t(y)) * dims[2] + std::uint64_t(z);
  };
  // Entry offsets: chunk starts (serial over chunks), then body starts
  // within each chunk; each body then enters its cells at its own offsets.
  {
    std::uint64_t start = 0;
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::uint64_t size = chunk_sizes_[c];
      chunk_sizes_[c] = start;
      start += size;
    }
  }
  entry_cell_.resize(std::size_t(total));
  entry_body_.resize(std::size_t(total));
  entry_begin_[n] = std::uint32_t(total);
  parallel_for_static(std::int64_t(chunks), parallel, [&](std::int64_t ci) {
    std::uint32_t next = std::uint32_t(chunk_sizes_[std::size_t(ci)]);
    for (std::size_t i = std::size_t(ci) * kBodyChunk; i < chunk_end(std::size_t(ci)); ++i) {
      const std::uint32_t count = entry_begin_[i];
      entry_begin_[i] = next;
      if (count == 0) continue;
      const int x0 = cell_of(lo_m_[i].x(), 0, cell), x1 = cell_of(hi_m_[i].x(), 0, cell);
      const int y0 = cell_of(lo_m_[i].y(), 1, cell), y1 = cell_of(hi_m_[i].y(), 1, cell);
      const int z0 = cell_of(lo_m_[i].z(), 2, cell), z1 = cell_of(hi_m_[i].z(), 2, cell);
      for (int x = x0; x <= x1; ++x)
        for (int y = y0; y <= y1; ++y)
          for (int z = z0; z <= z1; ++z) {
            entry_cell_[next] = linear(x, y, z);
            entry_body_[next] = BodyId(i);
            ++next;
          }
    }
  });
  const int cell_bits = std::max(1, bit_width(dims[0] * dims[1] * dims[2]));
  sort_entries(cell_bits, parallel);
  const std::size_t m = std::size_t(total);

  // Pairs per body: body i looks, in each cell it is entered in, at the
  // bodies entered after it (j > i: entries of a cell are in body order)
  // and keeps j when the boxes overlap and this cell holds the lower corner
  // of the overlap (so each pair is found once); its partners are sorted,
  // so the chunk lists joined in chunk order are sorted by (a, b).
  if (chunk_pairs_.size() < chunks) chunk_pairs_.resize(chunks);
  parallel_for_dynamic(std::int64_t(chunks), parallel, [&](std::int64_t ci) {
    std::vector<BodyPair>& out = chunk_pairs_[std::size_t(ci)];
    out.clear();
    for (std::size_t i = std::size_t(ci) * kBodyChunk; i < chunk_end(std::size_t(ci)); ++i) {
      const std::size_t first = out.size();
      const bool fixed_i = bodies.is_fixed[i] != 0;
      for (std::uint32_t o = entry_begin_[i]; o < entry_begin_[i + 1]; ++o) {
        const std::uint64_t here = entry_cell_[o];
        for (std::size_t q = std::size_t(entry_pos_[o]) + 1; q < m && sorted_cell_[q] == here; ++q) {
          const BodyId j = sorted_body_[q];
          if (fixed_i && bodies.is_fixed[std::size_t(j)]) continue;
          const Vec3 lo = lo_m_[i].cwiseMax(lo_m_[std::size_t(j)]);
          const Vec3 hi = hi_m_[i].cwiseMin(hi_m_[std::size_t(j)]);
          if ((lo.array() > hi.array()).any()) continue;
          const std::uint64_t owner = linear(cell_of(lo.x(), 0, cell), cell_of(lo.y(), 1, cell), cell_of(lo.z(), 2, cell));
          if (owner != here) continue;
          if (bonded && bonded->bonded(BodyId(i), j)) continue;
          out.push_back({BodyId(i), j});
        }
      }
      std::sort(out.begin() + std::ptrdiff_t(first), out.end(),
                [](const BodyPair& p, const BodyPair& q) { return p.b < q.b; });
    }
  });
  std::size_t pair_count = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    chunk_sizes_[c] = pair_count;
    pair_count += chunk_pairs_[c].size();
  }
  pairs_.resize(pair_count);
  parallel_for_static(std::int64_t(chunks), parallel, [&](std::int64_t ci) {
    const auto c = std::size_t(ci);
    std::copy(chunk_pairs_[c].begin(), chunk_pairs_[c].end(), pairs_.begin() + std::ptrdiff_t(chunk_sizes_[c]));
  });
}

}  // namespace fq
