// A case for the tests of what a run says of its first joint failure
// (tests/apps): a 0.1 kg hanger (10 x 10 x 100 mm at 10 000 kg/m^3) on one
// joint point whose normal spring is trilinear with an ultimate force of
// 1.5 N, no gravity, the ground accelerating upward at 10 t m/s^2 (the
// record write_hanger_ramp writes). The spring carries m a_g = 0.1 x 10 t
// = t N (statics, the hanger following the ground), so it reaches its
// ultimate force and is deleted at t = 1.5 s. With fracture criterion
// any_spring_deleted the joint breaks then; with `never` it loses that
// spring and holds on its shear springs.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace fq_test {

inline std::string hanger_case(const std::string& name, const std::string& criterion) {
  return "framequake_case: 1\n"
         "name: " + name + "\n"
         "time: {dt_s: 1.0e-5, duration_s: 1.6, gravity_mps2: [0, 0, 0]}\n"
         "materials: [{name: heavy, density_kg_per_m3: 10000}]\n"
         "sections: [{name: sq, width_m: 0.010, depth_m: 0.010}]\n"
         "nodes: [{id: top, xyz_m: [0, 0, 0.2]}, {id: bot, xyz_m: [0, 0, 0.1]}]\n"
         "members: [{id: hanger, kind: other, nodes: [top, bot], section: sq, material: heavy}]\n"
         "joint_types:\n"
         "  - name: tri\n"
         "    layout: single_point\n"
         "    normal: {law: trilinear, reference_length_m: 0.010, yield_strain_tension: 0.01, "
         "yield_force_tension_N: 1.0, ultimate_strain_tension: 0.05, ultimate_force_tension_N: 1.5, "
         "yield_strain_compression: 0.01, yield_force_compression_N: 1.0, ultimate_strain_compression: 0.05, "
         "ultimate_force_compression_N: 1.5, damping_ratio: 0.02}\n"
         "    shear: {law: linear, stiffness_N_per_m: 1.0e5, damping_ratio: 0.02}\n"
         "    fracture: {criterion: " + criterion + "}\n"
         "joints: {support_type: tri}\n"
         "supports: [{node: top}]\n"
         "ground_motion: {components: [{file: ramp.txt, format: two_column, unit: m/s2, axis: z}]}\n"
         "output: {frame_interval_s: 0.8, history_interval_s: 0.01}\n";
}

// ramp.txt in `folder`: a_g = 10 t m/s^2 from 0 to 2 s, every 0.01 s.
inline void write_hanger_ramp(const std::filesystem::path& folder) {
  std::ofstream ramp(folder / "ramp.txt");
  for (int i = 0; i <= 200; ++i) ramp << 0.01 * i << " " << 0.1 * i << "\n";
}

}  // namespace fq_test
