// Trilinear spring of seed 000 (Tingatinga et al. 2008, Fig. 3): separate
// tension and compression branches, each linear up to yield (eps_Y, F_Y),
// then strain hardening up to the ultimate point (eps_U, F_U). Once the strain
// passes eps_U (tension) or -eps_U (compression) the spring is DELETED and
// exerts nothing more, ever (seed 000: "no subsequent forces are exerted ...
// the link is marked DELETED"). Strain = delta / reference length.
//
// Unloading / reloading (not given by the seed; our choice): bilinear
// kinematic hardening written as a "bounded elastic" rule with one state
// variable, the plastic offset delta_p (m):
//   trial  F* = k_e (delta - delta_p),  k_e = k0_t if delta - delta_p >= 0 else k0_c
//   bounds F_lo(delta) <= F <= F_hi(delta), with the two hardening lines
//          F_hi = F_Yt + k1_t (delta - d_Yt)     (tension hardening line, extended)
//          F_lo = -F_Yc + k1_c (delta + d_Yc)    (compression hardening line, extended)
//   F = clamp(F*, F_lo, F_hi); if clamped, delta_p = delta - F / k_e.
// So unloading from a plastic state is elastic at the initial stiffness, the
// elastic range has constant height F_hi - F_lo (Bauschinger effect), and a
// monotonic path traces Fig. 3 exactly. The deletion test uses the total
// strain, as the seed does.
//
// Energy: stored = F^2 / (2 k_e), what elastic unloading to F = 0 gives back;
// plastic dissipation = work done - stored (booked by the joint system).
#pragma once

#include <algorithm>

#include "joints/law_output.h"

namespace fq {

// Magnitudes (all positive); strains are dimensionless, forces in N.
struct TrilinearParams {
  double yield_strain_tension = 0.0;
  double yield_force_tension_N = 0.0;
  double ultimate_strain_tension = 0.0;
  double ultimate_force_tension_N = 0.0;
  double yield_strain_compression = 0.0;
  double yield_force_compression_N = 0.0;
  double ultimate_strain_compression = 0.0;
  double ultimate_force_compression_N = 0.0;
};

// Parameters turned into deformations (m) and slopes (N/m) for one reference length.
struct TrilinearLaw {
  double k0_t_Npm = 0.0, k1_t_Npm = 0.0, dy_t_m = 0.0, fy_t_N = 0.0, du_t_m = 0.0;
  double k0_c_Npm = 0.0, k1_c_Npm = 0.0, dy_c_m = 0.0, fy_c_N = 0.0, du_c_m = 0.0;
  // 1 / k0 (m/N): the stored energy F^2 / (2 k_e) is formed every step, and
  // a division costs as much as the rest of the law.
  double inv_k0_t_mpN = 0.0, inv_k0_c_mpN = 0.0;
};

struct TrilinearState {
  double plastic_offset_m = 0.0;  // delta_p (m)
};

// Throws std::invalid_argument naming the field when the parameters are not
// 0 < eps_Y < eps_U, 0 < F_Y, 0 <= F_U, or when the hardening lines cross
// inside [-d_Uc, d_Ut] (the elastic range would vanish).
TrilinearLaw compile_trilinear(const TrilinearParams& p, double reference_length_m);

// Stored energy at law force f (J): F^2 / (2 k_e), k_e on the side of f.
inline double trilinear_stored_energy_J(const TrilinearLaw& law, double f_N) {
  return 0.5 * f_N * f_N * (f_N >= 0.0 ? law.inv_k0_t_mpN : law.inv_k0_c_mpN);
}

// Past the ultimate deformation on either side: the spring is deleted.
inline bool trilinear_past_ultimate(const TrilinearLaw& law, double delta_m) {
  return delta_m > law.du_t_m || delta_m < -law.du_c_m;
}

// The elastic trial force F* = k_e (delta - delta_p) and the two hardening
// bounds at delta (N).
struct TrilinearTrial {
  double force_N, lower_N, upper_N;
  bool inside() const { return !(force_N > upper_N || force_N < lower_N); }
};
inline TrilinearTrial trilinear_trial(const TrilinearLaw& law, double plastic_offset_m, double delta_m) {
  const double e = delta_m - plastic_offset_m;
  return {(e >= 0.0 ? law.k0_t_Npm : law.k0_c_Npm) * e, -law.fy_c_N + law.k1_c_Npm * (delta_m + law.dy_c_m),
          law.fy_t_N + law.k1_t_Npm * (delta_m - law.dy_t_m)};
}

inline LawOutput evaluate_trilinear(const TrilinearLaw& law, TrilinearState& io_state, double delta_m) {
  LawOutput out;
  if (trilinear_past_ultimate(law, delta_m)) {
    out.failed = true;
    out.inelastic = true;
    return out;
  }
  const TrilinearTrial trial = trilinear_trial(law, io_state.plastic_offset_m, delta_m);
  double f = trial.force_N;
  const double f_hi = trial.upper_N, f_lo = trial.lower_N;
  if (!trial.inside()) {
    f = std::clamp(f, f_lo, f_hi);
    io_state.plastic_offset_m = delta_m - f / (f >= 0.0 ? law.k0_t_Npm : law.k0_c_Npm);
  }
  out.force_N = f;
  out.stored_J = trilinear_stored_energy_J(law, f);
  out.inelastic = io_state.plastic_offset_m != 0.0;
  return out;
}

}  // namespace fq
