// Fracture rules of a joint (seed 001: "the joint is considered broken when
// the fracture criterion is met ... which limits the maximum strain of joint
// springs"; seed 000: springs deleted past their ultimate strain).
//
// Per spring: deleted by its own law (trilinear past eps_U, CUREE past
// delta_f). Per joint, one of:
//   AllNormalSpringsDeleted  broken when every normal spring (point normal
//                            springs and axial links) is deleted; a joint
//                            without normal springs breaks when all its
//                            springs are deleted
//   AnySpringDeleted         broken at the first deletion of any spring
//   StrainLimit              broken when the joint strain measure
//                            max_i |delta_i| / reference_length_i over its
//                            live springs exceeds strain_limit (seed 001)
//   Never                    the joint only loses springs
// A broken joint transmits no force from the next step on; its pair is
// released from BondedPairs in finish_step (ascending joint id) and the
// energy still stored in its springs is booked as dissipated (plastic),
// with their last force's work over the step after (joint_system.h, Energy).
#pragma once

#include <cstdint>
#include <limits>

namespace fq {

enum class BreakCriterion : std::uint8_t {
  AllNormalSpringsDeleted = 0,
  AnySpringDeleted = 1,
  StrainLimit = 2,
  Never = 3
};
const char* break_criterion_name(BreakCriterion c);

struct JointBreakDef {
  BreakCriterion criterion = BreakCriterion::AllNormalSpringsDeleted;
  double strain_limit = std::numeric_limits<double>::infinity();  // (-), for StrainLimit
};

// Decides a joint's fate from a summary of its springs.
struct JointSpringSummary {
  int springs = 0;
  int springs_alive = 0;
  int normal_springs = 0;
  int normal_springs_alive = 0;
  double max_strain = 0.0;  // max |delta| / reference length over live springs
};
bool joint_should_break(const JointBreakDef& def, const JointSpringSummary& s);

}  // namespace fq
