// ContactSystem keeps a point's dashpot coefficients from one step to the
// next while the point keeps its share of the stiffness and its mass
// (contact_system.h, ContactPoint::dashpots_known). Whatever it keeps, every
// point must carry at every step the closed form of linear_contact_law.h,
// c = 2 zeta sqrt(k m), for the share and mass it has at that step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "contacts/linear_contact_law.h"
#include "scene_helpers.h"

namespace {

using fq::Vec3;

TEST(ContactDashpots, EveryPointCarriesTheClosedFormForItsShareAndMassAtEveryStep) {
  // A tilted box dropped across the edge of a fixed slab lands on a corner
  // and rocks onto a face that overhangs the slab's side: clipped polygons
  // whose point weights change from step to step while the box turns and
  // their features (and so their history) are kept, and points whose
  // weights stay.
  fq::BodyStore store;
  fq::test::add_box(store, Vec3(0.3, 0.3, 0.1), 500.0, Vec3(0.0, 0.0, 0.05), fq::Quat::Identity(), true);
  const fq::Quat tilt = fq::Quat(Eigen::AngleAxisd(0.35, Vec3::UnitX())) * fq::Quat(Eigen::AngleAxisd(0.2, Vec3::UnitY()));
  fq::test::add_box(store, Vec3(0.1, 0.06, 0.04), 500.0, Vec3(0.13, 0.01, 0.16), tilt);
  fq::SimulationSettings settings;
  settings.dt_s = 1e-4;
  const fq::ContactParams params = fq::test::params(1e5, 0.5, 0.4);
  auto scene = fq::test::make_scene(std::move(store), settings, [&](fq::ContactSystem& c) {
    c.set_ground(0.0, params);
    c.set_pair_params(0, 0, params);
  });
  const fq::ContactCoefficients coeff = fq::make_contact_coefficients(params, "test");

  std::map<std::pair<std::uint64_t, std::uint32_t>, double> share_before;  // (pair, feature) -> share
  int points = 0, kept_share = 0, changed_share = 0;
  for (int step = 0; step < 4000; ++step) {
    scene.sim->step();
    std::map<std::pair<std::uint64_t, std::uint32_t>, double> share_now;
    for (const fq::ContactPoint& p : scene.contacts->contacts()) {
      const double kn = p.stiffness_scale * coeff.normal_stiffness_N_per_m;
      const double kt = p.stiffness_scale * coeff.tangential_stiffness_N_per_m;
      const double m = p.effective_mass_kg;
      ASSERT_TRUE(p.dashpots_known);
      ASSERT_EQ(p.normal_dashpot_Nspm, 2.0 * coeff.damping_ratio * std::sqrt(kn * m)) << "step " << step;
      ASSERT_EQ(p.tangential_dashpot_Nspm, 2.0 * coeff.damping_ratio * std::sqrt(kt * m)) << "step " << step;
      const auto key = std::make_pair(p.pair_key, p.feature);
      share_now[key] = p.stiffness_scale;
      if (const auto it = share_before.find(key); it != share_before.end())
        (it->second == p.stiffness_scale ? kept_share : changed_share) += 1;
      ++points;
    }
    share_before = std::move(share_now);
  }
  // The scene exercised both cases: points carried with the same share and
  // points carried with a new one.
  std::printf("points %d kept %d changed %d\n", points, kept_share, changed_share);
  EXPECT_GT(points, 1000);
  EXPECT_GT(kept_share, 100);
  EXPECT_GT(changed_share, 100);
}

}  // namespace
