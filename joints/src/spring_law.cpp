#include "joints/spring_law.h"

#include <limits>
#include <stdexcept>

namespace fq {

const char* spring_law_name(SpringLawKind kind) {
  switch (kind) {
    case SpringLawKind::LinearElastic:
      return "linear_elastic";
    case SpringLawKind::Trilinear:
      return "trilinear";
    case SpringLawKind::Curee:
      return "curee";
    case SpringLawKind::Count:
      break;
  }
  return "unknown";
}

double initial_stiffness_Npm(const SpringDef& def) {
  switch (def.law.kind) {
    case SpringLawKind::LinearElastic:
      validate_linear_elastic(def.law.linear);
      return def.law.linear.stiffness_Npm;
    case SpringLawKind::Trilinear: {
      const TrilinearLaw law = compile_trilinear(def.law.trilinear, def.reference_length_m);
      return std::max(law.k0_t_Npm, law.k0_c_Npm);
    }
    case SpringLawKind::Curee: {
      const CureeLaw law = compile_curee(def.law.curee);
      return law.p.r3 * law.p.K0_Npm;  // unloading is the stiffest branch
    }
    case SpringLawKind::Count:
      break;
  }
  throw std::invalid_argument("spring law: unknown kind");
}

double ultimate_deformation_m(const SpringDef& def, bool tension) {
  switch (def.law.kind) {
    case SpringLawKind::Trilinear: {
      const TrilinearLaw law = compile_trilinear(def.law.trilinear, def.reference_length_m);
      return tension ? law.du_t_m : law.du_c_m;
    }
    case SpringLawKind::Curee:
      return compile_curee(def.law.curee).delta_fail_m;
    default:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

SpringDef linear_spring(double stiffness_Npm, double damping_ratio) {
  SpringDef d;
  d.law.kind = SpringLawKind::LinearElastic;
  d.law.linear.stiffness_Npm = stiffness_Npm;
  d.dashpot.damping_ratio = damping_ratio;
  return d;
}

SpringDef trilinear_spring(const TrilinearParams& p, double reference_length_m, double damping_ratio) {
  SpringDef d;
  d.law.kind = SpringLawKind::Trilinear;
  d.law.trilinear = p;
  d.reference_length_m = reference_length_m;
  d.dashpot.damping_ratio = damping_ratio;
  return d;
}

SpringDef curee_spring(const CureeParams& p, double damping_ratio) {
  SpringDef d;
  d.law.kind = SpringLawKind::Curee;
  d.law.curee = p;
  d.dashpot.damping_ratio = damping_ratio;
  return d;
}

}  // namespace fq
