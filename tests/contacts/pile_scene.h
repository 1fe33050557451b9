// A pile of boxes falling onto the ground: the scene of the determinism
// test and of validation/bench_contact_pile.cpp. Boxes sit on a jittered
// lattice with random orientations, a little apart, thrown downwards, so they fall, collide
// with one another and come to rest in a heap.
#pragma once

#include <cmath>
#include <random>

#include "dem_core/body_store.h"

namespace fq::test {

inline BodyStore make_box_pile(int count, unsigned seed = 1) {
  BodyStore store;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int per_side = std::max(1, int(std::ceil(std::sqrt(double(count) / 4.0))));
  // m; boxes are 0.1 x 0.06 x 0.04 m, half-diagonal 0.062 m, so no two
  // overlap at the start whatever their orientation.
  const double pitch = 0.13;
  for (int i = 0; i < count; ++i) {
    const int ix = i % per_side, iy = (i / per_side) % per_side, iz = i / (per_side * per_side);
    BoxBodyDef def;
    def.name = "box" + std::to_string(i);
    def.kind = MemberKind::Block;
    def.size_m = Vec3(0.1, 0.06, 0.04);
    def.density_kg_per_m3 = 500.0;
    def.position_m = Vec3(pitch * ix + 0.02 * u(rng), pitch * iy + 0.02 * u(rng), 0.065 + pitch * iz);
    def.orientation = Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    // Thrown down at 1.5-2.5 m/s, so the lower layers land within ~200
    // steps of 1e-4 s and the layers then catch up with one another.
    def.velocity_mps = Vec3(0.2 * u(rng), 0.2 * u(rng), -2.0 + 0.5 * u(rng));
    store.add_box(def);
  }
  return store;
}

// Columns of boxes standing on one another (touching, turned by up to
// 3 mrad, so corners dip ~0.15 mm into their neighbours), pushed sideways
// into the next columns: nearly every box is in contact from the first
// steps, which makes a short run exercise the whole contact pipeline.
inline BodyStore make_pressed_columns(int count, unsigned seed = 1) {
  BodyStore store;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int kHigh = 4;
  const int columns = (count + kHigh - 1) / kHigh;
  const int per_row = std::max(1, int(std::ceil(std::sqrt(double(columns)))));
  for (int i = 0; i < count; ++i) {
    const int col = i / kHigh, level = i % kHigh;
    BoxBodyDef def;
    def.name = "box" + std::to_string(i);
    def.kind = MemberKind::Block;
    def.size_m = Vec3(0.1, 0.06, 0.04);
    def.density_kg_per_m3 = 500.0;
    def.position_m = Vec3(0.101 * (col % per_row) + 0.002 * u(rng), 0.061 * (col / per_row) + 0.002 * u(rng),
                          0.02 + 0.04 * level);
    def.orientation = Quat(Eigen::AngleAxisd(0.003 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    def.velocity_mps = Vec3(0.1 * u(rng), 0.1 * u(rng), 0.0);
    store.add_box(def);
  }
  return store;
}

}  // namespace fq::test
