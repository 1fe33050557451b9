// Small helpers shared by the contacts tests: build box bodies and run a
// simulation with one ContactSystem, keeping a pointer to it.
#pragma once

#include <memory>
#include <string>

#include "contacts/contact_system.h"
#include "dem_core/simulation.h"

namespace fq::test {

inline BodyId add_box(BodyStore& store, const Vec3& size_m, double density_kg_per_m3, const Vec3& position_m,
                      const Quat& orientation = Quat::Identity(), bool fixed = false,
                      MemberKind kind = MemberKind::Block) {
  BoxBodyDef def;
  def.name = "box" + std::to_string(store.size());
  def.kind = kind;
  def.size_m = size_m;
  def.density_kg_per_m3 = density_kg_per_m3;
  def.position_m = position_m;
  def.orientation = orientation;
  def.fixed = fixed;
  return store.add_box(def);
}

inline ContactParams params(double kn_N_per_m, double restitution, double mu, double kt_N_per_m = 0.0) {
  ContactParams p;
  p.normal_stiffness_N_per_m = kn_N_per_m;
  p.restitution = restitution;
  p.friction_coefficient = mu;
  p.tangential_stiffness_N_per_m = kt_N_per_m;
  return p;
}

// A simulation owning one ContactSystem whose set-up is done by `configure`.
struct ContactScene {
  std::unique_ptr<Simulation> sim;
  ContactSystem* contacts = nullptr;
};

template <class Configure>
ContactScene make_scene(BodyStore store, const SimulationSettings& settings, Configure configure,
                        GroundMotion ground_motion = {}, ContactSystemSettings contact_settings = {}) {
  ContactScene scene;
  scene.sim = std::make_unique<Simulation>(std::move(store), settings, std::move(ground_motion));
  auto system = std::make_unique<ContactSystem>(&scene.sim->bonded_pairs(), contact_settings);
  configure(*system);
  scene.contacts = system.get();
  scene.sim->add_force_provider(std::move(system));
  return scene;
}

// The boxes of `store` without gravity, dt = 1e-5 s, one contact material
// (k_n = 1e5 N/m, e = 0.5, mu = 0.4): two boxes meeting as the test sets
// them, with nothing else acting (test_bonded_release, test_initial_overlap).
inline ContactScene weightless_scene(BodyStore store) {
  SimulationSettings s;
  s.dt_s = 1e-5;
  s.gravity_mps2 = Vec3::Zero();
  return make_scene(std::move(store), s, [](ContactSystem& c) { c.set_pair_params(0, 0, params(1e5, 0.5, 0.4)); });
}

}  // namespace fq::test
