#include "joints/curee_law.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace fq {

namespace {

void require(bool ok, const char* field, const char* expected) {
  if (!ok) throw std::invalid_argument(std::string("CUREE spring: ") + field + " must be " + expected);
}

constexpr double kInf = std::numeric_limits<double>::infinity();

// Kp = K0 (delta0 / dmax)^alpha, capped at K0 (also before any excursion).
double reload_stiffness(const CureeLaw& law, double dmax_m) {
  return dmax_m > law.delta0_m ? law.p.K0_Npm * std::pow(law.delta0_m / dmax_m, law.p.alpha) : law.p.K0_Npm;
}

}  // namespace

CureeLaw compile_curee(const CureeParams& p) {
  require(p.K0_Npm > 0.0 && std::isfinite(p.K0_Npm), "K0_Npm", "> 0 (N/m)");
  require(p.F0_N > 0.0, "F0_N", "> 0 (N)");
  require(p.F1_N > 0.0 && p.F1_N < p.F0_N, "F1_N", "in (0, F0_N) (N)");
  require(p.r1 >= 0.0 && p.r1 < 1.0, "r1", "in [0, 1)");
  require(p.r2 < 0.0, "r2", "< 0");
  require(p.r3 >= 1.0, "r3", ">= 1");
  require(p.r4 > 0.0 && p.r4 < 1.0, "r4", "in (0, 1)");
  require(p.delta_u_m > 0.0, "delta_u_m", "> 0 (m)");
  require(p.alpha >= 0.0, "alpha", ">= 0");
  require(p.beta >= 1.0, "beta", ">= 1");
  CureeLaw law;
  law.p = p;
  law.delta0_m = p.F0_N / p.K0_Npm;
  law.force_u_N = (p.F0_N + p.r1 * p.K0_Npm * p.delta_u_m) * (1.0 - std::exp(-p.K0_Npm * p.delta_u_m / p.F0_N));
  law.delta_fail_m = p.delta_u_m - law.force_u_N / (p.r2 * p.K0_Npm);
  // delta_p, the first deformation where the envelope reaches the pinching
  // line (E - P is -F1 at zero): the first sign change on a grid of 256
  // intervals over (0, delta_u], then bisection to round-off.
  const auto above_pinching = [&](double x) { return curee_envelope(law, x) - (p.F1_N + p.r4 * p.K0_Npm * x); };
  constexpr int kGrid = 256;
  double lo = 0.0, hi = -1.0;
  for (int i = 1; i <= kGrid; ++i) {
    const double x = p.delta_u_m * i / kGrid;
    if (above_pinching(x) >= 0.0) {
      hi = x;
      break;
    }
    lo = x;
  }
  require(hi > 0.0, "F1_N",
          "small enough that the pinching line F1 + r4 K0 delta meets the envelope before delta_u_m "
          "(it lies above the envelope up to delta_u_m)");
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (above_pinching(mid) >= 0.0 ? hi : lo) = mid;
  }
  law.delta_pinch_m = hi;
  return law;
}

double curee_envelope_work_J(const CureeLaw& law, double x) {
  // Integral of (F0 + r1 K0 s)(1 - exp(-c s)), c = K0 / F0, written in
  // y = c x with expm1 so that small x keeps its digits:
  //   F0^2/K0 (y - 1 + e^-y) + r1 F0^2/K0 (y^2/2 - 1 + e^-y (1 + y)),
  // plus the descending line's trapezoid beyond delta_u.
  const CureeParams& p = law.p;
  const double xe = std::min(x, p.delta_u_m);
  const double y = p.K0_Npm * xe / p.F0_N;
  const double em1 = std::expm1(-y);
  const double scale = p.F0_N * p.F0_N / p.K0_Npm;
  double w = scale * (y + em1) + p.r1 * scale * (0.5 * y * y + em1 + y * std::exp(-y));
  if (x > p.delta_u_m) {
    const double dx = std::min(x, law.delta_fail_m) - p.delta_u_m;
    w += law.force_u_N * dx + 0.5 * p.r2 * p.K0_Npm * dx * dx;
  }
  return w;
}

double curee_envelope(const CureeLaw& law, double x) {
  const CureeParams& p = law.p;
  if (x <= p.delta_u_m) return (p.F0_N + p.r1 * p.K0_Npm * x) * (1.0 - std::exp(-p.K0_Npm * x / p.F0_N));
  if (x <= law.delta_fail_m) return law.force_u_N + p.r2 * p.K0_Npm * (x - p.delta_u_m);
  return 0.0;
}

LawOutput evaluate_curee(const CureeLaw& law, CureeState& s, double delta) {
  const CureeParams& p = law.p;
  LawOutput out;
  if (std::abs(delta) > law.delta_fail_m) {
    out.failed = true;
    out.inelastic = true;
    return out;
  }
  const double step = delta - s.delta_prev_m;
  const std::int8_t dir = step > 0.0 ? std::int8_t(1) : (step < 0.0 ? std::int8_t(-1) : s.direction);
  if (dir != s.direction) {
    if (s.direction != 0) {
      // Reversal at the previous point: it becomes the origin of the unloading line.
      s.has_reversal = true;
      s.reversal_delta_m = s.delta_prev_m;
      s.reversal_force_N = s.force_prev_N;
      if (s.delta_prev_m > 0.0) s.dmax_pos_m = std::max(s.dmax_pos_m, s.delta_prev_m);
      if (s.delta_prev_m < 0.0) s.dmax_neg_m = std::max(s.dmax_neg_m, -s.delta_prev_m);
    }
    s.direction = dir;
  }
  if (s.direction == 0) {  // never moved: at rest at delta = 0
    out.force_N = 0.0;
    return out;
  }
  // The state and output at force f, on either path below.
  auto settle = [&](double f) {
    s.delta_prev_m = delta;
    s.force_prev_N = f;
    if (std::abs(delta) > law.delta0_m) s.yielded = true;
    out.force_N = f;
    out.stored_J = curee_stored_energy_J(law, s, f, delta);
    out.inelastic = s.yielded;
    return out;
  };
  if (!s.beyond_pinch && std::abs(delta) <= law.delta_pinch_m)  // never beyond delta_p: elastic on the envelope (header)
    return settle(delta >= 0.0 ? curee_envelope(law, delta) : -curee_envelope(law, -delta));
  s.beyond_pinch = true;
  const double k0 = p.K0_Npm;
  const double unload =
      s.has_reversal ? s.reversal_force_N + p.r3 * k0 * (delta - s.reversal_delta_m) : (dir >= 0 ? kInf : -kInf);
  double f = 0.0;
  if (dir >= 0) {
    const double env = delta > 0.0 ? curee_envelope(law, delta) : kInf;
    const double env_on_pinch = delta >= law.delta_pinch_m ? env : kInf;  // header: not below delta_p
    const double pinch = p.F1_N + p.r4 * k0 * delta;
    const double target = p.beta * s.dmax_pos_m;
    const double reload = curee_envelope(law, target) + reload_stiffness(law, s.dmax_pos_m) * (delta - target);
    double bound = std::max(std::min(env_on_pinch, pinch), std::min(env, reload));
    if (s.has_reversal) bound = std::max(bound, std::min(s.reversal_force_N, env));  // continuity guard
    f = std::min(unload, bound);
  } else {
    const double env = delta < 0.0 ? -curee_envelope(law, -delta) : -kInf;
    const double env_on_pinch = delta <= -law.delta_pinch_m ? env : -kInf;
    const double pinch = -p.F1_N + p.r4 * k0 * delta;
    const double target = p.beta * s.dmax_neg_m;
    const double reload = -curee_envelope(law, target) + reload_stiffness(law, s.dmax_neg_m) * (delta + target);
    double bound = std::min(std::max(env_on_pinch, pinch), std::max(env, reload));
    if (s.has_reversal) bound = std::min(bound, std::max(s.reversal_force_N, env));  // continuity guard
    f = std::max(unload, bound);
  }
  return settle(f);
}

}  // namespace fq
