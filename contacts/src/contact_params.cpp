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
  const double s = std::sqrt(1.0 - zeta * zeta);
  // (1 - 2 zeta^2) sin(phi) = -2 zeta s cos(phi): the first root in (0, pi)
  // is atan2(2 zeta s, -(1 - 2 zeta^2)) (in (pi/2, pi) for zeta < 1/sqrt 2).
  const double wd_t = std::atan2(2.0 * zeta * s, -(1.0 - 2.0 * zeta * zeta));
  const double w_t = wd_t / s;
  return std::exp(-zeta * w_t) * std::fabs(std::cos(wd_t) - zeta / s * std::sin(wd_t));
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
  c.damping_ratio = damping_ratio_from_restitution(p.restitution);
  c.friction_coefficient = p.friction_coefficient;
  return c;
}

}  // namespace fq
