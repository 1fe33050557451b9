// Contact parameters of one material pair, with every default in one place,
// and the coefficients the contact law derives from them.
//
// Stiffnesses are per contact POINT. A box lying flat on a face touches with
// four points (a face clipped against a face, or four corners below the
// ground), so its face contact is four times as stiff as a corner contact, as
// a real face is stiffer than a corner. The dashpot is sized per point from
// the pair's reduced mass shared among the points of its manifold (see
// linear_contact_law.h), so a flat impact has exactly the damping ratio that
// the restitution asks for, and so its restitution.
#pragma once

namespace fq {

struct ContactParams {
  // Normal spring per contact point (N/m). Default from the scaled frames of
  // seed 001: wood across the grain has E_perp ~ 0.4 GPa; a face contact of
  // a 10 mm member has stiffness ~ E L = 0.4e9 * 0.01 = 4e6 N/m, shared by
  // its four points -> 1e6 N/m. With the lightest member (a 10x10x490 mm
  // beam, ~0.022 kg) one point's own mode alone would allow dt ~ 5e-5 s;
  // in the frames, where a column stands on the column below through four
  // such points with their dashpots, the network estimate is 2.26e-5 s
  // (`framequake info`), still above the seed's dt = 1e-5 s.
  double normal_stiffness_N_per_m = 1.0e6;
  // Coefficient of restitution of a centric normal impact (-), 0 < e <= 1.
  // Wood on wood rebounds with e ~ 0.4-0.6 in drop tests; 0.5 is the middle.
  double restitution = 0.5;
  // Tangential (shear) spring per contact point (N/m). 0 means "derive from
  // k_n": k_t = kTangentialToNormalStiffness * k_n (see below).
  double tangential_stiffness_N_per_m = 0.0;
  // Coulomb friction coefficient (-). Wood on wood (dry, planed) slides at
  // mu ~ 0.3-0.5; 0.4 is the middle.
  double friction_coefficient = 0.4;
};

// Why not 2/7: k_t/k_n = 2/7 makes the tangential and normal periods of a
// SPHERE contact equal, because a sphere's tangential motion at the contact
// couples to its rolling (effective mass 2/7 m). A box resting on a face does
// not roll, so that argument does not carry over. The elastic-contact ratio
// of Mindlin, k_t/k_n = 2(1 - nu)/(2 - nu), does: with nu = 0.3 (a middle
// value for wood across the grain) it is 1.4/1.7 = 0.82. The tangential
// period then stays shorter than the normal one, so the normal spring still
// sets the stable step.
inline constexpr double kContactPoisson = 0.3;
inline constexpr double kTangentialToNormalStiffness = 2.0 * (1.0 - kContactPoisson) / (2.0 - kContactPoisson);

// Damping ratio of the linear spring-dashpot whose free response (no clamp:
// the force may pull at the end) has restitution e: zeta = -ln e /
// sqrt(pi^2 + ln^2 e) (closed form of e = exp(-zeta pi / sqrt(1 - zeta^2))).
// e = 1 gives 0. Not what the contacts use (see below).
double damping_ratio_from_restitution(double restitution);
// Inverse: e = exp(-zeta pi / sqrt(1 - zeta^2)) for 0 <= zeta < 1.
double restitution_from_damping_ratio(double zeta);
// Restitution actually obtained when the normal force is clamped at zero
// (compression only): the bodies separate when k d + c d' = 0, before the
// overlap returns to zero. Time of force zero in the damped free response:
// tan(w_d t) = -2 zeta sqrt(1 - zeta^2) / (1 - 2 zeta^2), and
// e = exp(-zeta w t) |cos(w_d t) - zeta/sqrt(1 - zeta^2) sin(w_d t)|
// (Schwager & Poeschel, Phys. Rev. E 75, 051304 (2007), derive the same);
// e^-2 for zeta = 1 and the overdamped closed form above it (the .cpp). It is
// higher than the unclamped restitution of the same zeta (0.55 against 0.5).
double clamped_restitution_from_damping_ratio(double zeta);
// Its inverse: the damping ratio whose compression-only contact rebounds
// with restitution e, 0 < e <= 1 (bisection; above 1 for e < e^-2). This
// is what make_contact_coefficients uses, so that `restitution` is the
// restitution a centric normal impact has.
double damping_ratio_for_clamped_restitution(double restitution);

// What the law needs per material pair, derived once from ContactParams.
struct ContactCoefficients {
  double normal_stiffness_N_per_m = 0.0;
  double tangential_stiffness_N_per_m = 0.0;
  double damping_ratio = 0.0;  // zeta (-), same for normal and tangential dashpots (from the clamped restitution)
  double friction_coefficient = 0.0;
};

// Checks the values (throws std::invalid_argument naming the field and what
// was expected) and derives the coefficients; `what` names the pair in messages.
ContactCoefficients make_contact_coefficients(const ContactParams& params, const char* what);

}  // namespace fq
