// Contact law: linear normal spring-dashpot (compression only) and a
// Cundall-Strack incremental tangential spring-dashpot with a Coulomb cap
// (seed 001, Fig. 1: "normal and shear stiffness by spring dashpot assembly
// in direction normal to contact surface and shear spring-dash pot assembly
// in the plane perpendicular to the normal axis").
//
// The one signature a replacement law must keep (STYLE.md 3.4): a pure
// function of the contact's kinematics, its coefficients and its tangential
// history, returning forces and energy increments. No virtual call: the
// contact system calls it directly for every contact point.
//
// Point stiffness: k_n and k_t of the pair times the point's share s
// (ContactPointGeometry::weight); below, k_n and k_t mean the scaled values.
// Normal:  F_n = max(0, k_n d + c_n d'),  c_n = 2 zeta sqrt(k_n m_eff),
//          zeta the damping ratio whose clamped impact has the restitution
//          asked for (contact_params.h, damping_ratio_for_clamped_
//          restitution). The clamp keeps the force from ever pulling; the
//          bodies let go while the overlap is still positive, and the spring
//          energy left in it is lost (booked as viscous). The clamp alone
//          would raise the restitution of a given zeta (0.5 -> 0.55), which
//          is why zeta is taken from the clamped closed form.
// Tangential (Cundall & Strack 1979): the spring force F_s (history) is
//          first rotated into the current contact plane (normal component
//          removed, magnitude kept), then incremented by -k_t v_t dt. With
//          the dashpot c_t = 2 zeta sqrt(k_t m_eff) the trial force is
//          F_t = F_s - c_t v_t. If |F_t| > mu F_n the contact slides: F_t is
//          scaled to mu F_n along the trial force, and the spring follows
//          the rheology of a Kelvin-Voigt element (spring k_t parallel to
//          dashpot c_t) in series with the Coulomb slider: the element
//          carries the capped force, F_s + c_t u = F_t with u its own rate
//          of deformation, and the slider takes the rest of v_t. Over one
//          step, from the rotated history F_s0,
//            F_s = F_t + alpha (F_s0 - F_t),  alpha = c_t / (k_t dt + c_t),
//          so the spring relaxes towards the cap with the element's time
//          constant c_t / k_t (alpha^n ~ exp(-k_t t / c_t)), and without a
//          dashpot (alpha = 0) it is reset to the cap at once, the
//          Cundall-Strack rule. (Until 2026-11-26 the spring was reset to
//          F_t with a dashpot too: at the onset of sliding it jumped from
//          F_s0 to F_s0 + c_t |v_t|, energy no force had worked in, booked
//          as negative friction loss: -3.4 % of the input in a probe's
//          eccentric corner drop. Storing F_t + c_t v_t, as some
//          history-based models do, parks the dashpot's share in the spring
//          the same way.)
// Energies (per evaluation, step dt):
//   elastic   = 1/2 k_n d^2 + 1/2 |F_s|^2 / k_t (after the update)
//   viscous   = (F_n - k_n d) d' dt  (normal dashpot; >= 0, includes the clamp loss)
//             + (-F_t . v_t dt - change of tangential elastic)   when sticking
//   friction  =  -F_t . v_t dt - change of tangential elastic     when sliding
// so that stored + dissipated equals the work the law's forces do on the
// bodies, up to an O(dt) mismatch (velocities at n-1/2). These viscous and
// friction values are the law's own estimate; ContactSystem does not book
// them: it books the work the forces do with the leapfrog velocity at n
// (contact_system.h) and uses only elastic_J and elastic_tangential_J here.
#pragma once

#include <algorithm>
#include <cmath>

#include "contacts/contact_params.h"
#include "dem_core/types.h"

namespace fq {

struct ContactLawInput {
  double depth_m = 0.0;                      ///< overlap d > 0 along the normal (m)
  double approach_speed_mps = 0.0;           ///< d' (m/s), > 0 while the bodies close in
  Vec3 normal = Vec3::UnitZ();               ///< unit normal from body a to body b, world frame
  Vec3 tangential_velocity_mps = Vec3::Zero();  ///< velocity of b relative to a at the point, in the contact plane, world (m/s)
  double stiffness_scale = 1.0;              ///< share s of the pair's stiffness at this point (-): k = s k_n, s k_t
  double effective_mass_kg = 0.0;            ///< mass the dashpots act on for this point (kg)
  double dt_s = 0.0;                         ///< time step (s)
};

struct ContactLawOutput {
  double normal_force_N = 0.0;               ///< >= 0, acts on b along +normal (on a along -normal)
  Vec3 tangential_force_N = Vec3::Zero();    ///< on b, world frame, in the contact plane (on a: opposite)
  double elastic_J = 0.0;                    ///< energy stored in the point's springs after the update (J)
  double elastic_tangential_J = 0.0;         ///< part of elastic_J in the shear spring, 1/2 |F_s|^2 / k_t (J)
  double viscous_J = 0.0;                    ///< dissipated by the dashpots during this step (J)
  double friction_J = 0.0;                   ///< dissipated by Coulomb sliding during this step (J)
  bool sliding = false;                      ///< the Coulomb cap was active
};

// The point's dashpot coefficients (N s/m): c_n = 2 zeta sqrt(k_n m_eff),
// c_t = 2 zeta sqrt(k_t m_eff) with the scaled stiffnesses (header). A
// function of their own so that a caller whose point keeps the same share
// and mass from step to step can keep them (ContactSystem does: two square
// roots a point, the same bits).
struct ContactDashpots {
  double normal_Nspm = 0.0;
  double tangential_Nspm = 0.0;
};
[[gnu::always_inline]] inline ContactDashpots contact_dashpots(const ContactCoefficients& coeff,
                                                              const ContactLawInput& in) {
  const double kn = in.stiffness_scale * coeff.normal_stiffness_N_per_m;
  const double kt = in.stiffness_scale * coeff.tangential_stiffness_N_per_m;
  const double m = in.effective_mass_kg;
  return {2.0 * coeff.damping_ratio * std::sqrt(kn * m), 2.0 * coeff.damping_ratio * std::sqrt(kt * m)};
}

// io_shear_spring_N: tangential spring force on b (N, world) carried from the
// previous step (zero when the contact is new); updated in place.
// `dashpots` must be contact_dashpots(coeff, in).
// Defined here and always inlined: the contact system calls it for every
// point at every step, and a caller that does not use some outputs
// (ContactSystem books its own losses) then does not pay for them. A plain
// `inline` was not enough: GCC kept it out of line in process_item, a call
// per point that also computed the unused losses (a quotient, two dot
// products), 14 % of frame B's samples (docs/performance_history.md, change 24).
[[gnu::always_inline]] inline ContactLawOutput linear_contact_law(const ContactCoefficients& coeff,
                                                                  const ContactLawInput& in,
                                                                  const ContactDashpots& dashpots,
                                                                  Vec3& io_shear_spring_N) {
  ContactLawOutput out;
  const double kn = in.stiffness_scale * coeff.normal_stiffness_N_per_m;
  const double kt = in.stiffness_scale * coeff.tangential_stiffness_N_per_m;
  const double cn = dashpots.normal_Nspm;
  const double ct = dashpots.tangential_Nspm;
  const double d = in.depth_m;
  const double dd = in.approach_speed_mps;
  const double dt = in.dt_s;

  // Normal: compression only.
  const double spring_n = kn * d;
  const double fn = std::max(0.0, spring_n + cn * dd);
  out.normal_force_N = fn;
  out.viscous_J = (fn - spring_n) * dd * dt;

  // Tangential: rotate the history into the current plane, keep its length.
  Vec3 fs = io_shear_spring_N;
  const double fs_len_old = fs.norm();
  if (fs_len_old > 0.0) {
    fs -= in.normal * in.normal.dot(fs);
    const double len = fs.norm();
    fs = len > 0.0 ? Vec3(fs * (fs_len_old / len)) : Vec3::Zero();
  }
  const double elastic_t_old = kt > 0.0 ? 0.5 * fs.squaredNorm() / kt : 0.0;
  const Vec3 fs_rotated = fs;  // F_s0 of the sliding branch
  const Vec3& vt = in.tangential_velocity_mps;
  fs -= (kt * dt) * vt;
  Vec3 ft = fs - ct * vt;
  const double cap = coeff.friction_coefficient * fn;
  // |F_t| > cap decides sliding, and |F_t| (a square root) is needed only
  // then. When |F_t|^2 < (1 - 1e-6) cap^2, as computed, |F_t|^2 is below
  // cap^2 exactly: the margin is far wider than the rounding of cap^2 and
  // of the product; and where the bound is subnormal, the squares lie on
  // one evenly spaced grid, so |F_t|^2 is at least one spacing below the
  // rounded cap^2, which is within half a spacing of cap^2. A correctly
  // rounded root of a value below cap^2 cannot pass the representable cap,
  // so the root would decide "sticks" too. Elsewhere (and for NaN) the root
  // decides, as before: ft.norm() is sqrt(ft.squaredNorm()).
  const double ft_sq = ft.squaredNorm();
  const bool surely_sticks = ft_sq < (cap * cap) * (1.0 - 1e-6);
  const double ft_len = surely_sticks ? 0.0 : std::sqrt(ft_sq);
  if (!surely_sticks && ft_len > cap) {
    // Sliding: the contact transmits mu F_n along the trial force. The
    // spring-dashpot element in series with the slider carries it: the
    // spring moves from F_s0 towards it by k_t dt / (k_t dt + c_t) (header).
    // Without a dashpot that is all the way (Cundall-Strack), kept as a
    // plain assignment so that such scenes keep their bits.
    out.sliding = true;
    ft = ft_len > 0.0 ? Vec3(ft * (cap / ft_len)) : Vec3::Zero();
    if (ct > 0.0) {
      const double alpha = ct / (kt * dt + ct);
      fs = ft + alpha * (fs_rotated - ft);
    } else {
      fs = ft;
    }
  }
  io_shear_spring_N = fs;
  out.tangential_force_N = ft;
  const double elastic_t = kt > 0.0 ? 0.5 * fs.squaredNorm() / kt : 0.0;
  out.elastic_J = 0.5 * kn * d * d + elastic_t;
  out.elastic_tangential_J = elastic_t;
  const double loss_t = -ft.dot(vt) * dt - (elastic_t - elastic_t_old);
  if (out.sliding) {
    out.friction_J = loss_t;
  } else {
    out.viscous_J += loss_t;
  }
  return out;
}

// The same, computing the dashpot coefficients.
[[gnu::always_inline]] inline ContactLawOutput linear_contact_law(const ContactCoefficients& coeff,
                                                                  const ContactLawInput& in,
                                                                  Vec3& io_shear_spring_N) {
  return linear_contact_law(coeff, in, contact_dashpots(coeff, in), io_shear_spring_N);
}

}  // namespace fq
