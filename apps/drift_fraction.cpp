// Drift ratio as 1/n (drift_fraction.h).
#include "drift_fraction.h"

#include <cmath>

namespace fq_app {

std::string drift_one_in_n(double ratio_rad) {
  constexpr double kSmallestRatio_rad = 1e-9;
  if (!(ratio_rad >= kSmallestRatio_rad) || !std::isfinite(ratio_rad)) return "";
  return "1/" + std::to_string(std::llround(1.0 / ratio_rad));
}

}  // namespace fq_app
