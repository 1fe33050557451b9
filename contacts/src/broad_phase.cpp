#include "contacts/broad_phase.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fq {

namespace {
// At most this many cells per axis (the grid is coarsened beyond).
constexpr std::int64_t kMaxCells = (std::int64_t(1) << 20) - 1;
constexpr double kPi = 3.14159265358979323846;

int bit_width(std::uint64_t v) {
  int b = 0;
  while (v) {
    ++b;
    v >>= 1;
  }
  return b;
}
}  // namespace

// Entries sorted by (cell, body). When both fit in one 64-bit key (always in
// practice: 2^40 cells and 2^24 bodies) an LSD radix sort on 8-bit digits
// does it in a few linear passes; it is stable, hence deterministic.
void BroadPhase::sort_entries(std::uint64_t cell_count, std::size_t body_count) {
  const int body_bits = std::max(1, bit_width(body_count));
  const int cell_bits = std::max(1, bit_width(cell_count));
  if (body_bits + cell_bits > 64) {
    std::sort(entries_.begin(), entries_.end(), [](const Entry& p, const Entry& q) {
      return p.cell != q.cell ? p.cell < q.cell : p.body < q.body;
    });
    return;
  }
  const std::size_t m = entries_.size();
  keys_.resize(m);
  key_scratch_.resize(m);
  for (std::size_t k = 0; k < m; ++k) keys_[k] = (entries_[k].cell << body_bits) | std::uint64_t(entries_[k].body);
  const int total_bits = body_bits + cell_bits;
  for (int shift = 0; shift < total_bits; shift += 8) {
    std::size_t count[257] = {};
    for (std::size_t k = 0; k < m; ++k) ++count[((keys_[k] >> shift) & 0xFF) + 1];
    for (int d = 0; d < 256; ++d) count[d + 1] += count[d];
    for (std::size_t k = 0; k < m; ++k) key_scratch_[count[(keys_[k] >> shift) & 0xFF]++] = keys_[k];
    keys_.swap(key_scratch_);
  }
  const std::uint64_t body_mask = (std::uint64_t(1) << body_bits) - 1;
  for (std::size_t k = 0; k < m; ++k) entries_[k] = {keys_[k] >> body_bits, BodyId(keys_[k] & body_mask)};
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
  if (n < 4096) {
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
  position0_m_ = bodies.position_m;
  orientation0_ = bodies.orientation;
  half_diagonal_m_.resize(n);
  lo_m_.resize(n);
  hi_m_.resize(n);
  pairs_.clear();
  entries_.clear();

  const double margin = 0.5 * skin_m_;
  Vec3 scene_lo = Vec3::Constant(HUGE_VAL), scene_hi = Vec3::Constant(-HUGE_VAL);
  double size_sum = 0.0;
  std::size_t active = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& h = bodies.half_extents_m[i];
    half_diagonal_m_[i] = h.norm();
    if (!participates_[i]) continue;
    const Vec3 e = bodies.rotation[i].cwiseAbs() * h + Vec3::Constant(margin);
    lo_m_[i] = bodies.position_m[i] - e;
    hi_m_[i] = bodies.position_m[i] + e;
    scene_lo = scene_lo.cwiseMin(lo_m_[i]);
    scene_hi = scene_hi.cwiseMax(hi_m_[i]);
    size_sum += 2.0 * e.maxCoeff();
    ++active;
  }
  if (active < 2) return;

  double cell = size_sum / double(active);
  const Vec3 extent = scene_hi - scene_lo;
  cell = std::max(cell, extent.maxCoeff() / double(kMaxCells));
  auto cell_of = [&](double coord, int axis, double c) { return int(std::floor((coord - scene_lo[axis]) / c)); };
  // Keep the entry count near-linear: a box spanning many cells makes many
  // entries, so coarsen the grid until there are at most 8 per box.
  for (;;) {
    std::size_t total = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!participates_[i]) continue;
      std::size_t cells = 1;
      for (int k = 0; k < 3; ++k) cells *= std::size_t(cell_of(hi_m_[i][k], k, cell) - cell_of(lo_m_[i][k], k, cell) + 1);
      total += cells;
    }
    if (total <= 8 * active) break;
    cell *= 2.0;
  }
  cell_m_ = cell;
  // Compact linear cell index over the scene's grid.
  std::uint64_t dims[3];
  for (int k = 0; k < 3; ++k) dims[k] = std::uint64_t(cell_of(scene_hi[k], k, cell)) + 1;
  auto linear = [&](int x, int y, int z) {
    return (std::uint64_t(x) * dims[1] + std::uint64_t(y)) * dims[2] + std::uint64_t(z);
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!participates_[i]) continue;
    const int x0 = cell_of(lo_m_[i].x(), 0, cell), x1 = cell_of(hi_m_[i].x(), 0, cell);
    const int y0 = cell_of(lo_m_[i].y(), 1, cell), y1 = cell_of(hi_m_[i].y(), 1, cell);
    const int z0 = cell_of(lo_m_[i].z(), 2, cell), z1 = cell_of(hi_m_[i].z(), 2, cell);
    for (int x = x0; x <= x1; ++x)
      for (int y = y0; y <= y1; ++y)
        for (int z = z0; z <= z1; ++z) entries_.push_back({linear(x, y, z), BodyId(i)});
  }
  sort_entries(dims[0] * dims[1] * dims[2], n);

  for (std::size_t s = 0; s < entries_.size();) {
    std::size_t e = s + 1;
    while (e < entries_.size() && entries_[e].cell == entries_[s].cell) ++e;
    for (std::size_t p = s; p < e; ++p) {
      const BodyId i = entries_[p].body;
      for (std::size_t q = p + 1; q < e; ++q) {
        const BodyId j = entries_[q].body;  // j > i (sorted)
        if (bodies.is_fixed[i] && bodies.is_fixed[j]) continue;
        const Vec3 lo = lo_m_[i].cwiseMax(lo_m_[j]);
        const Vec3 hi = hi_m_[i].cwiseMin(hi_m_[j]);
        if ((lo.array() > hi.array()).any()) continue;
        // Report only from the cell holding the lower corner of the overlap.
        const std::uint64_t owner = linear(cell_of(lo.x(), 0, cell), cell_of(lo.y(), 1, cell), cell_of(lo.z(), 2, cell));
        if (owner != entries_[s].cell) continue;
        if (bonded && bonded->bonded(i, j)) continue;
        pairs_.push_back({i, j});
      }
    }
    s = e;
  }
  std::sort(pairs_.begin(), pairs_.end(),
            [](const BodyPair& p, const BodyPair& q) { return p.a != q.a ? p.a < q.a : p.b < q.b; });
}

}  // namespace fq
