#include "contacts/contact_params.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace fq {

double damping_ratio_from_restitution(double restitution) {
  const double l = std::log(restitution);
  return -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

double restitution_from_damping_ratio(double zeta) {
  return std::exp(-zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
}

double clamped_restitution_from_damping_ratio(double zeta) {
  if (zeta <= 0.0) return 1.0;
  if (zeta < 1.0) {
    const double s = std::sqrt(1.0 - zeta * zeta);
    // (1 - 2 zeta^2) sin(phi) = -2 zeta s cos(phi): the first root in (0, pi)
    // is atan2(2 zeta s, -(1 - 2 zeta^2)) (in (pi/2, pi) for zeta < 1/sqrt 2).
    const double wd_t = std::atan2(2.0 * zeta * s, -(1.0 - 2.0 * zeta * zeta));
    const double w_t = wd_t / s;
    return std::exp(-zeta * w_t) * std::fabs(std::cos(wd_t) - zeta / s * std::sin(wd_t));
  }
  if (zeta == 1.0) return std::exp(-2.0);  // x = v t e^(-t): force zero at t = 2, x' = -v e^(-2)
  // Overdamped (units w = 1): x = v (e^(r1 t) - e^(r2 t)) / (r1 - r2), r1,2 =
  // -zeta +- s, s = sqrt(zeta^2 - 1). Force zero, x + 2 zeta x' = 0, at
  // e^((r1 - r2) t) = (2 zeta^2 - 1 + 2 zeta s) / (2 zeta^2 - 1 - 2 zeta s);
  // the restitution is |x'(t)| / v there.
  const double s = std::sqrt(zeta * zeta - 1.0);
  const double r1 = -zeta + s, r2 = -zeta - s;
  const double q = 2.0 * zeta * zeta - 1.0;
  const double t = std::log((q + 2.0 * zeta * s) / (q - 2.0 * zeta * s)) / (2.0 * s);
  return std::fabs(r1 * std::exp(r1 * t) - r2 * std::exp(r2 * t)) / (2.0 * s);
}

double damping_ratio_for_clamped_restitution(double restitution) {
  if (!(restitution > 0.0 && restitution <= 1.0))
    throw std::invalid_argument("restitution must lie in (0, 1]");
  if (restitution == 1.0) return 0.0;
  // clamped_restitution_from_damping_ratio falls from 1 (zeta = 0) towards 0
  // as zeta grows (e^-2 at zeta = 1, 0.048 at zeta = 2): bracket, then bisect
  // to the last bit.
  double lo = 0.0, hi = 1.0;
  while (clamped_restitution_from_damping_ratio(hi) > restitution) {
    lo = hi;
    hi *= 2.0;
    if (hi > 1e12) throw std::invalid_argument("restitution too small for a spring-dashpot contact");
  }
  for (int k = 0; k < 200 && hi - lo > 1e-16 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (clamped_restitution_from_damping_ratio(mid) > restitution ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

ContactCoefficients make_contact_coefficients(const ContactParams& p, const char* what) {
  const std::string where = std::string("contact parameters of ") + what + ": ";
  if (!(p.normal_stiffness_N_per_m > 0.0) || !std::isfinite(p.normal_stiffness_N_per_m))
    throw std::invalid_argument(where + "normal_stiffness_N_per_m must be a positive number of N/m");
  if (!(p.restitution > 0.0 && p.restitution <= 1.0))
    throw std::invalid_argument(where + "restitution must lie in (0, 1]");
  if (!(p.tangential_stiffness_N_per_m >= 0.0) || !std::isfinite(p.tangential_stiffness_N_per_m))
    throw std::invalid_argument(where +
                                "tangential_stiffness_N_per_m must be >= 0 N/m (0 derives it from the normal one)");
  if (!(p.friction_coefficient >= 0.0) || !std::isfinite(p.friction_coefficient))
    throw std::invalid_argument(where + "friction_coefficient must be a number >= 0");
  ContactCoefficients c;
  c.normal_stiffness_N_per_m = p.normal_stiffness_N_per_m;
  c.tangential_stiffness_N_per_m = p.tangential_stiffness_N_per_m > 0.0
                                       ? p.tangential_stiffness_N_per_m
                                       : kTangentialToNormalStiffness * p.normal_stiffness_N_per_m;
  // The restitution asked for is the one a centric normal impact gives with
  // the compression-only law (not that of a free spring-dashpot, which the
  // clamp would raise: 0.5 would give 0.55).
  c.damping_ratio = damping_ratio_for_clamped_restitution(p.restitution);
  c.friction_coefficient = p.friction_coefficient;
  return c;
}

}  // namespace fq
