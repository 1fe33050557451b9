// Checkpoint state of the contact system and its broad phase
// (contact_system.h, broad_phase.h, force_provider.h). The contact list of
// the last step is the contacts' whole history (the next step looks up
// tangential springs and reference depths in it); the broad phase is saved
// too, so a resumed run rebuilds it at the same steps and reports the same
// candidate pairs. Materials and coefficients are rebuilt from the case.
#include <string>

#include "contacts/contact_system.h"
#include "dem_core/state_io.h"

namespace fq {

namespace {

// 2: initial overlaps; 3: the largest press so far (ContactPressPeak); 4:
// with the box it was measured against; 5: each point's lean force (stop 42).
constexpr std::uint32_t kContactStateVersion = 5;

void save_point(StateWriter& out, const ContactPoint& c) {
  out.pod(c.body_a);
  out.pod(c.body_b);
  out.u32(c.feature);
  out.vec3(c.position_m);
  out.vec3(c.normal);
  out.f64(c.depth_m);
  out.f64(c.normal_force_N);
  out.vec3(c.tangential_force_N);
  out.vec3(c.shear_spring_N);
  out.vec3(c.lean_force_N);
  out.f64(c.reference_depth_m);
  out.boolean(c.sliding);
  out.u64(c.pair_key);
  out.pod(c.coeff_index);
  out.f64(c.stiffness_scale);
  out.f64(c.effective_mass_kg);
  out.boolean(c.history_carried);
  out.f64(c.elastic_J);
  out.f64(c.elastic_tangential_J);
  out.f64(c.elastic_prev_J);
  out.f64(c.elastic_tangential_prev_J);
  out.vec3(c.arm_a_m);
  out.vec3(c.arm_b_m);
  out.vec3(c.velocity_prev_mps);
  out.f64(c.viscous_J);
  out.f64(c.friction_J);
  out.f64(c.viscous_work_loss_J);
  out.f64(c.friction_work_loss_J);
}

ContactPoint load_point(StateReader& in, std::size_t body_count, std::size_t coeff_count) {
  ContactPoint c;
  const char* what = "contact point";
  c.body_a = in.pod<BodyId>(what);
  c.body_b = in.pod<BodyId>(what);
  if (c.body_a < kNoBody || c.body_a >= BodyId(body_count) || c.body_b < 0 || c.body_b >= BodyId(body_count))
    in.fail("contact point names a body this scene does not have");
  c.feature = in.u32(what);
  c.position_m = in.vec3(what);
  c.normal = in.vec3(what);
  c.depth_m = in.f64(what);
  c.normal_force_N = in.f64(what);
  c.tangential_force_N = in.vec3(what);
  c.shear_spring_N = in.vec3(what);
  c.lean_force_N = in.vec3(what);  // the lean itself the next narrow phase sets again
  c.reference_depth_m = in.f64(what);
  c.sliding = in.boolean(what);
  c.pair_key = in.u64(what);
  // Ground contacts carry the key 0xFFFFFFFF'b (contact_system.cpp); any
  // other contact is between two bodies and is keyed by them.
  const bool ground = (c.pair_key >> 32) == 0xFFFFFFFFull;
  if (!ground && (c.body_a < 0 || c.pair_key != ((std::uint64_t(std::uint32_t(c.body_a)) << 32) | std::uint32_t(c.body_b))))
    in.fail("contact point whose key does not match its bodies");
  c.coeff_index = in.pod<std::int32_t>(what);
  if (c.coeff_index < 0 || std::size_t(c.coeff_index) >= coeff_count)
    in.fail("contact point refers to a contact coefficient this scene does not have");
  c.stiffness_scale = in.f64(what);
  c.effective_mass_kg = in.f64(what);
  c.history_carried = in.boolean(what);
  c.elastic_J = in.f64(what);
  c.elastic_tangential_J = in.f64(what);
  c.elastic_prev_J = in.f64(what);
  c.elastic_tangential_prev_J = in.f64(what);
  c.arm_a_m = in.vec3(what);
  c.arm_b_m = in.vec3(what);
  c.velocity_prev_mps = in.vec3(what);
  c.viscous_J = in.f64(what);
  c.friction_J = in.f64(what);
  c.viscous_work_loss_J = in.f64(what);
  c.friction_work_loss_J = in.f64(what);
  return c;
}

}  // namespace

void BroadPhase::save_state(StateWriter& out) const {
  out.section("broad_phase");
  out.f64(skin_m_);
  out.f64(cell_m_);
  out.i64(rebuilds_);
  out.boolean(built_);
  out.u64(bonded_size_at_build_);
  out.u64(pairs_.size());
  for (const BodyPair& p : pairs_) {
    out.pod(p.a);
    out.pod(p.b);
  }
  out.vec3s(position0_m_);
  out.quats(orientation0_);
  out.vec(half_diagonal_m_);
}

void BroadPhase::load_state(StateReader& in) {
  in.section("broad_phase");
  const double skin = in.f64("broad-phase skin");
  if (skin != skin_m_) in.fail("broad-phase skin differs from this scene's");
  const double cell = in.f64("broad-phase cell size");
  const std::int64_t rebuilds = in.i64("broad-phase rebuild count");
  const bool built = in.boolean("broad-phase built flag");
  const std::uint64_t bonded_size = in.u64("broad-phase bonded count");
  const std::uint64_t n_pairs = in.u64("broad-phase pair count");
  if (n_pairs > in.remaining() / (2 * sizeof(BodyId))) in.fail("broad-phase pair count larger than the data left");
  const std::size_t n = participates_.size();
  std::vector<BodyPair> pairs(static_cast<std::size_t>(n_pairs));
  for (BodyPair& p : pairs) {
    p.a = in.pod<BodyId>("broad-phase pair");
    p.b = in.pod<BodyId>("broad-phase pair");
    if (p.a < 0 || p.b <= p.a || std::size_t(p.b) >= n) in.fail("broad-phase pair names a body this scene does not have");
  }
  // Saved poses: one per body once built, none before.
  const std::size_t expected = built ? n : 0;
  auto position0 = in.vec3s("broad-phase saved positions", expected);
  auto orientation0 = in.quats("broad-phase saved orientations", expected);
  auto half_diagonal = in.vec<double>("broad-phase half diagonals", expected);
  cell_m_ = cell;
  rebuilds_ = rebuilds;
  built_ = built;
  bonded_size_at_build_ = std::size_t(bonded_size);
  pairs_ = std::move(pairs);
  position0_m_ = std::move(position0);
  orientation0_ = std::move(orientation0);
  half_diagonal_m_ = std::move(half_diagonal);
}

void ContactSystem::save_state(StateWriter& out) const {
  out.section("contacts");
  out.u32(kContactStateVersion);
  out.u64(body_material_.size());
  out.u64(coeffs_.size());
  out.boolean(prepared_);
  out.u64(contacts_.size());
  for (const ContactPoint& c : contacts_) save_point(out, c);
  out.vec(soft_start_pairs_);
  out.u64(released_read_);
  out.boolean(initial_overlaps_checked_);
  out.u64(initial_overlaps_.size());
  for (const InitialOverlap& o : initial_overlaps_) {
    out.u64(std::uint64_t(o.body_a));
    out.u64(std::uint64_t(o.body_b));
    out.f64(o.depth_m);
  }
  out.f64(elastic_J_);
  out.f64(viscous_J_);
  out.f64(friction_J_);
  out.f64(viscous_half_J_);
  out.f64(friction_half_J_);
  out.f64(press_peak_.ratio);
  out.f64(press_peak_.depth_m);
  out.f64(press_peak_.half_dimension_m);
  out.f64(press_peak_.time_s);
  out.u64(std::uint64_t(std::int64_t(press_peak_.body_a)));
  out.u64(std::uint64_t(std::int64_t(press_peak_.body_b)));
  out.u64(std::uint64_t(std::int64_t(press_peak_.measured)));
  broad_.save_state(out);
}

void ContactSystem::load_state(StateReader& in) {
  in.section("contacts");
  const std::uint32_t version = in.u32("contact state version");
  if (version != kContactStateVersion)
    in.fail("contact state version " + std::to_string(version) + ", this build reads " +
            std::to_string(kContactStateVersion));
  const std::uint64_t bodies = in.u64("contact body count");
  if (bodies != body_material_.size())
    in.fail("the contact state has " + std::to_string(bodies) + " bodies, this scene " +
            std::to_string(body_material_.size()));
  const std::uint64_t coeffs = in.u64("contact coefficient count");
  if (coeffs != coeffs_.size())
    in.fail("the contact state has " + std::to_string(coeffs) + " material pairs, this scene " +
            std::to_string(coeffs_.size()));
  if (!in.boolean("contacts prepared flag")) in.fail("the contact state was saved before the contacts were prepared");
  if (!prepared_) in.fail("load_state called on contacts that are not prepared (initialize the simulation first)");
  const std::uint64_t n = in.u64("contact count");
  // A saved point takes well over 100 bytes.
  if (n > in.remaining() / 100) in.fail("contact count larger than the data left");
  std::vector<ContactPoint> contacts;
  contacts.reserve(std::size_t(n));
  for (std::uint64_t k = 0; k < n; ++k) contacts.push_back(load_point(in, body_material_.size(), coeffs_.size()));
  auto soft_start = in.vec<std::uint64_t>("released pairs in overlap");
  const std::uint64_t released_read = in.u64("released pairs read");
  const bool overlaps_checked = in.boolean("initial overlaps checked flag");
  const std::uint64_t overlap_count = in.u64("initial overlap count");
  if (overlap_count > in.remaining() / 24) in.fail("initial overlap count larger than the data left");
  std::vector<InitialOverlap> overlaps;
  for (std::uint64_t k = 0; k < overlap_count; ++k) {
    InitialOverlap o;
    const std::uint64_t a = in.u64("initial overlap body a"), b = in.u64("initial overlap body b");
    if (a >= body_material_.size() || b >= body_material_.size()) in.fail("initial overlap names a body out of range");
    o.body_a = BodyId(a);
    o.body_b = BodyId(b);
    o.depth_m = in.f64("initial overlap depth");
    overlaps.push_back(o);
  }
  const double elastic = in.f64("contact elastic energy");
  const double viscous = in.f64("contact viscous energy");
  const double friction = in.f64("contact friction energy");
  const double viscous_half = in.f64("contact viscous half step");
  const double friction_half = in.f64("contact friction half step");
  ContactPressPeak press;
  press.ratio = in.f64("largest contact press");
  press.depth_m = in.f64("largest contact press");
  press.half_dimension_m = in.f64("largest contact press");
  press.time_s = in.f64("largest contact press");
  for (BodyId* body : {&press.body_a, &press.body_b, &press.measured}) {
    const auto id = std::int64_t(in.u64("largest contact press body"));
    if (id < -1 || id >= std::int64_t(body_material_.size())) in.fail("largest contact press names a body out of range");
    *body = BodyId(id);
  }
  if (press.ratio > 0.0 && (press.body_b == kNoBody || (press.measured != press.body_a && press.measured != press.body_b)))
    in.fail("largest contact press without its bodies");
  broad_.load_state(in);

  contacts_ = std::move(contacts);
  previous_.clear();
  soft_start_pairs_ = std::move(soft_start);
  released_read_ = std::size_t(released_read);
  initial_overlaps_checked_ = overlaps_checked;
  initial_overlaps_ = std::move(overlaps);
  elastic_J_ = elastic;
  viscous_J_ = viscous;
  friction_J_ = friction;
  viscous_half_J_ = viscous_half;
  friction_half_J_ = friction_half;
  press_peak_ = press;
  // Coefficient of each candidate pair: a function of the pairs (as after a rebuild).
  const auto& pairs = broad_.pairs();
  pair_coeff_.resize(pairs.size());
  for (std::size_t p = 0; p < pairs.size(); ++p)
    pair_coeff_[p] = coeff_index_for(body_material_[pairs[p].a], body_material_[pairs[p].b]);
}

}  // namespace fq
