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
    const double shown_rad = 1.0 / shown_n;
    for (const double limit_rad : limits_rad)
      if ((shown_rad > limit_rad) != (ratio_rad > limit_rad) || (shown_rad >= limit_rad) != (ratio_rad >= limit_rad))
        return false;
    return true;
  };
  // Whole n rounded half away from zero (1/262.5 rad is 1/263), as
  // before; decimals by printf's rounding.
  std::string text = std::to_string(std::llround(n));
  if (same_side(double(std::llround(n)))) return "1/" + text;
  char decimal_text[64];
  for (int decimals = 1; decimals <= 6; ++decimals) {
    std::snprintf(decimal_text, sizeof decimal_text, "%.*f", decimals, n);
    text = decimal_text;
    if (same_side(std::strtod(decimal_text, nullptr))) break;
  }
  return "1/" + text;
}

}  // namespace fq_app
