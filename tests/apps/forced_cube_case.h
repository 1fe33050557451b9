// A case for the tests of forced runs (tests/apps): a 0.1 m spruce cube
// resting on the ground at dt = 1e-3 s, 4.2 times the stable estimate that
// `framequake info` gives for it (2.37e-4 s, from its stiffest contact
// mode), so `run` refuses it without --force and warns with it.
#pragma once

namespace fq_test {

inline constexpr const char* kForcedCubeCase =
    "framequake_case: 1\n"
    "name: cube\n"
    "time: {dt_s: 1.0e-3, duration_s: 0.05}\n"
    "materials: [{name: spruce, density_kg_per_m3: 450}]\n"
    "ground: {level_m: 0.0}\n"
    "blocks: [{id: cube, size_m: [0.1, 0.1, 0.1], center_m: [0, 0, 0.05], material: spruce}]\n"
    "contact: {ground: {normal_stiffness_N_per_m: 1.0e6, restitution: 0.5, friction_coefficient: 0.4}}\n";

}  // namespace fq_test
