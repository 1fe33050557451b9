// Registry of spring laws (STYLE.md 3.4): a small table of law kinds, each
// plain data plus a pure function of deformation and history. The joint
// system groups its springs by kind and runs one loop per kind (a switch per
// batch, never a virtual call per spring).
//
// How to add a law:
//   1. write joints/include/joints/<name>_law.h and src/<name>_law.cpp with a
//      Params struct (user data), a compiled Law struct, a State struct
//      (history) and `LawOutput evaluate_<name>(const Law&, State&, double delta_m)`
//      (plus compile_<name> that validates and throws std::invalid_argument);
//   2. add a value to SpringLawKind (before Count) and its name in
//      spring_law_name() (src/spring_law.cpp);
//   3. add a Params member to SpringLawDef and cases in
//      initial_stiffness_Npm() and ultimate_deformation_m() (src/spring_law.cpp);
//   4. add a batch (law, state and spring-id arrays) and a case in
//      JointSystem::add_spring_ and JointSystem::evaluate_laws_
//      (src/joint_system.cpp), which instantiate the batch template;
//   5. add a curve test in tests/joints/test_spring_laws.cpp.
#pragma once

#include <cstdint>

#include "joints/curee_law.h"
#include "joints/linear_elastic_law.h"
#include "joints/trilinear_law.h"

namespace fq {

enum class SpringLawKind : std::uint8_t { LinearElastic = 0, Trilinear = 1, Curee = 2, Count };
const char* spring_law_name(SpringLawKind kind);

struct SpringLawDef {
  SpringLawKind kind = SpringLawKind::LinearElastic;
  LinearElasticParams linear;
  TrilinearParams trilinear;
  CureeParams curee;
};

// Parallel dashpot: c = coefficient_Nspm + 2 damping_ratio sqrt(k0 m_eff),
// m_eff the reduced mass of the two bodies (the free body's mass when the
// other is fixed), k0 the law's initial stiffness.
struct DashpotDef {
  double coefficient_Nspm = 0.0;  // (N s/m)
  double damping_ratio = 0.0;     // zeta (-)
};

// One spring: law, dashpot and the length that turns deformation into strain.
struct SpringDef {
  SpringLawDef law;
  DashpotDef dashpot;
  double reference_length_m = 1.0;  // strain = delta / reference_length_m
};

// Initial (elastic) stiffness k0 (N/m), for dashpots from damping ratios and
// the stable-time-step estimate. Throws std::invalid_argument on bad parameters.
double initial_stiffness_Npm(const SpringDef& def);
// Deformation (m) at which the spring is deleted, tension side (> 0) and
// compression side (as a magnitude); infinity when the law never fails.
double ultimate_deformation_m(const SpringDef& def, bool tension);

// Convenience builders.
SpringDef linear_spring(double stiffness_Npm, double damping_ratio = 0.0);
SpringDef trilinear_spring(const TrilinearParams& p, double reference_length_m, double damping_ratio = 0.0);
SpringDef curee_spring(const CureeParams& p, double damping_ratio = 0.0);

}  // namespace fq
