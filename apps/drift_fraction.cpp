// Drift ratio as 1/n (drift_fraction.h).
#include "drift_fraction.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace fq_app {

std::string drift_one_in_n(double ratio_rad, const std::vector<double>& limits_rad) {
  constexpr double kSmallestRatio_rad = 1e-9;
  if (!(ratio_rad >= kSmallestRatio_rad) || !std::isfinite(ratio_rad)) return "";
  const double n = 1.0 / ratio_rad;
  // The shown n, read back, on the same side of every limit as the ratio
  // (a limit is "beyond" for one verdict and "from" for another: both
  // comparisons must agree).
  auto same_side = [&](double shown_n) {
    const double shown = 1.0 / shown_n;
    for (const double limit : limits_rad)
      if ((shown > limit) != (ratio_rad > limit) || (shown >= limit) != (ratio_rad >= limit)) return false;
    return true;
  };
  char text[64];
  for (int decimals = 0;; ++decimals) {
    std::snprintf(text, sizeof text, "%.*f", decimals, n);
    if (decimals == 6 || same_side(std::strtod(text, nullptr))) break;
  }
  return std::string("1/") + text;
}

}  // namespace fq_app
