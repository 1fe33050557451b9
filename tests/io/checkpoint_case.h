// A small case for the checkpoint tests (tests/io/test_checkpoint.cpp,
// tests/apps/test_checkpoint_cli.cpp): a column fixed to the ground by an
// unbreakable joint carries a horizontal arm on a weak joint (trilinear
// normal springs, CUREE hysteretic shear springs). Shaken by a 5 Hz sine,
// the arm's joint yields, cycles and breaks at its first spring deletion; the
// arm then falls, touches the column (a pair released from its joint,
// starting from its overlap) and lands on the ground (contacts with
// friction). Every kind of state a checkpoint must carry is exercised:
// plastic offsets, hysteretic histories, deleted springs, a broken joint,
// released pairs, contact histories and the broad phase.
#pragma once

#include <cmath>
#include <string>

namespace fq::test {

// Ground motion "time acceleration" (m/s^2): 3 sin(2 pi 5 t), sampled every
// 1 ms over `end_s`.
inline std::string sine_record(double end_s) {
  std::string s = "# 5 Hz sine, 3 m/s^2\n";
  const int n = static_cast<int>(std::lround(end_s / 0.001));
  for (int k = 0; k <= n; ++k) {
    const double t = 0.001 * k;
    s += std::to_string(t) + " " + std::to_string(3.0 * std::sin(2.0 * M_PI * 5.0 * t)) + "\n";
  }
  return s;
}

// The case text; the record file `record_file` lies next to the case file.
inline std::string arm_case(double duration_s, const std::string& record_file) {
  return "framequake_case: 1\n"
         "name: checkpoint_arm\n"
         "time: {dt_s: 1.0e-5, duration_s: " + std::to_string(duration_s) + "}\n"
         "materials: [{name: wood, density_kg_per_m3: 450}]\n"
         "sections:\n"
         "  - {name: col, width_m: 0.02, depth_m: 0.02}\n"
         "  - {name: arm, width_m: 0.01, depth_m: 0.01}\n"
         "nodes:\n"
         "  - {id: base, xyz_m: [0, 0, 0]}\n"
         "  - {id: top, xyz_m: [0, 0, 0.2]}\n"
         "  - {id: tip, xyz_m: [0.2, 0, 0.2]}\n"
         "members:\n"
         "  - {id: column, kind: column, nodes: [base, top], section: col, material: wood}\n"
         "  - {id: arm, kind: beam, nodes: [top, tip], section: arm, material: wood}\n"
         "joint_types:\n"
         "  - name: fixed\n"
         "    layout: four_corner\n"
         "    normal: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
         "    shear: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.05}\n"
         "    fracture: {criterion: never}\n"
         "  - name: weak\n"
         "    layout: four_corner\n"
         "    normal:\n"
         "      law: trilinear\n"
         "      reference_length_m: 0.01\n"
         "      yield_strain_tension: 0.01\n"
         "      yield_force_tension_N: 0.2\n"
         "      ultimate_strain_tension: 0.05\n"
         "      ultimate_force_tension_N: 0.3\n"
         "      yield_strain_compression: 0.01\n"
         "      yield_force_compression_N: 0.2\n"
         "      ultimate_strain_compression: 0.05\n"
         "      ultimate_force_compression_N: 0.3\n"
         "      damping_ratio: 0.05\n"
         "    shear: {law: curee, K0_N_per_m: 2000, F0_N: 0.5, F1_N: 0.05, r1: 0.05, r2: -0.1, r3: 1.2,\n"
         "            r4: 0.02, delta_u_m: 0.002, alpha: 0.5, beta: 1.1, damping_ratio: 0.05}\n"
         "    fracture: {criterion: any_spring_deleted}\n"
         "joints: {default_type: weak, support_type: fixed}\n"
         "supports: [{node: base}]\n"
         "ground: {level_m: 0.0}\n"
         "contact:\n"
         "  ground: {normal_stiffness_N_per_m: 1.0e4, restitution: 0.3, friction_coefficient: 0.5}\n"
         "  default: {normal_stiffness_N_per_m: 1.0e4, restitution: 0.3, friction_coefficient: 0.5}\n"
         "ground_motion:\n"
         "  components: [{file: " + record_file + ", format: two_column, axis: x}]\n"
         "output: {frame_interval_s: 0.01, history_interval_s: 0.001}\n";
}

}  // namespace fq::test
