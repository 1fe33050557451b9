// Determinism (issue 7): the same case gives bitwise-identical final states
// with 1 and 2 OpenMP threads and from run to run. The scene is large enough
// (240 blocks in contact with the ground and each other) that the contact
// system's parallel loops (threshold 128 items) really run on two threads.
#include <gtest/gtest.h>

#include <string>

#include "io/case_file.h"
#include "io/case_runner.h"
#include "io_test_util.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace fq {
namespace {

std::string pile_case() {
  std::string s =
      "framequake_case: 1\n"
      "time: {dt_s: 5.0e-5, duration_s: 0.25}\n"
      "materials: [{name: wood, density_kg_per_m3: 450}]\n"
      "ground: {level_m: 0.0}\n"
      "contact:\n"
      "  ground: {normal_stiffness_N_per_m: 1.0e5, restitution: 0.5, friction_coefficient: 0.4}\n"
      "  default: {normal_stiffness_N_per_m: 1.0e5, restitution: 0.5, friction_coefficient: 0.4}\n"
      "blocks:\n";
  // Three layers of 8 x 10 blocks of 50 mm, slightly rotated, spaced by more
  // than a block's diagonal (87 mm) so none overlaps another or the ground
  // at the start; they fall and pile up.
  int id = 0;
  for (int layer = 0; layer < 3; ++layer)
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 10; ++j, ++id)
        s += "  - {id: b" + std::to_string(id) + ", size_m: [0.05, 0.05, 0.05], center_m: [" +
             std::to_string(0.09 * i + 0.02 * layer) + ", " + std::to_string(0.09 * j) + ", " +
             std::to_string(0.045 + 0.09 * layer) + "], rotation_deg: [" + std::to_string(3 * (id % 5)) +
             ", 0, " + std::to_string(7 * (id % 3)) + "], material: wood}\n";
  return s;
}

std::uint64_t run_with_threads(const CaseDef& def, int threads) {
#if defined(_OPENMP)
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  Scene scene = build_scene(def);
  const RunResult r = scene.simulation->run();
  EXPECT_EQ(r.status, RunStatus::Completed);
  EXPECT_GT(scene.contacts->contact_count(), 128u) << "the scene must be large enough to run in parallel";
  return scene.simulation->state_hash();
}

TEST(Determinism, SameStateWithOneAndTwoThreadsAndFromRunToRun) {
  test::TempDir dir;
  const CaseDef def = load_case_file(dir.write("pile.yaml", pile_case()));
  const std::uint64_t one = run_with_threads(def, 1);
  const std::uint64_t two = run_with_threads(def, 2);
  const std::uint64_t again = run_with_threads(def, 2);
  EXPECT_EQ(one, two);
  EXPECT_EQ(two, again);
#if defined(_OPENMP)
  omp_set_num_threads(omp_get_num_procs());
#endif
}

TEST(Determinism, StateHashChangesWithTheState) {
  // A hash that ignored the state would make the test above pass vacuously.
  test::TempDir dir;
  CaseDef def = load_case_file(dir.write("pile.yaml", pile_case()));
  Scene a = build_scene(def);
  const std::uint64_t before = a.simulation->state_hash();
  a.simulation->step();
  EXPECT_NE(before, a.simulation->state_hash());
  def.blocks[0].center_m.z() += 1e-9;
  EXPECT_NE(before, build_scene(def).simulation->state_hash());
}

}  // namespace
}  // namespace fq
