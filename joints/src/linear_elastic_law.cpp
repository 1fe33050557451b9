#include "joints/linear_elastic_law.h"

#include <cmath>
#include <stdexcept>

namespace fq {

void validate_linear_elastic(const LinearElasticParams& p) {
  if (!(p.stiffness_Npm > 0.0) || !std::isfinite(p.stiffness_Npm))
    throw std::invalid_argument("linear elastic spring: stiffness_Npm must be a positive number of N/m");
}

}  // namespace fq
