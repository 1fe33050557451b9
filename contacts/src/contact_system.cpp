#include "contacts/contact_system.h"

#include <type_traits>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "contacts/collide_box_box.h"
#include "contacts/collide_box_ground.h"
#include "contacts/linear_contact_law.h"
#include "dem_core/parallel_for.h"

namespace fq {

namespace {

// Work items per narrow-phase chunk: large enough to amortise the chunk
// bookkeeping, small enough to balance two threads on a few hundred pairs.
constexpr std::size_t kChunkItems = 64;
// What a narrow-phase chunk costs, in units of one item rejected by the
// bounding-sphere test (two positions and radii loaded, about 20
// instructions): an item that goes on to a full box test (separating-axis
// test over up to 15 axes, some 400 instructions) adds about 20; each
// contact point made (its share of the clipping, the history search and the
// contact law, some 200 instructions) about 10. Only the split of the work
// between threads depends on these, never a result.
constexpr double kCostPerBoxTest = 20.0;
constexpr double kCostPerPoint = 10.0;
constexpr std::uint64_t kGroundKeyHigh = 0xFFFFFFFFull << 32;
// History cursor not yet placed (process_item).
constexpr std::size_t kNoCursor = ~std::size_t(0);

std::uint64_t pair_key(BodyId a, BodyId b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); }

OrientedBoxRef box_of(const BodyStore& bodies, BodyId i) {
  return {bodies.position_m[i], bodies.rotation[i], bodies.half_extents_m[i]};
}

}  // namespace

ContactSystem::ContactSystem(const BondedPairs* bonded, ContactSystemSettings settings)
    : bonded_(bonded), settings_(settings) {}

void ContactSystem::set_body_material(BodyId body, int material) {
  if (body < 0) throw std::invalid_argument("set_body_material: body id must be >= 0");
  if (material < 0) throw std::invalid_argument("set_body_material: material index must be >= 0");
  if (std::size_t(body) >= body_material_.size()) body_material_.resize(std::size_t(body) + 1, 0);
  body_material_[std::size_t(body)] = material;
  prepared_ = false;
}

void ContactSystem::set_pair_params(int material_i, int material_j, const ContactParams& params) {
  if (material_i < 0 || material_j < 0) throw std::invalid_argument("set_pair_params: material index must be >= 0");
  const std::string what = "material pair (" + std::to_string(material_i) + ", " + std::to_string(material_j) + ")";
  (void)make_contact_coefficients(params, what.c_str());  // validate now, with the caller on the stack
  pair_params_[{std::min(material_i, material_j), std::max(material_i, material_j)}] = params;
  prepared_ = false;
}

void ContactSystem::set_ground(double level_m, const ContactParams& params) {
  if (!std::isfinite(level_m)) throw std::invalid_argument("set_ground: ground level must be a finite number of metres");
  (void)make_contact_coefficients(params, "the ground");
  ground_enabled_ = true;
  ground_level_m_ = level_m;
  ground_params_ = params;
  prepared_ = false;
}

int ContactSystem::coeff_index_for(int material_i, int material_j) const {
  return material_coeff_[std::size_t(material_i * n_materials_ + material_j)];
}

void ContactSystem::prepare(const BodyStore& bodies) {
  const std::size_t n = bodies.size();
  body_material_.resize(n, 0);
  n_materials_ = 1;
  for (int m : body_material_) n_materials_ = std::max(n_materials_, m + 1);
  for (const auto& [key, params] : pair_params_) n_materials_ = std::max(n_materials_, key.second + 1);

  coeffs_.clear();
  coeffs_.push_back(make_contact_coefficients(ContactParams{}, "the default pair"));
  material_coeff_.assign(std::size_t(n_materials_ * n_materials_), 0);
  for (const auto& [key, params] : pair_params_) {
    const std::string what = "material pair (" + std::to_string(key.first) + ", " + std::to_string(key.second) + ")";
    coeffs_.push_back(make_contact_coefficients(params, what.c_str()));
    const int idx = int(coeffs_.size()) - 1;
    material_coeff_[std::size_t(key.first * n_materials_ + key.second)] = idx;
    material_coeff_[std::size_t(key.second * n_materials_ + key.first)] = idx;
  }
  ground_coeff_ = 0;
  if (ground_enabled_) {
    coeffs_.push_back(make_contact_coefficients(ground_params_, "the ground"));
    ground_coeff_ = int(coeffs_.size()) - 1;
  }

  bounding_radius_m_.resize(n);
  for (std::size_t i = 0; i < n; ++i) bounding_radius_m_[i] = bodies.half_extents_m[i].norm();
  half_dimension_m_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    half_dimension_m_[i] = bodies.is_fixed[i] ? HUGE_VAL : bodies.half_extents_m[i].minCoeff();
  press_peak_ = ContactPressPeak{};
  participates_.assign(n, 1);
  ground_body_ = kNoBody;
  ground_candidates_.clear();
  double thinnest_m = HUGE_VAL;
  for (std::size_t i = 0; i < n; ++i) {
    if (bodies.info[i].kind == MemberKind::Ground) {
      participates_[i] = 0;
      if (ground_body_ == kNoBody) ground_body_ = BodyId(i);
      continue;
    }
    thinnest_m = std::min(thinnest_m, 2.0 * bodies.half_extents_m[i].minCoeff());
    if (!bodies.is_fixed[i]) ground_candidates_.push_back(BodyId(i));
  }
  if (!ground_enabled_) ground_candidates_.clear();
  const double skin = settings_.skin_m > 0.0 ? settings_.skin_m : (std::isfinite(thinnest_m) ? 0.4 * thinnest_m : 1.0);
  broad_.configure(skin, participates_);
  broad_.set_parallel_min_bodies(settings_.broad_phase_parallel_bodies);
  contacts_.clear();
  previous_.clear();
  prepared_ = true;
}

void ContactSystem::accumulate_forces(BodyStore& bodies, const StepInfo& step) {
  if (!prepared_ || body_material_.size() != bodies.size()) prepare(bodies);
  if (broad_.update(bodies, bonded_)) {
    const auto& pairs = broad_.pairs();
    pair_separating_axis_.assign(pairs.size(), -1);
    pair_coeff_.resize(pairs.size());
    const std::int64_t n_pairs = std::int64_t(pairs.size());
    parallel_for_static(n_pairs, n_pairs >= std::int64_t(settings_.broad_phase_parallel_bodies), [&](std::int64_t p) {
      pair_coeff_[std::size_t(p)] = coeff_index_for(body_material_[pairs[std::size_t(p)].a], body_material_[pairs[std::size_t(p)].b]);
    });
  }
  if (bonded_) {
    const auto& released = bonded_->released();
    for (; released_read_ < released.size(); ++released_read_) {
      const auto [first, second] = released[released_read_];
      // A supported body kept off the ground while its joint held starts on
      // the ground from its overlap (ground contacts have keys of their own).
      const bool ground_held = !settings_.ground_under_intact_supports && ground_body_ != kNoBody &&
                               (first == ground_body_ || second == ground_body_);
      const std::uint64_t key = ground_held ? kGroundKeyHigh | std::uint32_t(first == ground_body_ ? second : first)
                                            : pair_key(first, second);
      soft_start_pairs_.insert(std::lower_bound(soft_start_pairs_.begin(), soft_start_pairs_.end(), key), key);
    }
  }
  std::swap(previous_, contacts_);
  narrow_phase(bodies, step);
  if (step.step == 0 && !initial_overlaps_checked_) {
    initial_overlaps_checked_ = true;
    // Again, now with the overlapping pairs starting from their overlap
    // (previous_ is unchanged, contacts_ is rewritten).
    if (soft_start_initial_overlaps_()) narrow_phase(bodies, step);
  }
  if (!soft_start_pairs_.empty()) {
    // A released pair without any contact point has separated: from now on
    // it is an ordinary pair. contacts_ is sorted by pair key.
    std::erase_if(soft_start_pairs_, [&](std::uint64_t key) {
      return !std::binary_search(contacts_.begin(), contacts_.end(), key,
                                 [](const auto& x, const auto& y) {
                                   if constexpr (std::is_same_v<std::decay_t<decltype(x)>, ContactPoint>)
                                     return x.pair_key < y;
                                   else
                                     return x < y.pair_key;
                                 });
    });
  }
  gather(bodies);
}

// Narrow phase, one pass per work item (a candidate pair or a box near the
// ground): the manifold's points are made, sorted by feature, given their
// history and their velocities while the bodies' data is still in cache
// (apply_law then loads them). Work items
// come in increasing pair key (pairs sorted by (a, b), then ground contacts
// by box), and so do the records of previous_: the history of each point is
// found by a cursor that only moves forward (one binary search per chunk,
// then a merge), with the same result as a search per point.
std::size_t ContactSystem::process_item(const BodyStore& bodies, std::size_t item,
                                        std::size_t& cursor, ContactManifold& manifold,
                                        std::vector<ContactPoint>& out, std::size_t& used,
                                        std::size_t& box_tests) {
  const auto& pairs = broad_.pairs();
  const std::size_t n_pairs = pairs.size();
  BodyId a, b;
  std::uint64_t key;
  int coeff;
  double pair_mass;
  if (item < n_pairs) {
    a = pairs[item].a;
    b = pairs[item].b;
    // Bounding spheres first: most candidates inside the skin do not touch.
    const double reach = bounding_radius_m_[std::size_t(a)] + bounding_radius_m_[std::size_t(b)];
    if ((bodies.position_m[b] - bodies.position_m[a]).squaredNorm() > reach * reach) return 0;
    ++box_tests;
    // A fixed body's faces are preferred as the reference (collide_box_box.h).
    if (collide_box_box(box_of(bodies, a), box_of(bodies, b), manifold, &pair_separating_axis_[item],
                        bodies.is_fixed[b] && !bodies.is_fixed[a]) == 0)
      return 0;
    key = pair_key(a, b);
    coeff = pair_coeff_[item];
    const double ma = bodies.mass_kg[a], mb = bodies.mass_kg[b];
    pair_mass = bodies.is_fixed[a] ? mb : bodies.is_fixed[b] ? ma : ma * mb / (ma + mb);
  } else {
    b = ground_candidates_[item - n_pairs];
    a = ground_body_;
    // Lowest corner first (box_lowest_z_m without building the box).
    const Mat3& r = bodies.rotation[b];
    const Vec3& h = bodies.half_extents_m[b];
    const double lowest_z =
        bodies.position_m[b].z() - (std::fabs(r(2, 0)) * h.x() + std::fabs(r(2, 1)) * h.y() + std::fabs(r(2, 2)) * h.z());
    if (!(lowest_z < ground_level_m_)) return 0;
    if (!settings_.ground_under_intact_supports && bonded_ && bonded_->bonded(ground_body_, b)) return 0;
    ++box_tests;
    if (collide_box_ground(box_of(bodies, b), ground_level_m_, manifold) == 0) return 0;
    key = kGroundKeyHigh | std::uint32_t(b);
    coeff = ground_coeff_;
    pair_mass = bodies.mass_kg[b];
  }
  // Points in feature order (insertion sort of indices: at most 8 points).
  std::array<int, kMaxManifoldPoints> order;
  int count = 0;
  for (int k = 0; k < manifold.count; ++k) {
    const std::uint32_t f = manifold.points[std::size_t(k)].feature;
    int pos = count;
    while (pos > 0 && manifold.points[std::size_t(order[std::size_t(pos - 1)])].feature > f) {
      order[std::size_t(pos)] = order[std::size_t(pos - 1)];
      --pos;
    }
    // Features are unique by construction; drop any duplicate defensively.
    if (pos > 0 && manifold.points[std::size_t(order[std::size_t(pos - 1)])].feature == f) {
      for (int m = pos; m < count; ++m) order[std::size_t(m)] = order[std::size_t(m + 1)];
      continue;
    }
    order[std::size_t(pos)] = k;
    ++count;
  }
  double weight_sum = 0.0;
  for (int k = 0; k < count; ++k) weight_sum += manifold.points[std::size_t(order[std::size_t(k)])].weight;
  // Points that all have a zero share (every turning corner of the clipped
  // polygon lies above the reference face and the points below sit on its
  // straight edges, as where faces only just touch) carry no stiffness: the
  // pair makes no point this step. Dividing the pair's mass by their zero
  // sum made the next state NaN (three cubes touching face to face under
  // shaking; stress probe). Any other manifold keeps its bits.
  if (!(weight_sum > 0.0)) count = 0;
  const double mass_per_weight = count > 0 ? pair_mass / weight_sum : 0.0;

  // History cursor: first record of previous_ with a key not below this pair's.
  if (cursor == kNoCursor) {
    cursor = std::size_t(std::lower_bound(previous_.begin(), previous_.end(), key,
                                          [](const ContactPoint& p, std::uint64_t k) { return p.pair_key < k; }) -
                         previous_.begin());
  }
  ContactPoint* const previous_end = previous_.data() + previous_.size();
  ContactPoint* history = previous_.data() + cursor;
  while (history != previous_end && history->pair_key < key) ++history;
  ContactPoint* history_end = history;  // end of this pair's records
  while (history_end != previous_end && history_end->pair_key == key) ++history_end;
  cursor = std::size_t(history_end - previous_.data());

  const bool moving_a = item < n_pairs && a >= 0;
  const Vec3 x_a = moving_a ? bodies.position_m[a] : Vec3(Vec3::Zero());
  const Vec3 v_a = moving_a ? bodies.velocity_mps[a] : Vec3(Vec3::Zero());
  const Vec3 w_a = moving_a ? bodies.angular_velocity_radps[a] : Vec3(Vec3::Zero());
  const Vec3& x_b = bodies.position_m[b];
  const Vec3& v_b = bodies.velocity_mps[b];
  const Vec3& w_b = bodies.angular_velocity_radps[b];
  const bool soft_start_pair =
      !soft_start_pairs_.empty() && std::binary_search(soft_start_pairs_.begin(), soft_start_pairs_.end(), key);
  // A point that appears after the pair's first touch (a new feature, as
  // the members slide or turn) may start from no more overlap than the
  // pair still allows, the largest reference depth of its points at the
  // step before (header): taking its whole depth would let the members
  // sink a little further into each other at every change of features.
  // Negative: no point at the step before (first touch).
  double pair_allowance_m = -1.0;
  if (soft_start_pair)
    for (const ContactPoint* h = history; h != history_end; ++h) pair_allowance_m = std::max(pair_allowance_m, h->reference_depth_m);
  // A point takes over a record of the step before: its shear spring, its
  // reference depth (within its depth), its energies for the books and, with
  // the same share and mass (same bits), its dashpot coefficients.
  auto take_history = [](ContactPoint& c, ContactPoint& p) {
    c.shear_spring_N = p.shear_spring_N;
    c.reference_depth_m = std::min(p.reference_depth_m, c.depth_m);
    c.elastic_prev_J = p.elastic_J;
    c.elastic_tangential_prev_J = p.elastic_tangential_J;
    const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
    if (p.dashpots_known && bits(p.stiffness_scale) == bits(c.stiffness_scale) &&
        bits(p.effective_mass_kg) == bits(c.effective_mass_kg)) {
      c.dashpots_known = true;
      c.normal_dashpot_Nspm = p.normal_dashpot_Nspm;
      c.tangential_dashpot_Nspm = p.tangential_dashpot_Nspm;
    }
    // Keys are unique, so no two contacts write the same record.
    p.history_carried = true;
  };
  ContactPoint* const pair_history = history;  // this pair's records of the step before: [pair_history, history_end)
  std::array<std::size_t, kMaxManifoldPoints> unmatched;  // indices in `out` of points without a record of their feature
  int unmatched_count = 0;
  for (int k = 0; k < count; ++k) {
    const ContactPointGeometry& g = manifold.points[std::size_t(order[std::size_t(k)])];
    // The next record: one left in `out` from an earlier step, reused,
    // or a new one. A reused record is not cleared as a whole (a 336-byte
    // zeroing per point was the costliest instruction of this function):
    // every field is written below or by apply_law, those that only some
    // points set start from their defaults here, and the losses, which
    // finish_step writes, start at zero for anyone reading before it.
    // (Test: BondedRelease.APairNeverBondedStartsFromZeroOverlapBesideAReleasedOne,
    // and the contact energy tests for the history fields.)
    ContactPoint& c = used < out.size() ? out[used] : out.emplace_back();
    ++used;
    c.shear_spring_N.setZero();
    c.reference_depth_m = 0.0;
    c.elastic_prev_J = 0.0;
    c.elastic_tangential_prev_J = 0.0;
    c.history_carried = false;
    c.dashpots_known = false;
    c.viscous_J = c.friction_J = c.viscous_work_loss_J = c.friction_work_loss_J = 0.0;
    c.body_a = a;
    c.body_b = b;
    c.feature = g.feature;
    c.position_m = g.position_m;
    c.normal = g.normal;
    c.lean = g.lean;
    c.depth_m = g.depth_m;
    c.pair_key = key;
    c.coeff_index = coeff;
    c.stiffness_scale = g.weight;
    c.effective_mass_kg = mass_per_weight * g.weight;

    // Tangential history of the same (pair, feature) at the previous step
    // (a new point's shear spring starts empty: the record's zero).
    while (history != history_end && history->feature < c.feature) ++history;
    if (history != history_end && history->feature == c.feature)
      take_history(c, *history);
    else
      unmatched[unmatched_count++] = used - 1;

    // Arms at n and the velocity at n-1/2, kept for finish_step's books.
    c.arm_a_m = moving_a ? Vec3(c.position_m - x_a) : Vec3(Vec3::Zero());
    c.arm_b_m = c.position_m - x_b;
    const Vec3 va = moving_a ? Vec3(v_a + w_a.cross(c.arm_a_m)) : Vec3(Vec3::Zero());
    const Vec3 v_rel = v_b + w_b.cross(c.arm_b_m) - va;
    c.velocity_prev_mps = v_rel;
  }
  // Points whose feature had no record: the same patch of the faces may
  // have touched at the step before under another feature. Equal faces
  // lying on each other (a column on a column) change the features of
  // their corner points with the sign of a lateral offset of round-off
  // size; an oscillation across that offset then renamed the points at
  // every step, every shear spring restarted from the last step's
  // increment alone, and the contact's tangential stiffness at the highest
  // frequency doubled (the box on a box of ContactStableStep went unstable
  // at 0.88 of its stable step, 2026-11-26). So such a point takes a record
  // of the pair that no point took, within a tenth of the thinnest
  // half-size of the two bodies (a point that moved that far in one step
  // is not the same contact); closest pairs first, so that a crossing of
  // nearly parallel edges racing along an edge (its position moves by
  // offset / angle) does not take the record of a renamed corner it
  // happens to pass. The spring keeps its displacement, not its force: a
  // record of share w_old gives a point of share w the force w / w_old
  // times its own. A point no record is left for is new.
  if (unmatched_count > 0) {
    double thinnest_m = bodies.half_extents_m[b].minCoeff();
    if (item < n_pairs) thinnest_m = std::min(thinnest_m, bodies.half_extents_m[a].minCoeff());
    const double reach_sq = 0.01 * thinnest_m * thinnest_m;
    struct Candidate {
      double distance_sq;
      int point;   // index into unmatched
      int record;  // offset from pair_history
    };
    std::array<Candidate, kMaxManifoldPoints * 2 * kMaxManifoldPoints> candidates;
    int n_candidates = 0;
    const int n_records = int(history_end - pair_history);
    for (int u = 0; u < unmatched_count; ++u) {
      const Vec3& position = out[unmatched[std::size_t(u)]].position_m;
      for (int r = 0; r < n_records && n_candidates < int(candidates.size()); ++r) {
        const ContactPoint& h = pair_history[r];
        if (h.history_carried) continue;
        const double d_sq = (h.position_m - position).squaredNorm();
        if (d_sq <= reach_sq) candidates[std::size_t(n_candidates++)] = {d_sq, u, r};
      }
    }
    std::sort(candidates.begin(), candidates.begin() + n_candidates, [](const Candidate& x, const Candidate& y) {
      return x.distance_sq != y.distance_sq ? x.distance_sq < y.distance_sq
                                            : (x.point != y.point ? x.point < y.point : x.record < y.record);
    });
    std::array<bool, kMaxManifoldPoints> took{};
    for (int k = 0; k < n_candidates; ++k) {
      const Candidate& cand = candidates[std::size_t(k)];
      ContactPoint& h = pair_history[cand.record];
      if (took[std::size_t(cand.point)] || h.history_carried) continue;
      ContactPoint& c = out[unmatched[std::size_t(cand.point)]];
      take_history(c, h);
      if (h.stiffness_scale > 0.0) c.shear_spring_N *= c.stiffness_scale / h.stiffness_scale;
      // The record's reference depth belonged to its own share: a point of
      // a small share beside a face's corners may have kept a far smaller
      // one, and a renamed corner taking it met its overlap in full (frame
      // A's collapse: two corners of a released beam end went from 0.4 N to
      // 288 N in one step, 0.08 J that no load put in; collapse probe,
      // 2026-11-26). A renamed point of a released pair takes what a new
      // point takes, the pair's allowance.
      if (soft_start_pair) c.reference_depth_m = std::min(c.depth_m, pair_allowance_m);
      took[std::size_t(cand.point)] = true;
    }
    if (soft_start_pair) {
      for (int u = 0; u < unmatched_count; ++u) {
        if (took[std::size_t(u)]) continue;
        // First touch of a pair released from a joint or overlapping at the
        // start: the overlap it has; a later new point: within the allowance.
        ContactPoint& c = out[unmatched[std::size_t(u)]];
        c.reference_depth_m = pair_allowance_m < 0.0 ? c.depth_m : std::min(c.depth_m, pair_allowance_m);
      }
    }
  }
  return std::size_t(count);
}

// The contact law of every record in [first, last) (process_item made
// them). A pass of its own rather than a step of process_item: the law
// needs nothing of the pair, only the record, and its square roots and
// quotients then run back to back for the points of a chunk (measured
// alone, the split moved the contact stage by 1 %; what it saves comes
// from the dashpot coefficients kept between steps, below, and the
// root-free sliding test of the law).
void ContactSystem::apply_law(ContactPoint* first, ContactPoint* last, const StepInfo& step) const {
  for (ContactPoint* cp = first; cp != last; ++cp) {
    ContactPoint& c = *cp;
    const Vec3& v_rel = c.velocity_prev_mps;
    const double vn = c.normal.dot(v_rel);
    ContactLawInput in;
    in.depth_m = c.depth_m - c.reference_depth_m;
    in.approach_speed_mps = -vn;
    in.normal = c.normal;
    in.tangential_velocity_mps = v_rel - vn * c.normal;
    in.stiffness_scale = c.stiffness_scale;
    in.effective_mass_kg = c.effective_mass_kg;
    in.dt_s = step.dt_s;
    const ContactCoefficients& coeff = coeffs_[std::size_t(c.coeff_index)];
    if (!c.dashpots_known) {
      const ContactDashpots d = contact_dashpots(coeff, in);
      c.normal_dashpot_Nspm = d.normal_Nspm;
      c.tangential_dashpot_Nspm = d.tangential_Nspm;
      c.dashpots_known = true;
    }
    const ContactLawOutput law =
        linear_contact_law(coeff, in, {c.normal_dashpot_Nspm, c.tangential_dashpot_Nspm}, c.shear_spring_N);
    c.normal_force_N = law.normal_force_N;
    c.tangential_force_N = law.tangential_force_N;
    // The spring's part of the normal force, k (d - d0) >= 0, also pushes
    // across the normal where the point slides (ContactPointGeometry::lean).
    c.lean_force_N = (std::max(0.0, in.depth_m) * in.stiffness_scale * coeff.normal_stiffness_N_per_m) * c.lean;
    c.sliding = law.sliding;
    c.elastic_J = law.elastic_J;
    c.elastic_tangential_J = law.elastic_tangential_J;
    if (step.step == 0) {
      // The ledger's initial stored energy already holds the springs at t = 0.
      c.elastic_prev_J = c.elastic_J;
      c.elastic_tangential_prev_J = c.elastic_tangential_J;
    }
  }
}

bool ContactSystem::soft_start_initial_overlaps_() {
  // contacts_ is sorted by pair key, ground contacts last (key high word
  // all ones); one entry per pair with its deepest point.
  std::vector<InitialOverlap> found;
  std::vector<std::uint64_t> keys;
  for (const ContactPoint& c : contacts_) {
    if ((c.pair_key & kGroundKeyHigh) == kGroundKeyHigh) continue;
    if (!(c.depth_m - c.reference_depth_m > kInitialOverlapTolerance_m)) continue;
    if (keys.empty() || keys.back() != c.pair_key) {
      keys.push_back(c.pair_key);
      found.push_back({c.body_a, c.body_b, 0.0});
    }
    found.back().depth_m = std::max(found.back().depth_m, c.depth_m);
  }
  if (keys.empty()) return false;
  for (const std::uint64_t key : keys) {
    const auto at = std::lower_bound(soft_start_pairs_.begin(), soft_start_pairs_.end(), key);
    if (at == soft_start_pairs_.end() || *at != key) soft_start_pairs_.insert(at, key);
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const InitialOverlap& x, const InitialOverlap& y) { return x.depth_m > y.depth_m; });
  initial_overlaps_ = std::move(found);
  return true;
}

void ContactSystem::narrow_phase(const BodyStore& bodies, const StepInfo& step) {
  const std::size_t n_pairs = broad_.pairs().size();
  const std::size_t n_items = n_pairs + ground_candidates_.size();
  if (pair_separating_axis_.size() != n_pairs) pair_separating_axis_.assign(n_pairs, -1);
  const bool parallel = n_items >= std::size_t(settings_.parallel_threshold);
  if (!parallel) {
    // One thread: straight into the contact list (same order as the chunks).
    // (contacts_ holds the records of two steps ago: process_item reuses them.)
    std::size_t cursor = kNoCursor, used = 0;
    std::size_t box_tests = 0;
    for (std::size_t item = 0; item < n_items; ++item)
      process_item(bodies, item, cursor, manifold_, contacts_, used, box_tests);
    contacts_.resize(used);
    apply_law(contacts_.data(), contacts_.data() + contacts_.size(), step);
  } else {
    const std::size_t n_chunks = (n_items + kChunkItems - 1) / kChunkItems;
    if (chunk_buffers_.size() < n_chunks) chunk_buffers_.resize(n_chunks);
    // One contiguous run of chunks per thread, not chunks handed out
    // dynamically: the same thread then makes chunk c's records every step,
    // copies them in the join below (same runs) and reads them back as
    // history, so they stay in its core's cache. Handed out dynamically they
    // moved between the cores: on the 1e4-body pressed columns the two
    // threads together spent 1.23-1.33x the one-thread CPU time per
    // body-step, and 0.98-1.08x with fixed runs (docs/performance_history.md,
    // change 15). The runs are cut at equal cost, as the chunks cost at the
    // last step, not at equal counts: the touching pairs of a falling pile
    // sit among its lowest bodies, and in equal halves one thread got
    // nearly all of them (change 16).
    if (chunk_cost_.size() != n_chunks) chunk_cost_.resize(n_chunks, double(kChunkItems));
    split_by_cost(chunk_cost_.data(), std::int64_t(n_chunks), std::min(worker_count(), int(n_chunks)), chunk_runs_);
    parallel_for_parts(chunk_runs_, true, [&](std::int64_t c) {
      std::vector<ContactPoint>& buf = chunk_buffers_[std::size_t(c)];
      std::size_t cursor = kNoCursor, used = 0;
      ContactManifold manifold;
      const std::size_t begin = std::size_t(c) * kChunkItems;
      const std::size_t end = std::min(n_items, begin + kChunkItems);
      std::size_t box_tests = 0;
      for (std::size_t item = begin; item < end; ++item)
        process_item(bodies, item, cursor, manifold, buf, used, box_tests);
      buf.resize(used);
      apply_law(buf.data(), buf.data() + buf.size(), step);
      chunk_cost_[std::size_t(c)] =
          double(end - begin) + kCostPerBoxTest * double(box_tests) + kCostPerPoint * double(buf.size());
    });
    // Join the chunk buffers in chunk order: offsets first (serial over
    // chunks), then every chunk copies its own records. contacts_ keeps its
    // old records (those of two steps ago) up to the new size, so only the
    // growth is constructed and every record is written once, by its chunk.
    chunk_offsets_.resize(n_chunks + 1);
    std::size_t total = 0;
    for (std::size_t c = 0; c < n_chunks; ++c) {
      chunk_offsets_[c] = total;
      total += chunk_buffers_[c].size();
    }
    chunk_offsets_[n_chunks] = total;
    contacts_.resize(total);
    parallel_for_parts(chunk_runs_, true, [&](std::int64_t bc) {
      const auto c = std::size_t(bc);
      std::copy(chunk_buffers_[c].begin(), chunk_buffers_[c].end(), contacts_.begin() + std::ptrdiff_t(chunk_offsets_[c]));
    });
  }
  // Elastic energy summed in contact order (deterministic); springs of
  // contacts that ended lose their energy (header): the shear spring's as
  // friction, the normal spring's as viscous. The terms are first put into
  // compact arrays (on threads for large lists), then added one by one in
  // list order: the same sums, bit for bit, as one loop over the records,
  // at a fraction of the serial memory traffic. A carried record adds +0.0,
  // which leaves a sum that started at +0.0 unchanged.
  const std::size_t n_now = contacts_.size(), n_prev = previous_.size();
  sum_terms_.resize(std::max(n_now, 2 * n_prev));
  parallel_for_static(std::int64_t(n_now), parallel && n_now >= std::size_t(settings_.parallel_threshold),
                      [&](std::int64_t k) { sum_terms_[std::size_t(k)] = contacts_[std::size_t(k)].elastic_J; });
  double elastic = 0.0, viscous = 0.0, friction = 0.0;
  for (std::size_t k = 0; k < n_now; ++k) elastic += sum_terms_[k];
  parallel_for_static(std::int64_t(n_prev), parallel && n_prev >= std::size_t(settings_.parallel_threshold),
                      [&](std::int64_t bk) {
                        const auto k = std::size_t(bk);
                        const ContactPoint& p = previous_[k];
                        sum_terms_[2 * k] = p.history_carried ? 0.0 : p.elastic_tangential_J;
                        sum_terms_[2 * k + 1] = p.history_carried ? 0.0 : p.elastic_J - p.elastic_tangential_J;
                      });
  for (std::size_t k = 0; k < n_prev; ++k) {
    friction += sum_terms_[2 * k];
    viscous += sum_terms_[2 * k + 1];
  }
  elastic_J_ = elastic;
  viscous_J_ += viscous;
  friction_J_ += friction;
}

void ContactSystem::finish_step(const BodyStore& bodies, const StepInfo& step, EventLog& /*events*/) {
  // Losses of step n from the work of the contact forces with v_n (header).
  // The bodies hold v(n+1/2) and w(n+1/2); the arms are those of step n.
  const double dt = step.dt_s;
  const std::int64_t n = std::int64_t(contacts_.size());
  // The ledger counts step 0's work from t = 0 only (its second half), and
  // reports each step's work half at the step itself (energy_ledger.h);
  // elastic changes count in full.
  const double first_missing = step.step == 0 ? 0.5 : 0.0;
  sum_terms_.resize(std::max(sum_terms_.size(), 4 * contacts_.size()));
  parallel_for_static(n, n >= settings_.parallel_threshold, [&](std::int64_t k) {
    ContactPoint& c = contacts_[std::size_t(k)];
    const bool moving_a = c.body_a >= 0 && (c.pair_key & kGroundKeyHigh) != kGroundKeyHigh;
    const Vec3 va = moving_a ? Vec3(bodies.velocity_mps[c.body_a] + bodies.angular_velocity_radps[c.body_a].cross(c.arm_a_m))
                             : Vec3(Vec3::Zero());
    const Vec3 v_next = bodies.velocity_mps[c.body_b] + bodies.angular_velocity_radps[c.body_b].cross(c.arm_b_m) - va;
    const Vec3 v_rel = 0.5 * (c.velocity_prev_mps + v_next);
    const double loss_normal_J = -dt * (c.normal_force_N * c.normal.dot(v_rel) + c.lean_force_N.dot(v_rel));  // -W_N
    const double loss_tangential_J = -dt * c.tangential_force_N.dot(v_rel);      // -W_T
    const double d_elastic_t = c.elastic_tangential_J - c.elastic_tangential_prev_J;
    const double d_elastic_n = (c.elastic_J - c.elastic_tangential_J) - (c.elastic_prev_J - c.elastic_tangential_prev_J);
    c.viscous_work_loss_J = loss_normal_J + (c.sliding ? 0.0 : loss_tangential_J);
    c.friction_work_loss_J = c.sliding ? loss_tangential_J : 0.0;
    c.viscous_J = c.viscous_work_loss_J - d_elastic_n - (c.sliding ? 0.0 : d_elastic_t);
    c.friction_J = c.friction_work_loss_J - (c.sliding ? d_elastic_t : 0.0);
    // The terms of the sums below, in a compact array (narrow_phase says why).
    double* terms = sum_terms_.data() + 4 * std::size_t(k);
    terms[0] = c.viscous_J - first_missing * c.viscous_work_loss_J;
    terms[1] = c.friction_J - first_missing * c.friction_work_loss_J;
    terms[2] = 0.5 * c.viscous_work_loss_J;
    terms[3] = 0.5 * c.friction_work_loss_J;
  });
  // Summed in contact order (deterministic); with them the press that is the
  // largest fraction of its box's section (ContactPressPeak; the first such
  // point in contact order).
  double viscous = 0.0, friction = 0.0, viscous_half = 0.0, friction_half = 0.0;
  for (std::size_t k = 0; k < contacts_.size(); ++k) {
    const double* terms = sum_terms_.data() + 4 * k;
    viscous += terms[0];
    friction += terms[1];
    viscous_half += terms[2];
    friction_half += terms[3];
    const ContactPoint& c = contacts_[k];
    const double pressed_m = c.depth_m - c.reference_depth_m;
    if (!(pressed_m > 0.0)) continue;
    const bool ground = (c.pair_key & kGroundKeyHigh) == kGroundKeyHigh;
    BodyId measured = c.body_b;
    if (!ground && half_dimension_m_[std::size_t(c.body_a)] < half_dimension_m_[std::size_t(c.body_b)])
      measured = c.body_a;
    const double half_m = half_dimension_m_[std::size_t(measured)];
    if (pressed_m > press_peak_.ratio * half_m) {
      press_peak_ = {pressed_m / half_m, pressed_m, half_m, step.time_s, ground ? kNoBody : c.body_a, c.body_b,
                     measured};
    }
  }
  viscous_J_ += viscous;
  friction_J_ += friction;
  viscous_half_J_ = viscous_half;
  friction_half_J_ = friction_half;
}

void ContactSystem::gather(BodyStore& bodies) {
  const std::size_t n = bodies.size();
  const bool parallel =
      std::int64_t(n) >= settings_.parallel_threshold && contacts_.size() >= std::size_t(settings_.parallel_threshold);
  if (!parallel) {
    // One thread: each body's sums run over its contacts in contact order,
    // from zero, exactly as the per-body lists below do them.
    body_force_N_.resize(n);
    body_torque_Nm_.resize(n);
    body_touched_.assign(n, 0);
    auto add = [&](std::size_t i, const Vec3& fi, const Vec3& p) {
      const Vec3 ti = (p - bodies.position_m[i]).cross(fi);
      if (body_touched_[i]) {
        body_force_N_[i] += fi;
        body_torque_Nm_[i] += ti;
      } else {
        body_touched_[i] = 1;
        body_force_N_[i] = Vec3::Zero() + fi;
        body_torque_Nm_[i] = Vec3::Zero() + ti;
      }
    };
    for (const ContactPoint& c : contacts_) {
      const Vec3 fb = c.force_N();
      if (c.body_a >= 0) add(std::size_t(c.body_a), Vec3(-fb), c.position_m);
      add(std::size_t(c.body_b), fb, c.position_m);
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!body_touched_[i]) continue;
      bodies.force_N[i] += body_force_N_[i];
      bodies.torque_Nm[i] += body_torque_Nm_[i];
    }
    return;
  }
  // The two bodies of every contact, copied out of the records on threads,
  // so that the serial passes building the CSR below read 8 bytes per
  // contact instead of a whole record.
  const std::int32_t cn = std::int32_t(contacts_.size());
  contact_bodies_.resize(2 * std::size_t(cn));
  parallel_for_static(cn, true, [&](std::int64_t k) {
    contact_bodies_[2 * std::size_t(k)] = contacts_[std::size_t(k)].body_a;
    contact_bodies_[2 * std::size_t(k) + 1] = contacts_[std::size_t(k)].body_b;
  });
  body_start_.assign(n + 1, 0);
  for (std::int32_t k = 0; k < cn; ++k) {
    const BodyId a = contact_bodies_[2 * std::size_t(k)], b = contact_bodies_[2 * std::size_t(k) + 1];
    if (a >= 0) ++body_start_[std::size_t(a) + 1];
    ++body_start_[std::size_t(b) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) body_start_[i + 1] += body_start_[i];
  body_entries_.resize(std::size_t(body_start_[n]));
  {
    // Fill in contact order; a running cursor per body (reuses the CSR shape).
    std::vector<std::int32_t>& cursor = body_start_;
    for (std::int32_t k = 0; k < cn; ++k) {
      const BodyId a = contact_bodies_[2 * std::size_t(k)], b = contact_bodies_[2 * std::size_t(k) + 1];
      if (a >= 0) body_entries_[std::size_t(cursor[std::size_t(a)]++)] = 2 * k;
      body_entries_[std::size_t(cursor[std::size_t(b)]++)] = 2 * k + 1;
    }
    // Cursors now hold the ends; shift back to starts.
    for (std::size_t i = n; i > 0; --i) body_start_[i] = body_start_[i - 1];
    body_start_[0] = 0;
  }
  const std::int64_t nb = std::int64_t(n);
  parallel_for_static(nb, true, [&](std::int64_t i) {
    const std::int32_t s = body_start_[std::size_t(i)], e = body_start_[std::size_t(i) + 1];
    if (s == e) return;
    Vec3 f = Vec3::Zero(), t = Vec3::Zero();
    const Vec3 x = bodies.position_m[std::size_t(i)];
    for (std::int32_t k = s; k < e; ++k) {
      const std::int32_t entry = body_entries_[std::size_t(k)];
      const ContactPoint& c = contacts_[std::size_t(entry >> 1)];
      const Vec3 fb = c.force_N();
      const Vec3 fi = (entry & 1) ? fb : Vec3(-fb);
      f += fi;
      t += (c.position_m - x).cross(fi);
    }
    bodies.force_N[std::size_t(i)] += f;
    bodies.torque_Nm[std::size_t(i)] += t;
  });
}

void ContactSystem::report_energy(EnergyLedger& ledger) const {
  ledger.elastic_J += elastic_J_;
  ledger.dissipated_viscous_J += dissipated_viscous_J();
  ledger.dissipated_friction_J += dissipated_friction_J();
}

Vec3 ContactSystem::force_from_fixed_bodies_N(const BodyStore& bodies) const {
  Vec3 sum = Vec3::Zero();
  for (const ContactPoint& c : contacts_) {
    // force_N() acts on b; the ground is always a.
    const bool ground = (c.pair_key & kGroundKeyHigh) == kGroundKeyHigh;
    const bool fixed_a = ground || (c.body_a >= 0 && bodies.is_fixed[std::size_t(c.body_a)] != 0);
    const bool fixed_b = c.body_b >= 0 && bodies.is_fixed[std::size_t(c.body_b)] != 0;
    if (fixed_a && !fixed_b) sum += c.force_N();
    if (fixed_b && !fixed_a) sum -= c.force_N();
  }
  return sum;
}

double ContactSystem::ground_normal_force_N() const {
  double sum = 0.0;
  for (const ContactPoint& c : contacts_)
    if ((c.pair_key & kGroundKeyHigh) == kGroundKeyHigh) sum += c.normal_force_N;
  return sum;
}

namespace {

// Largest eigenvalue of sum (coef g g^T) over the four corner points of a
// face of one box against a fixed surface, worst over its three face
// orientations: each point a normal term (coef_n) along the face normal and
// two tangential terms (coef_t) in the face plane; g the mass-scaled
// gradient in the box's principal frame. With coef = k it is omega^2 of the
// box resting on that face (1/s^2); with coef = dt^2 k + 2 dt c the matrix
// whose top eigenvalue reaches 4 at the damped limit.
double one_sided_contact_eigenvalue(const Vec3& half_extents_m, double mass_kg, const Vec3& inertia_kgm2,
                                    double coef_n, double coef_t) {
  double worst = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    Eigen::Matrix<double, 6, 6> k = Eigen::Matrix<double, 6, 6>::Zero();
    for (int corner = 0; corner < 4; ++corner) {
      Vec3 arm = Vec3::Zero();
      arm[axis] = -half_extents_m[axis];
      arm[u] = (corner & 1 ? 1.0 : -1.0) * half_extents_m[u];
      arm[v] = (corner & 2 ? 1.0 : -1.0) * half_extents_m[v];
      for (int d = 0; d < 3; ++d) {
        const Vec3 e = Vec3::Unit(d);
        Vec6 g;
        g.head<3>() = e / std::sqrt(mass_kg);
        g.tail<3>() = arm.cross(e).cwiseQuotient(inertia_kgm2.cwiseSqrt());
        k += (d == axis ? coef_n : coef_t) * g * g.transpose();
      }
    }
    worst = std::max(worst, Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(k).eigenvalues().maxCoeff());
  }
  return worst;
}

// one_sided_contact_eigenvalue, each distinct set of arguments computed
// once (compared bit for bit, so the values are those of the function
// itself). The members of a frame come in a few sizes and materials, and
// nine 6x6 eigenvalue problems per box took a fifth of `framequake info`
// on a frame-B-style grid of 97 606 boxes once the network's estimate had
// been made faster.
// A box's size, mass and inertia as bits: boxes with the same bits have the
// same contact eigenvalues and limits (ContactEigenvalues, and the boxes
// bisected in later_stiffest_mode).
using BoxShapeBits = std::array<std::uint64_t, 7>;
BoxShapeBits box_shape_bits(const Vec3& half_extents_m, double mass_kg, const Vec3& inertia_kgm2) {
  return {std::bit_cast<std::uint64_t>(half_extents_m.x()), std::bit_cast<std::uint64_t>(half_extents_m.y()),
          std::bit_cast<std::uint64_t>(half_extents_m.z()), std::bit_cast<std::uint64_t>(mass_kg),
          std::bit_cast<std::uint64_t>(inertia_kgm2.x()),   std::bit_cast<std::uint64_t>(inertia_kgm2.y()),
          std::bit_cast<std::uint64_t>(inertia_kgm2.z())};
}

class ContactEigenvalues {
 public:
  double operator()(const Vec3& half_extents_m, double mass_kg, const Vec3& inertia_kgm2, double coef_n,
                    double coef_t) {
    Key key;
    const BoxShapeBits shape = box_shape_bits(half_extents_m, mass_kg, inertia_kgm2);
    std::copy(shape.begin(), shape.end(), key.begin());
    key[7] = std::bit_cast<std::uint64_t>(coef_n);
    key[8] = std::bit_cast<std::uint64_t>(coef_t);
    const auto [it, is_new] = values_.try_emplace(key, 0.0);
    if (is_new) it->second = one_sided_contact_eigenvalue(half_extents_m, mass_kg, inertia_kgm2, coef_n, coef_t);
    return it->second;
  }

 private:
  using Key = std::array<std::uint64_t, 9>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ULL;
      for (std::uint64_t w : k) h = (h ^ w) * 0x100000001b3ULL + (h >> 29);
      return std::size_t(h);
    }
  };
  std::unordered_map<Key, double, KeyHash> values_;
};

// The dashpots of one of the four corner points of a face contact whose
// pair has mass m_pair (ContactSystem::process_item: share 1 of 4, mass
// m_pair / 4 per point), as the contact law forms them.
ContactDashpots corner_dashpots(const ContactCoefficients& coeff, double pair_mass_kg) {
  ContactLawInput in;
  in.stiffness_scale = 1.0;
  in.effective_mass_kg = 0.25 * pair_mass_kg;
  return contact_dashpots(coeff, in);
}

// The dt at which `lambda(dt)`, the top eigenvalue of dt^2 K~ + 2 dt C~ of
// some contact (increasing in dt), reaches 4, between `lo` (lambda <= 4)
// and `hi` (lambda >= 4); bisection to 1e-12 relative.
template <class Lambda>
double damped_limit(Lambda lambda, double lo, double hi) {
  for (int it = 0; it < 60 && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (lambda(mid) < 4.0 ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

// Box pair keys of linearised terms: (a + 1) << 32 | b, a = -1 for the ground.
void ContactSystem::linearised_springs(const BodyStore& bodies, std::vector<LinearisedSpring>& out) const {
  // The contacts present now (contacts/README.md, "Stable step"): every box
  // within kTouchMargin_m of the ground or of another (unbonded) box gets
  // the points the narrow phase would give, each point a normal and two
  // tangential spring-dashpots with the stiffness share and the mass share
  // process_item gives it (k = w k_n, m = w m_pair / sum w, c = 2 zeta
  // sqrt(k m), contact_dashpots), with the coefficients of its pair
  // (coefficients_of: the ground's, or the materials').
  const std::size_t nb = bodies.size();
  auto is_free = [&](std::size_t i) { return !bodies.is_fixed[i] && bodies.info[i].kind != MemberKind::Ground; };
  auto box_of = [&](std::size_t i, double inflate_m) {
    OrientedBox box;
    box.center_m = bodies.position_m[i];
    box.rotation = bodies.rotation[i];
    box.half_extents_m = bodies.half_extents_m[i] + Vec3::Constant(inflate_m);
    return box;
  };
  // coefficients_of solves for the damping ratio of the restitution asked
  // for by bisection (some 200 evaluations of the impact's closed form): at
  // 10 000 touching boxes, doing that per pair took a fifth of `info`. The
  // coefficients depend only on the pair's materials (or the ground), so
  // each distinct pair of materials is solved once here.
  std::map<std::pair<int, int>, ContactCoefficients> coefficient_cache;
  auto cached_coefficients_of = [&](BodyId a, BodyId b) -> const ContactCoefficients& {
    const int ma = a == kNoBody ? -1 : material_of(std::size_t(a)), mb = material_of(std::size_t(b));
    const std::pair<int, int> key{std::min(ma, mb), std::max(ma, mb)};
    auto it = coefficient_cache.find(key);
    if (it == coefficient_cache.end()) it = coefficient_cache.emplace(key, coefficients_of(a, b)).first;
    return it->second;
  };
  auto add_manifold = [&](BodyId a, BodyId b, const ContactManifold& manifold) {
    double weight_sum = 0.0;
    for (int k = 0; k < manifold.count; ++k) weight_sum += manifold.points[std::size_t(k)].weight;
    if (!(weight_sum > 0.0)) return;
    const double ma = a == kNoBody ? 0.0 : bodies.mass_kg[std::size_t(a)], mb = bodies.mass_kg[std::size_t(b)];
    const double pair_mass = a == kNoBody || bodies.is_fixed[std::size_t(a)] ? mb
                             : bodies.is_fixed[std::size_t(b)]                ? ma
                                                                              : ma * mb / (ma + mb);
    const std::int64_t element = (std::int64_t(a + 1) << 32) | std::int64_t(b);
    const ContactCoefficients& co = cached_coefficients_of(a, b);
    for (int k = 0; k < manifold.count; ++k) {
      const ContactPointGeometry& p = manifold.points[std::size_t(k)];
      const Vec3 n = p.normal;
      const Vec3 t1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
      const Vec3 t2 = n.cross(t1);
      // The normal spring acts along n + lean (ContactPointGeometry::lean):
      // stiffness k |n + lean|^2 <= 2 k along it. Its dashpot is taken
      // along the same direction, which overstates it by as much and errs
      // towards a smaller step.
      const Vec3 normal_spring = n + p.lean;
      const Vec3* dirs[3] = {&normal_spring, &t1, &t2};
      // The point's shares as process_item gives them, its dashpots as the
      // law forms them.
      ContactLawInput in;
      in.stiffness_scale = p.weight;
      in.effective_mass_kg = pair_mass * p.weight / weight_sum;
      const ContactDashpots c = contact_dashpots(co, in);
      for (int d = 0; d < 3; ++d) {
        LinearisedSpring r;
        r.a = a;
        r.b = b;
        r.k_Npm = p.weight * (d == 0 ? co.normal_stiffness_N_per_m : co.tangential_stiffness_N_per_m);
        r.c_Nspm = d == 0 ? c.normal_Nspm : c.tangential_Nspm;
        if (a != kNoBody) r.ga = -mass_scaled_gradient(bodies, a, p.position_m - bodies.position_m[std::size_t(a)], *dirs[d]);
        r.gb = mass_scaled_gradient(bodies, b, p.position_m - bodies.position_m[std::size_t(b)], *dirs[d]);
        r.element = element;
        out.push_back(r);
      }
    }
  };
  ContactManifold manifold;
  if (ground_enabled_) {
    for (std::size_t i = 0; i < nb; ++i) {
      if (!is_free(i)) continue;
      const OrientedBox box = box_of(i, 0.0);
      if (box_lowest_z_m(box) > ground_level_m_ + kTouchMargin_m) continue;
      collide_box_ground(box, ground_level_m_ + kTouchMargin_m, manifold);
      add_manifold(kNoBody, BodyId(i), manifold);
    }
  }
  // Box pairs: sweep along x over bounding spheres (O(n log n + pairs)).
  std::vector<std::pair<double, std::size_t>> order;
  for (std::size_t i = 0; i < nb; ++i)
    if (bodies.info[i].kind != MemberKind::Ground)
      order.push_back({bodies.position_m[i].x() - bodies.half_extents_m[i].norm(), i});
  std::sort(order.begin(), order.end());
  for (std::size_t p = 0; p < order.size(); ++p) {
    const std::size_t i = order[p].second;
    const double ri = bodies.half_extents_m[i].norm();
    const double x_end = bodies.position_m[i].x() + ri + kTouchMargin_m;
    for (std::size_t q = p + 1; q < order.size() && order[q].first <= x_end; ++q) {
      const std::size_t j = order[q].second;
      if (!is_free(i) && !is_free(j)) continue;
      const double reach = ri + bodies.half_extents_m[j].norm() + kTouchMargin_m;
      if ((bodies.position_m[i] - bodies.position_m[j]).squaredNorm() > reach * reach) continue;
      const BodyId a = BodyId(std::min(i, j)), b = BodyId(std::max(i, j));
      if (bonded_ && bonded_->bonded(a, b)) continue;
      if (collide_box_box(box_of(std::size_t(a), 0.5 * kTouchMargin_m), box_of(std::size_t(b), 0.5 * kTouchMargin_m),
                          manifold) == 0)
        continue;
      add_manifold(a, b, manifold);
    }
  }
}

int ContactSystem::material_of(std::size_t body) const {
  return body < body_material_.size() ? body_material_[body] : 0;  // before prepare: unset bodies are 0
}

ContactParams ContactSystem::material_pair_params(int m1, int m2) const {
  const auto it = pair_params_.find({std::min(m1, m2), std::max(m1, m2)});
  return it == pair_params_.end() ? ContactParams{} : it->second;
}

ContactCoefficients ContactSystem::coefficients_of(BodyId a, BodyId b) const {
  // As prepare() assigns them, before or after it: the ground's, the
  // materials' pair, or the default pair.
  if (a == kNoBody) return make_contact_coefficients(ground_params_, "the ground");
  return make_contact_coefficients(material_pair_params(material_of(std::size_t(a)), material_of(std::size_t(b))),
                                   "a pair");
}

std::string ContactSystem::describe_linearised_spring(const BodyStore& bodies, std::int64_t element) const {
  const BodyId a = BodyId(element >> 32) - 1, b = BodyId(element & 0xffffffff);
  const ContactCoefficients co = coefficients_of(a, b);
  std::ostringstream where;
  where << "contact springs (k_n = " << co.normal_stiffness_N_per_m << " N/m, k_t = "
        << co.tangential_stiffness_N_per_m << " N/m per point, damping ratio " << co.damping_ratio
        << ") of the contact of '" << bodies.info[std::size_t(b)].name << "' with ";
  if (a == kNoBody)
    where << "the ground";
  else
    where << "'" << bodies.info[std::size_t(a)].name << "'";
  return where.str();
}

ContactCoefficients ContactSystem::stiffest_coefficients(const BodyStore& bodies, LaterContact kind) const {
  // The coefficient sets the later contacts of `kind` can use, from the
  // materials of the bodies that can meet: a free box on a fixed surface
  // (the ground when it is on, a fixed box of some material), or two free
  // boxes. A lone block on the ground is then limited by the ground's
  // coefficients alone, and a stack of soft boxes on a stiff ground by the
  // ground for a box landing on it and by the soft pair for two boxes
  // meeting, not by a stiffness no such contact can have.
  std::vector<int> free_materials, fixed_materials;
  std::vector<std::size_t> free_count;  // free bodies of free_materials[k]
  std::size_t free_bodies = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies.info[i].kind == MemberKind::Ground) continue;
    std::vector<int>& list = bodies.is_fixed[i] ? fixed_materials : free_materials;
    const auto at = std::find(list.begin(), list.end(), material_of(i));
    const std::size_t k = std::size_t(at - list.begin());
    if (at == list.end()) list.push_back(material_of(i));
    if (!bodies.is_fixed[i]) {
      ++free_bodies;
      if (k == free_count.size()) free_count.push_back(0);
      ++free_count[k];
    }
  }
  ContactCoefficients sc;  // all zero: no such contact can form
  auto take = [&](const ContactParams& params) {
    const ContactCoefficients c = make_contact_coefficients(params, "a contact");
    sc.normal_stiffness_N_per_m = std::max(sc.normal_stiffness_N_per_m, c.normal_stiffness_N_per_m);
    sc.tangential_stiffness_N_per_m = std::max(sc.tangential_stiffness_N_per_m, c.tangential_stiffness_N_per_m);
    sc.damping_ratio = std::max(sc.damping_ratio, c.damping_ratio);
  };
  auto take_pair = [&](int m1, int m2) { take(material_pair_params(m1, m2)); };
  if (kind == LaterContact::OnFixedSurface) {
    if (free_bodies == 0) return sc;
    if (ground_enabled_) take(ground_params_);
    for (int f : free_materials)
      for (int x : fixed_materials) take_pair(f, x);
  } else {
    if (free_bodies < 2) return sc;
    // Two boxes of one material only where there are two of them.
    for (std::size_t f = 0; f < free_materials.size(); ++f)
      for (std::size_t g = f; g < free_materials.size(); ++g)
        if (g != f || free_count[f] >= 2) take_pair(free_materials[f], free_materials[g]);
  }
  return sc;
}

StiffestMode ContactSystem::later_stiffest_mode(const BodyStore& bodies) const {
  // The worst single contact that may form later (falling debris), with
  // its dashpots (contacts/README.md, "Stable step"). One box on a fixed
  // surface: its four-corner face contact, worst face. A face contact is
  // the worst a box can rest in: an edge or corner contact has a subset of
  // its points, a face on a smaller face has shorter arms. Two free boxes
  // a, b: for unit x = (x_a, x_b) in mass-scaled coordinates the Rayleigh
  // quotient of any sum of coef g g^T terms is |G_b x_b - G_a x_a|^2 <=
  // (|G_a| |x_a| + |G_b| |x_b|)^2 <= lambda(a) + lambda(b) (Cauchy-Schwarz),
  // with equality for two equal boxes in their antisymmetric mode; the
  // bound uses the two boxes of largest undamped lambda, with the dashpots
  // of their pair's reduced mass. The damped limit of each is the dt where
  // its lambda(dt^2 K~ + 2 dt C~) reaches 4. Each uses the stiffest
  // coefficients its kind of contact can have (stiffest_coefficients).
  StiffestMode mode;
  const std::size_t nb = bodies.size();
  auto is_free = [&](std::size_t i) { return !bodies.is_fixed[i] && bodies.info[i].kind != MemberKind::Ground; };
  ContactEigenvalues eigenvalue;
  auto lambda_of = [&](const ContactCoefficients& sc, std::size_t i, double dt, double pair_mass_kg) {
    const ContactDashpots c = corner_dashpots(sc, pair_mass_kg);
    return eigenvalue(bodies.half_extents_m[i], bodies.mass_kg[i], bodies.principal_inertia_kgm2[i],
                      dt * dt * sc.normal_stiffness_N_per_m + 2.0 * dt * c.normal_Nspm,
                      dt * dt * sc.tangential_stiffness_N_per_m + 2.0 * dt * c.tangential_Nspm);
  };
  double best_dt = HUGE_VAL;
  std::string where;
  ContactCoefficients where_sc;
  // A box whose eigenvalue overflows (a stiffness of 1e308, a mass of
  // 1e-300): the limit is not a number, reported as NaN so that the run is
  // refused rather than left without a limit.
  bool not_finite = false;

  // One box on a fixed surface. Undamped lambda of every free box; the
  // damped limit of one box lies between 2 / (sqrt(l_k + l_c^2 / 4) +
  // l_c / 2) and 2 / sqrt(l_k), so only boxes whose lower bound is below
  // the best limit found need it.
  const ContactCoefficients surface = stiffest_coefficients(bodies, LaterContact::OnFixedSurface);
  if (surface.normal_stiffness_N_per_m > 0.0) {
    struct Box {
      double lower_dt, lambda_k;
      std::size_t i;
    };
    std::vector<Box> boxes;
    for (std::size_t i = 0; i < nb; ++i) {
      if (!is_free(i)) continue;
      const double lk = eigenvalue(bodies.half_extents_m[i], bodies.mass_kg[i], bodies.principal_inertia_kgm2[i],
                                   surface.normal_stiffness_N_per_m, surface.tangential_stiffness_N_per_m);
      if (!std::isfinite(lk)) {
        not_finite = true;
        where = "a later face contact of '" + bodies.info[i].name + "' on a fixed surface (on its worst face, should it land flat on one: a contact that may form later)";
        where_sc = surface;
      }
      if (!(lk > 0.0)) continue;
      const ContactDashpots c = corner_dashpots(surface, bodies.mass_kg[i]);
      const double lc = eigenvalue(bodies.half_extents_m[i], bodies.mass_kg[i], bodies.principal_inertia_kgm2[i],
                                   c.normal_Nspm, c.tangential_Nspm);
      boxes.push_back({2.0 / (std::sqrt(lk + 0.25 * lc * lc) + 0.5 * lc), lk, i});
    }
    std::sort(boxes.begin(), boxes.end(), [](const Box& x, const Box& y) { return x.lower_dt < y.lower_dt; });
    // A box of the size, mass and inertia of one already bisected has its
    // limit (the same bits), which cannot be below the best found.
    std::set<BoxShapeBits> bisected;
    for (const Box& box : boxes) {
      if (box.lower_dt >= best_dt) break;
      const auto shape =
          box_shape_bits(bodies.half_extents_m[box.i], bodies.mass_kg[box.i], bodies.principal_inertia_kgm2[box.i]);
      if (!bisected.insert(shape).second) continue;
      const double m = bodies.mass_kg[box.i];
      const double dt = damped_limit([&](double t) { return lambda_of(surface, box.i, t, m); }, box.lower_dt,
                                     2.0 / std::sqrt(box.lambda_k));
      if (dt < best_dt) {
        best_dt = dt;
        where = "a later face contact of '" + bodies.info[box.i].name + "' on a fixed surface (on its worst face, should it land flat on one: a contact that may form later)";
        where_sc = surface;
      }
    }
  }

  // Two free boxes.
  const ContactCoefficients pair = stiffest_coefficients(bodies, LaterContact::BoxOnBox);
  if (pair.normal_stiffness_N_per_m > 0.0) {
    double top1 = 0.0, top2 = 0.0;
    std::size_t top1_body = nb, top2_body = nb;
    for (std::size_t i = 0; i < nb; ++i) {
      if (!is_free(i)) continue;
      const double lk = eigenvalue(bodies.half_extents_m[i], bodies.mass_kg[i], bodies.principal_inertia_kgm2[i],
                                   pair.normal_stiffness_N_per_m, pair.tangential_stiffness_N_per_m);
      if (!std::isfinite(lk)) {
        not_finite = true;
        where = "a later face contact of '" + bodies.info[i].name + "' on another free box (on its worst face, should it land flat on one: a contact that may form later)";
        where_sc = pair;
      }
      if (lk > top1) {
        top2 = top1;
        top2_body = top1_body;
        top1 = lk;
        top1_body = i;
      } else if (lk > top2) {
        top2 = lk;
        top2_body = i;
      }
    }
    if (top2_body < nb && top1 + top2 > 0.0) {
      const double ma = bodies.mass_kg[top1_body], mb = bodies.mass_kg[top2_body];
      const double reduced = ma * mb / (ma + mb);
      const double dt = damped_limit(
          [&](double t) { return lambda_of(pair, top1_body, t, reduced) + lambda_of(pair, top2_body, t, reduced); },
          0.0, 2.0 / std::sqrt(top1 + top2));
      if (dt < best_dt) {
        best_dt = dt;
        where = "a later face contact of '" + bodies.info[top1_body].name + "' on another free box (on its worst face, should it land flat on one: a contact that may form later)";
        where_sc = pair;
      }
    }
  }
  if (not_finite) {
    mode.omega_radps = std::numeric_limits<double>::quiet_NaN();
  } else {
    if (!(best_dt < HUGE_VAL) || !(best_dt > 0.0)) return mode;
    mode.omega_radps = 2.0 / best_dt;
  }
  std::ostringstream w;
  w << "contact springs (k_n = " << where_sc.normal_stiffness_N_per_m << " N/m, k_t = "
    << where_sc.tangential_stiffness_N_per_m << " N/m per point, damping ratio " << where_sc.damping_ratio << ") of "
    << where;
  mode.where = w.str();
  return mode;
}

}  // namespace fq
