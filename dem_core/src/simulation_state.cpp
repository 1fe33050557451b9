// Checkpoint state of the step loop (simulation.h "Checkpoints"). Kept apart
// from simulation.cpp so the scheme's code and the list of what it carries
// between steps can change independently; a member added to Simulation that
// survives from one step to the next must be added here too (the round-trip
// tests in tests/io/test_checkpoint.cpp fail otherwise).
#include <algorithm>
#include <string>

#include "dem_core/simulation.h"
#include "dem_core/state_io.h"

namespace fq {

namespace {

// Bumped whenever the layout written below changes.
constexpr std::uint32_t kSimulationStateVersion = 1;

// FNV-1a over the bits of what defines the bodies (not their motion): a
// checkpoint is refused on a scene whose bodies differ.
std::uint64_t body_definition_hash(const BodyStore& b) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* p, std::size_t n) {
    const auto* bytes = static_cast<const unsigned char*>(p);
    for (std::size_t k = 0; k < n; ++k) {
      h ^= bytes[k];
      h *= 1099511628211ull;
    }
  };
  for (std::size_t i = 0; i < b.size(); ++i) {
    mix(&b.mass_kg[i], sizeof(double));
    mix(b.principal_inertia_kgm2[i].data(), 3 * sizeof(double));
    mix(b.half_extents_m[i].data(), 3 * sizeof(double));
    mix(&b.is_fixed[i], 1);
  }
  return h;
}

}  // namespace

void ForceProvider::save_state(StateWriter& /*out*/) const {
  throw std::logic_error(std::string("force provider '") + name() + "' does not support checkpoints");
}

void ForceProvider::load_state(StateReader& /*in*/) {
  throw std::logic_error(std::string("force provider '") + name() + "' does not support checkpoints");
}

void BondedPairs::save_state(StateWriter& out) const {
  out.section("bonded_pairs");
  // Sorted by key: the file does not depend on the hash map's order.
  std::vector<std::pair<std::uint64_t, int>> held(count_.begin(), count_.end());
  std::sort(held.begin(), held.end());
  out.u64(held.size());
  for (const auto& [key, n] : held) {
    out.u64(key);
    out.i64(n);
  }
  out.u64(released_.size());
  for (const auto& [a, b] : released_) {
    out.pod(a);
    out.pod(b);
  }
}

void BondedPairs::load_state(StateReader& in) {
  in.section("bonded_pairs");
  const std::uint64_t held = in.u64("bonded pair count");
  if (held > in.remaining() / 16) in.fail("bonded pair count larger than the data left");
  std::unordered_map<std::uint64_t, int> count;
  for (std::uint64_t k = 0; k < held; ++k) {
    const std::uint64_t key = in.u64("bonded pair");
    const std::int64_t n = in.i64("bonded pair joint count");
    if (n <= 0 || n > 1000000) in.fail("bonded pair with an impossible joint count");
    count[key] = int(n);
  }
  const std::uint64_t released = in.u64("released pair count");
  if (released > in.remaining() / (2 * sizeof(BodyId))) in.fail("released pair count larger than the data left");
  std::vector<std::pair<BodyId, BodyId>> log(static_cast<std::size_t>(released));
  for (auto& [a, b] : log) {
    a = in.pod<BodyId>("released pair");
    b = in.pod<BodyId>("released pair");
  }
  count_ = std::move(count);
  released_ = std::move(log);
}

void Simulation::save_state(StateWriter& out) const {
  out.section("simulation");
  out.u32(kSimulationStateVersion);
  out.u64(bodies_.size());
  out.u64(body_definition_hash(bodies_));
  out.f64(settings_.dt_s);
  out.u64(providers_.size());
  for (const auto& p : providers_) out.str(p->name());

  out.i64(step_);
  out.boolean(initialized_);
  out.boolean(forces_current_);
  out.vec3(ground_acceleration_);
  out.f64(work_gravity_through_prev_J_);
  out.f64(work_ground_through_prev_J_);
  out.f64(energy_floor_J_);
  out.pod(ledger_);

  out.section("bodies");
  out.vec3s(bodies_.position_m);
  out.quats(bodies_.orientation);
  out.mat3s(bodies_.rotation);
  out.vec3s(bodies_.velocity_mps);
  out.vec3s(bodies_.angular_momentum_Nms);
  out.vec3s(bodies_.angular_velocity_radps);
  out.vec3s(bodies_.force_N);
  out.vec3s(bodies_.torque_Nm);

  events_.save_state(out);
  bonded_pairs_.save_state(out);
  for (const auto& p : providers_) {
    out.section(p->name());
    p->save_state(out);
  }
  out.section("simulation_end");
}

void Simulation::load_state(StateReader& in) {
  // Lets every provider build what it builds lazily (prepare, first force
  // evaluation), all of which the saved state then overwrites.
  initialize();
  in.section("simulation");
  const std::uint32_t version = in.u32("simulation state version");
  if (version != kSimulationStateVersion)
    in.fail("simulation state version " + std::to_string(version) + ", this build reads " +
            std::to_string(kSimulationStateVersion));
  const std::size_t n = bodies_.size();
  const std::uint64_t saved_n = in.u64("body count");
  if (saved_n != n)
    in.fail("the state has " + std::to_string(saved_n) + " bodies, this scene " + std::to_string(n));
  if (in.u64("body definition hash") != body_definition_hash(bodies_))
    in.fail("the bodies' masses or sizes differ from those of the saved scene");
  const double dt = in.f64("time step");
  if (dt != settings_.dt_s)
    in.fail("the state was saved with dt_s = " + std::to_string(dt) + " s, this scene has " +
            std::to_string(settings_.dt_s) + " s");
  const std::uint64_t saved_providers = in.u64("provider count");
  if (saved_providers != providers_.size())
    in.fail("the state has " + std::to_string(saved_providers) + " force providers, this scene " +
            std::to_string(providers_.size()));
  for (const auto& p : providers_) {
    const std::string name = in.str("provider name");
    if (name != p->name()) in.fail("provider '" + name + "' in the state where this scene has '" + p->name() + "'");
  }

  const std::int64_t step = in.i64("step");
  if (step < 0) in.fail("negative step counter");
  const bool initialized = in.boolean("initialized flag");
  const bool forces_current = in.boolean("forces flag");
  if (!initialized) in.fail("the state was saved before the simulation was initialized");
  const Vec3 ground_acceleration = in.vec3("ground acceleration");
  const double work_gravity = in.f64("gravity work");
  const double work_ground = in.f64("ground-motion work");
  const double energy_floor = in.f64("energy floor");
  const EnergyLedger ledger = in.pod<EnergyLedger>("energy ledger");

  in.section("bodies");
  BodyStore& b = bodies_;
  b.position_m = in.vec3s("positions", n);
  b.orientation = in.quats("orientations", n);
  b.rotation = in.mat3s("rotations", n);
  b.velocity_mps = in.vec3s("velocities", n);
  b.angular_momentum_Nms = in.vec3s("angular momenta", n);
  b.angular_velocity_radps = in.vec3s("angular velocities", n);
  b.force_N = in.vec3s("forces", n);
  b.torque_Nm = in.vec3s("torques", n);

  events_.load_state(in);
  bonded_pairs_.load_state(in);
  for (const auto& p : providers_) {
    in.section(p->name());
    p->load_state(in);
  }
  in.section("simulation_end");

  step_ = step;
  forces_current_ = forces_current;
  ground_acceleration_ = ground_acceleration;
  work_gravity_through_prev_J_ = work_gravity;
  work_ground_through_prev_J_ = work_ground;
  energy_floor_J_ = energy_floor;
  ledger_ = ledger;
}

}  // namespace fq
