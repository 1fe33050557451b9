#include "contacts/linear_contact_law.h"

#include <cmath>

namespace fq {

ContactLawOutput linear_contact_law(const ContactCoefficients& coeff, const ContactLawInput& in,
                                    Vec3& io_shear_spring_N) {
  ContactLawOutput out;
  const double kn = in.stiffness_scale * coeff.normal_stiffness_N_per_m;
  const double kt = in.stiffness_scale * coeff.tangential_stiffness_N_per_m;
  const double m = in.effective_mass_kg;
  const double cn = 2.0 * coeff.damping_ratio * std::sqrt(kn * m);
  const double ct = 2.0 * coeff.damping_ratio * std::sqrt(kt * m);
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
  const Vec3& vt = in.tangential_velocity_mps;
  fs -= (kt * dt) * vt;
  Vec3 ft = fs - ct * vt;
  const double cap = coeff.friction_coefficient * fn;
  const double ft_len = ft.norm();
  if (ft_len > cap) {
    // Sliding: the contact transmits mu F_n along the trial force, and the
    // spring is reset to carry exactly that force (Cundall-Strack). Storing
    // fs = ft + c_t v_t instead would park the dashpot's share in the spring:
    // energy that no elastic unloading gives back, and a jerk of c_t v_t when
    // sliding stops.
    out.sliding = true;
    ft = ft_len > 0.0 ? Vec3(ft * (cap / ft_len)) : Vec3::Zero();
    fs = ft;
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

}  // namespace fq
