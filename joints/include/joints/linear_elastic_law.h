// Linear elastic spring: F = k delta. Never yields, never fails on its own
// (a joint holding only linear springs breaks only by its strain criterion).
#pragma once

#include "joints/law_output.h"

namespace fq {

struct LinearElasticParams {
  double stiffness_Npm = 0.0;  // k (N/m)
};

struct LinearElasticState {};

inline double linear_elastic_stored_energy_J(const LinearElasticParams& p, double delta_m) {
  return 0.5 * p.stiffness_Npm * delta_m * delta_m;
}

inline LawOutput evaluate_linear_elastic(const LinearElasticParams& p, LinearElasticState& /*io_state*/,
                                         double delta_m) {
  LawOutput out;
  out.force_N = p.stiffness_Npm * delta_m;
  out.stored_J = linear_elastic_stored_energy_J(p, delta_m);
  return out;
}

// Throws std::invalid_argument naming the field when k <= 0 or not finite.
void validate_linear_elastic(const LinearElasticParams& p);

}  // namespace fq
