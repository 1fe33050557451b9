// With no dissipation (e = 1, mu = 0) and no external input, the energy of a
// contact-only scene (kinetic + gravity potential + contact elastic) must not
// grow beyond the integrator's error; with dissipation, the ledger must
// balance (what is lost is booked as viscous or friction loss).
//
// Booking (contact_system.h): the contacts book as loss the work their
// forces do with the leapfrog velocity v_n minus the change of their elastic
// energy, so a conservative contact books as "viscous" (either sign) what
// the former booking left in the balance error: its springs' leapfrog
// mismatch and the jumps of stored energy when a manifold switches (see the
// limitation below). The growth of the stored energy is therefore what
// tells whether contacts create energy.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "dem_core/address_sanitizer.h"
#include "scene_helpers.h"

namespace {

using fq::Vec3;

struct MaxError : fq::StepObserver {
  double max_rel = 0.0;
  double max_abs = 0.0;
  double max_growth_rel = 0.0;  // (stored - initial stored) / scale
  double max_growth = 0.0;
  std::vector<double> lowest_centre_m;  // per body: the lowest z its centre reached (m)
  void on_sample(const fq::Simulation& sim) override {
    const auto& l = sim.ledger();
    const auto& z = sim.bodies().position_m;
    lowest_centre_m.resize(z.size(), std::numeric_limits<double>::infinity());
    for (std::size_t b = 0; b < z.size(); ++b) lowest_centre_m[b] = std::min(lowest_centre_m[b], z[b].z());
    max_abs = std::max(max_abs, std::fabs(l.balance_error_J()));
    max_rel = std::max(max_rel, std::fabs(l.balance_error_J()) / l.scale_J);
    max_growth = std::max(max_growth, l.stored_J() - l.initial_stored_J);
    max_growth_rel = std::max(max_growth_rel, (l.stored_J() - l.initial_stored_J) / l.scale_J);
  }
};

// Eight tumbling boxes (0.1 x 0.06 x 0.04 m, 500 kg/m^3) at random
// orientations and sideways speeds from generator `seed`, dropped from
// 0.1 + 0.12 i m: on one another (`apart` false: their centres within 0.03
// m of one vertical line) or side by side 1 m apart, where each meets only
// what lies under it: a frictionless surface pushes along z alone, so each
// box keeps its sideways speed (at most 0.3 m/s in x and in y) and drifts
// at most 0.3 m in the 1 s run, and two boxes (0.062 m half diagonal)
// 1 m apart never come within reach of each other.
fq::BodyStore tumbling_boxes(unsigned seed, bool apart = false) {
  fq::BodyStore store;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 8; ++i) {
    const Vec3 axis(u(rng), u(rng), u(rng));
    const fq::Quat q(Eigen::AngleAxisd(3.0 * u(rng), axis.normalized()));
    const Vec3 x = apart ? Vec3(1.0 * i, 0.0, 0.1 + 0.12 * i) : Vec3(0.03 * (i % 2), 0.03 * ((i / 2) % 2), 0.1 + 0.12 * i);
    const auto id = fq::test::add_box(store, Vec3(0.1, 0.06, 0.04), 500.0, x, q);
    store.velocity_mps[id] = Vec3(0.3 * u(rng), 0.3 * u(rng), 0.0);
    store.angular_momentum_Nms[id] = Vec3::Zero();
  }
  return store;
}

// k = 1e5 N/m on ~0.12 kg boxes: w^2 <= 24 k / m = 2e7, w dt <= 0.09 at
// dt = 2e-5 s. Leapfrog keeps a shadow energy within (w dt)^2 / 8 of the
// energy exchanged with a spring; the kink of the penalty force at first
// touch adds an error of the same order per impact (the force is
// continuous, its slope is not). Bound: the energy may exceed its initial
// value by at most (w dt)^2 / 4 = 0.2 % of the largest energy of the run,
// for the whole run (5e4 steps, ~100 impacts). A sign or bookkeeping error
// in the law (e.g. a damping of the wrong sign or a history that injects
// energy) produces growth of the order of the impact energy itself.
double omega_dt(double k_Npm, double mass_kg, double dt_s) { return std::sqrt(24.0 * k_Npm / mass_kg) * dt_s; }
constexpr double kStep_s = 2e-5;
// The bound above for the tumbling boxes of `sim` (k = 1e5 N/m, dt = kStep_s).
double integrator_bound(const fq::Simulation& sim) {
  const double w_dt = omega_dt(1e5, sim.bodies().mass_kg[0], kStep_s);
  return w_dt * w_dt / 4.0;
}

// Seeds 1..kSeeds of each scene. Under AddressSanitizer (CI's second suite,
// which looks for memory errors, not for physics: the plain suite runs all
// eight) one seed: the eight took 146 s there, 2.2 s in the plain build.
constexpr unsigned kSeeds = FQ_ADDRESS_SANITIZER ? 1 : 8;

// tumbling_boxes(seed) falling on one another and on the ground, one
// contact material (k_n = 1e5 N/m, restitution e, friction mu), for 1 s at
// dt = 2e-5 s, with `obs` sampling every step.
fq::test::ContactScene run_stacked_boxes(unsigned seed, double restitution, double mu, fq::StepObserver& obs) {
  fq::SimulationSettings s;
  s.dt_s = kStep_s;
  s.duration_s = 1.0;
  auto scene = fq::test::make_scene(tumbling_boxes(seed), s, [&](fq::ContactSystem& c) {
    const auto p = fq::test::params(1e5, restitution, mu);
    c.set_ground(0.0, p);
    c.set_pair_params(0, 0, p);
  });
  scene.sim->add_observer(&obs, 1);
  scene.sim->run();
  return scene;
}

TEST(ContactEnergy, ConservativeContactsAtCornersDoNotCreateEnergy) {
  // With no dissipation (e = 1, mu = 0) a contact whose points are corners
  // of a box pressing on a face (the ground, or a fixed slab's top face,
  // which the contacts take as the reference face) is a spring between
  // material points along a fixed normal: a potential, so the energy is
  // conserved up to the integrator. Eight seeds, each box meeting only the
  // surface under it; both surfaces, since the slab's corners are found by
  // the box-box narrow phase (clipping against the slab's side planes,
  // which lie far away) and the ground's by the corner test.
  for (const bool on_slab : {false, true}) {
    for (unsigned seed = 1; seed <= kSeeds; ++seed) {
      SCOPED_TRACE(std::string(on_slab ? "fixed slab" : "ground") + ", seed " + std::to_string(seed));
      fq::SimulationSettings s;
      s.dt_s = kStep_s;
      s.duration_s = 1.0;
      fq::BodyStore boxes = tumbling_boxes(seed, true);
      // 8 x 1.5 m, top face at z = 0, under all eight boxes wherever they
      // drift (x = -0.4 to 7.4 m, |y| < 0.4 m).
      if (on_slab) fq::test::add_box(boxes, Vec3(8.0, 1.5, 0.1), 500.0, Vec3(3.5, 0.0, -0.05), fq::Quat::Identity(), true);
      auto scene = fq::test::make_scene(std::move(boxes), s, [&](fq::ContactSystem& c) {
        const auto p = fq::test::params(1e5, 1.0, 0.0);
        if (on_slab)
          c.set_pair_params(0, 0, p);
        else
          c.set_ground(0.0, p);
      });
      MaxError obs;
      scene.sim->add_observer(&obs, 1);
      scene.sim->run();
      const double bound = integrator_bound(*scene.sim);
      // Every box met the surface: its centre came within its half diagonal
      // (0.0616 m) of it.
      for (int b = 0; b < 8; ++b) EXPECT_LT(obs.lowest_centre_m[b], 0.0617) << "box " << b;
      EXPECT_LT(obs.max_growth_rel, bound) << "max growth " << obs.max_growth << " J";
      EXPECT_EQ(scene.sim->ledger().dissipated_plastic_J, 0.0);
      EXPECT_LT(obs.max_rel, bound) << "max error " << obs.max_abs << " J";
    }
  }
}

TEST(ContactEnergy, TumblingBoxesOnOneAnotherBookWhatTheirContactsCreate) {
  // The same boxes falling on one another. A box-box contact whose
  // manifold switches between an edge contact (one point, k_n) and a face
  // contact (shares summing to 4 k_n) changes its stiffness at once, and
  // its stored energy jumps (contacts/README.md, "Known limitations"); the
  // stored energy of this scene is therefore not conserved: at the end of
  // the 1 s it was between -1.1 % and +16.4 % of the run's largest energy
  // over seeds 1-8 when this test was written (stop 42, with the face
  // points' leans; between -6.1 % and +10.4 % before them, when clipped
  // crossings also did work no energy paid for, and the scene is chaotic,
  // so each seed's figure moved). An earlier form of this test ran seed 7
  // alone and held its growth to the integrator's bound, which seed 7 alone
  // of ten did. What holds for every seed is the books: the contacts book
  // as viscous loss (either sign) the work their forces did less the
  // change of their elastic energy, so the balance error stays within the
  // integrator's bound, and with nothing dissipative in the scene the
  // "viscous" book is minus the energy the contacts created.
  for (unsigned seed = 1; seed <= kSeeds; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    MaxError obs;
    const auto scene = run_stacked_boxes(seed, 1.0, 0.0, obs);
    const auto& l = scene.sim->ledger();
    const double bound = integrator_bound(*scene.sim);
    EXPECT_GT(scene.contacts->broad_phase_rebuilds(), 1);
    EXPECT_EQ(l.dissipated_plastic_J, 0.0);
    EXPECT_EQ(l.dissipated_friction_J, 0.0);
    EXPECT_LT(obs.max_rel, bound) << "max error " << obs.max_abs << " J";
    EXPECT_NEAR(l.dissipated_viscous_J, -(l.stored_J() - l.initial_stored_J), bound * l.scale_J);
    std::printf("seed %u: stored energy %+.4f of the run's largest energy\n", seed,
                (l.stored_J() - l.initial_stored_J) / l.scale_J);
  }
}

TEST(ContactEnergy, ABlockTippingOverASmallerFixedBlocksEdgeCreatesNoEnergy) {
  // A 0.1 x 0.08 x 0.05 m block (450 kg/m^3, 0.18 kg) dropped flat from
  // 0.075 m onto a fixed 0.06 x 0.06 x 0.05 m block, off centre, with e = 1
  // and mu = 0 (k_n = 1e6 N/m, ground alike): it bounces, rocks and tips
  // over the fixed block's edges. While it tips, the fixed block's top edge
  // presses into its bottom face: the
  // contact's points are crossings of the block's tilted edges with the
  // fixed face's side planes, and corners of that face. Their forces now
  // follow their depths' gradients (ContactPointGeometry::lean), so the
  // energy may not rise above its start by more than the integrator's
  // (w dt)^2 / 4 of the drop's energy, w^2 = 24 k / m as above (4.4e-4 J
  // at dt = 1e-5 s, 1.1e-4 J at 5e-6 s). Pushed along the fixed face's
  // normal alone (before stop 42) the first offset created 1.7e-3 J at
  // 1e-5 s and 8.1e-2 J, 61 % of the drop's 0.132 J, at 5e-6 s, in 1 ms
  // (an energy probe). The energy may still fall: an edge contact that
  // becomes a face contact changes its stiffness at once (contacts/README.md),
  // which lost 7e-3 J at 1e-5 s and 3e-3 J at 5e-6 s in the first offset.
  // Under AddressSanitizer the first offset at 1e-5 s only.
  const double dts[2] = {1e-5, 5e-6};
  const Vec3 offsets[3] = {Vec3(0.01, 0.005, 0.0), Vec3(0.015, -0.01, 0.0), Vec3(-0.012, 0.008, 0.0)};
  for (int i = 0; i < (FQ_ADDRESS_SANITIZER ? 1 : 2); ++i) {
    for (int o = 0; o < (FQ_ADDRESS_SANITIZER ? 1 : 3); ++o) {
      SCOPED_TRACE("dt " + std::to_string(dts[i]) + " s, offset " + std::to_string(o));
      fq::BodyStore store;
      fq::test::add_box(store, Vec3(0.06, 0.06, 0.05), 450.0, Vec3(0.0, 0.0, 0.025), fq::Quat::Identity(), true);
      fq::test::add_box(store, Vec3(0.1, 0.08, 0.05), 450.0, offsets[o] + Vec3(0.0, 0.0, 0.15));
      fq::SimulationSettings s;
      s.dt_s = dts[i];
      s.duration_s = 1.0;
      auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
        const auto p = fq::test::params(1e6, 1.0, 0.0);
        c.set_ground(0.0, p);
        c.set_pair_params(0, 0, p);
      });
      MaxError obs;
      scene.sim->add_observer(&obs, 1);
      scene.sim->run();
      const double mass_kg = scene.sim->bodies().mass_kg[1];
      const double drop_J = mass_kg * 9.80665 * 0.075;
      const double w_dt = omega_dt(1e6, mass_kg, dts[i]);
      EXPECT_LT(obs.max_growth, w_dt * w_dt / 4.0 * drop_J);
      EXPECT_LT(obs.max_rel, 1e-6);  // the books close
    }
  }
}

TEST(ContactEnergy, DissipativeContactsBalanceTheLedger) {
  // The same scenes with e = 0.5, mu = 0.4: energy now leaves through
  // dashpots and friction. The books must still close: the losses are
  // booked as the work the contact forces do with v_n, the work the
  // ledger's kinetic energy sees (contact_system.h), so no first-order term
  // is left (the former booking from v(n-1/2) left zeta w dt of the
  // dissipated energy) and the balance error stays within the conservative
  // run's integrator bound.
  const double zeta = fq::damping_ratio_from_restitution(0.5);
  for (unsigned seed = 1; seed <= kSeeds; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    MaxError obs;
    const auto scene = run_stacked_boxes(seed, 0.5, 0.4, obs);
    const auto& l = scene.sim->ledger();
    EXPECT_GT(l.dissipated_viscous_J, 0.0);
    EXPECT_GT(l.dissipated_friction_J, 0.0);
    const double w_dt = omega_dt(1e5, scene.sim->bodies().mass_kg[0], kStep_s);
    EXPECT_LT(obs.max_rel, w_dt * w_dt / 4.0)
        << "max error " << obs.max_abs << " J; stored " << l.stored_J() << " dissipated " << l.dissipated_J()
        << " (former bound's first-order part zeta w dt D = " << zeta * w_dt * l.dissipated_J() << " J)";
  }
}

// A cube landing on one corner, tilted (30 deg about x, then 20 deg about
// y) so that the impact is eccentric and its corner slides while the
// dashpots act: no gravity, 1.4 m/s straight down, k_n = 1e6 N/m, e = 0.5,
// mu = 0.4 (a probe's scene). Coulomb sliding only dissipates, so no step
// may take energy out of the friction book (the contacts' whole-step
// losses; the ledger's own figure also takes back half of the current
// step's work, contact_system.h). With the spring reset to the capped
// force at the onset of sliding (until 2026-11-26), the book fell by
// 0.0158 J, 3.6 % of the 0.441 J brought in: the spring gained c_t |v_t|
// of force that no motion had worked in (linear_contact_law.h).
struct FrictionSteps : fq::StepObserver {
  const fq::ContactSystem* contacts = nullptr;
  double previous_J = 0.0;
  double most_negative_step_J = 0.0;
  void on_sample(const fq::Simulation&) override {
    const double now = contacts->friction_loss_whole_steps_J();
    most_negative_step_J = std::min(most_negative_step_J, now - previous_J);
    previous_J = now;
  }
};

TEST(ContactEnergy, FrictionNeverCreatesEnergyInAnEccentricCornerImpact) {
  const double size = 0.1;
  const fq::Quat q = fq::Quat(Eigen::AngleAxisd(20.0 * M_PI / 180.0, Vec3::UnitY())) *
                     fq::Quat(Eigen::AngleAxisd(30.0 * M_PI / 180.0, Vec3::UnitX()));
  // The lowest corner 0.1 mm above the ground.
  double lowest = 0.0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner(k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 0.5 : -0.5);
    lowest = std::min(lowest, (q * (size * corner)).z());
  }
  fq::BodyStore store;
  fq::test::add_box(store, Vec3::Constant(size), 450.0, Vec3(0.0, 0.0, 1e-4 - lowest), q);
  store.velocity_mps[0] = Vec3(0.0, 0.0, -1.4);
  fq::SimulationSettings s;
  s.dt_s = 1e-5;
  s.duration_s = 0.02;
  s.gravity_mps2 = Vec3::Zero();
  auto scene = fq::test::make_scene(std::move(store), s, [](fq::ContactSystem& c) {
    c.set_ground(0.0, fq::test::params(1e6, 0.5, 0.4));
  });
  FrictionSteps obs;
  obs.contacts = scene.contacts;
  scene.sim->add_observer(&obs, 1);
  scene.sim->run();
  const double brought_in_J = 0.5 * scene.sim->bodies().mass_kg[0] * 1.4 * 1.4;
  ASSERT_GT(scene.contacts->friction_loss_whole_steps_J(), 1e-3 * brought_in_J) << "the corner must slide";
  // Round-off of sums of ~1e-3 J terms: 1e-12 of the energy in play.
  EXPECT_GE(obs.most_negative_step_J, -1e-12 * brought_in_J) << "a step's friction created energy";
}

}  // namespace
