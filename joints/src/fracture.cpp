#include "joints/fracture.h"

namespace fq {

const char* break_criterion_name(BreakCriterion c) {
  switch (c) {
    case BreakCriterion::AllNormalSpringsDeleted:
      return "all_normal_springs_deleted";
    case BreakCriterion::AnySpringDeleted:
      return "any_spring_deleted";
    case BreakCriterion::StrainLimit:
      return "strain_limit";
    case BreakCriterion::Never:
      return "never";
  }
  return "unknown";
}

bool joint_should_break(const JointBreakDef& def, const JointSpringSummary& s) {
  switch (def.criterion) {
    case BreakCriterion::AllNormalSpringsDeleted:
      return s.normal_springs > 0 ? s.normal_springs_alive == 0 : (s.springs > 0 && s.springs_alive == 0);
    case BreakCriterion::AnySpringDeleted:
      return s.springs_alive < s.springs;
    case BreakCriterion::StrainLimit:
      return s.max_strain > def.strain_limit || s.springs_alive == 0;
    case BreakCriterion::Never:
      return false;
  }
  return false;
}

}  // namespace fq
