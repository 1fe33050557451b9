#include <gtest/gtest.h>

#include "dem_core/simulation.h"

TEST(Smoke, BuildsABox) {
  fq::BodyStore store;
  fq::BoxBodyDef def;
  def.size_m = fq::Vec3(1, 2, 3);
  def.density_kg_per_m3 = 10;
  store.add_box(def);
  EXPECT_DOUBLE_EQ(store.mass_kg[0], 60.0);
}
