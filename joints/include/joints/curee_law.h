// Hysteretic timber-connection spring with pinching and stiffness/strength
// degradation: the 10-parameter CUREE model of Folz & Filiatrault (2001,
// J. Struct. Eng. 127(4); the SAWS program), written here from its published
// description (parameters K0, F0, F1, r1, r2, r3, r4, delta_u, alpha, beta).
// delta is the deformation (m); the model is symmetric in sign.
//
// Envelope (monotonic backbone), x = |delta|:
//   E(x) = (F0 + r1 K0 x)(1 - exp(-K0 x / F0))            0 <= x <= delta_u
//   E(x) = E(delta_u) + r2 K0 (x - delta_u)               delta_u < x <= delta_f
//   delta_f = delta_u - E(delta_u) / (r2 K0)  (descending branch reaches zero)
// Beyond delta_f the connection has failed: the spring is deleted.
//
// Cyclic rules implemented (one state per spring; lines written for a motion
// towards +delta, the other direction is the mirror image):
//   U(delta) = F_r + r3 K0 (delta - delta_r)   unloading line from the last
//              reversal point (delta_r, F_r)
//   P(delta) = +F1 + r4 K0 delta               pinching line (intercept F1)
//   R(delta) = E(beta dmax) + Kp (delta - beta dmax)   reloading line towards
//              the envelope point at beta times the largest previous
//              excursion dmax on this side (beta > 1 degrades the strength
//              reached at dmax), with degraded stiffness
//              Kp = K0 (delta0 / dmax)^alpha, delta0 = F0 / K0, Kp <= K0.
//   F = min( U, max( min(P, E(delta) if delta >= delta_p), min(R, E(delta) if delta > 0) ) )
//   (and F = sign(delta) E(|delta|) until |delta| first exceeds delta_p;
//   both explained below)
// i.e. unload along r3 K0 until the pinching line, follow it until the
// reloading line, reload to the envelope, then follow the envelope. Before
// any excursion to a side (dmax = 0) the reloading line is K0 delta, which
// lies above the (concave) envelope, so the first loading follows the
// envelope and a first excursion to the other side still pinches.
//
// Near zero the pinching line lies outside the envelope: it crosses
// delta = 0 at -F1 (moving towards -delta), where E is 0. The loops of the
// model cross zero deformation at +-F1, so the envelope does not bound the
// pinching line for |delta| < delta_p, the deformation where the pinching
// line meets the envelope, E(delta_p) = F1 + r4 K0 delta_p (SAWS's DINT2).
// (Bounding it there made the force jump by about F1 at every crossing of
// zero.) The envelope still bounds the unloading and reloading lines. So
// that the first loading still starts on the envelope, a spring that has
// never been deformed beyond delta_p follows the envelope both ways,
// F = sign(delta) E(|delta|), as nonlinear elastic (as SAWS does below
// 1.05 delta_p); the rules above apply once |delta| has exceeded delta_p.
// dmax is updated at reversals only, so the force is a continuous function
// of delta between reversals, provided the reloading line crosses delta = 0
// within +-F1 (Kp beta dmax >= E(beta dmax) - F1, which holds for the usual
// alpha < 1; otherwise the force steps to the pinching line at zero).
// Continuity guard: if at a reversal the new bound lies beyond the current
// force (after tiny reversals, e.g. a small vibration riding on cyclic
// loading), the force stays at F_r until the bound catches up (never beyond
// the envelope).
// "Yielded" = first time |delta| > delta0. Stored energy: below delta_p
// (never exceeded) the work done on the envelope, the integral of E; after,
// F^2 / (2 r3 K0), what unloading along the unloading slope gives back; the
// rest of the work is hysteretic dissipation.
#pragma once

#include <cstdint>

#include "joints/law_output.h"

namespace fq {

struct CureeParams {
  double K0_Npm = 0.0;     // initial stiffness (N/m)
  double F0_N = 0.0;       // intercept of the envelope's asymptote (N), F0 > F1 > 0
  double F1_N = 0.0;       // intercept of the pinching line (N)
  double r1 = 0.0;         // asymptote slope / K0, 0 <= r1 < 1
  double r2 = 0.0;         // descending slope / K0, r2 < 0
  double r3 = 1.0;         // unloading slope / K0, r3 >= 1
  double r4 = 0.0;         // pinching slope / K0, r4 > 0
  double delta_u_m = 0.0;  // deformation at peak force (m), > 0
  double alpha = 0.0;      // stiffness degradation exponent (-), >= 0
  double beta = 1.0;       // strength degradation factor (-), >= 1
};

struct CureeLaw {
  CureeParams p;
  double delta0_m = 0.0;      // F0 / K0
  double force_u_N = 0.0;     // E(delta_u)
  double delta_fail_m = 0.0;  // delta_f
  double delta_pinch_m = 0.0; // delta_p: E(delta_p) = F1 + r4 K0 delta_p, 0 < delta_p < delta_u
};

struct CureeState {
  double delta_prev_m = 0.0;
  double force_prev_N = 0.0;
  double reversal_delta_m = 0.0;
  double reversal_force_N = 0.0;
  double dmax_pos_m = 0.0;    // largest previous excursion towards +delta (m), at reversals
  double dmax_neg_m = 0.0;    // same towards -delta, as a magnitude (m)
  std::int8_t direction = 0;  // +1 / -1 direction of the current branch, 0 before any motion
  bool has_reversal = false;
  bool yielded = false;
  bool beyond_pinch = false;  // |delta| has exceeded delta_p: the hysteretic rules apply
};

// Throws std::invalid_argument naming the field when a parameter is out of range.
CureeLaw compile_curee(const CureeParams& p);
// Envelope E(x) for x >= 0 (N); 0 beyond delta_f.
double curee_envelope(const CureeLaw& law, double x_m);
LawOutput evaluate_curee(const CureeLaw& law, CureeState& io_state, double delta_m);
// Integral of E from 0 to x (J), x >= 0 within delta_u.
double curee_envelope_work_J(const CureeLaw& law, double x_m);
// Stored energy (J) at law force f and deformation delta in `state`: the
// envelope's work while the spring has not passed delta_p (elastic there),
// else what unloading at r3 K0 gives back.
inline double curee_stored_energy_J(const CureeLaw& law, const CureeState& state, double f_N, double delta_m) {
  if (!state.beyond_pinch) return curee_envelope_work_J(law, delta_m < 0.0 ? -delta_m : delta_m);
  return 0.5 * f_N * f_N / (law.p.r3 * law.p.K0_Npm);
}

}  // namespace fq
