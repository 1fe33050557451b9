#include "dem_core/rotation.h"

#include <cmath>

#include "dem_core/lane_isa.h"
#include "rotation_series.h"

namespace fq {

using namespace rotation_series;

void fast_sincos(double angle, double& out_cos, double& out_sin) {
  if (std::abs(angle) < kSeriesAngle) {
    const double a2 = angle * angle;
    out_sin = angle * (1.0 - a2 * k6 * (1.0 - a2 * k20 * (1.0 - a2 * k42)));
    out_cos = 1.0 - a2 * 0.5 * (1.0 - a2 * k12 * (1.0 - a2 * k30));
  } else {
    out_sin = std::sin(angle);
    out_cos = std::cos(angle);
  }
}

namespace {

// Exact flow of T_axis = pi_axis^2 / (2 I_axis) for time h: the body turns
// about its own axis by theta = h pi_axis / I_axis. Orientation q <- q * exp,
// and the body-frame momentum turns the opposite way, pi <- Rot(theta)^T pi.
inline void rotate_about_body_axis(int axis, double h, const Vec3& inverse_inertia, Quat& q, Vec3& pi) {
  const double theta = h * pi[axis] * inverse_inertia[axis];
  // One series for the half angle; the whole angle by the double-angle
  // formulas (exact identities, one rounding each).
  double ch, sh;
  fast_sincos(0.5 * theta, ch, sh);
  const double c = 1.0 - 2.0 * sh * sh, s = 2.0 * sh * ch;
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const double pa = pi[a], pb = pi[b];
  pi[a] = c * pa + s * pb;
  pi[b] = -s * pa + c * pb;
  // q <- q * (ch, sh e_axis), written out: the step quaternion has two
  // non-zero components, and v x e_axis = (0, v_b, -v_a) in the order
  // (axis, a, b).
  const double w = q.w();
  Vec3 v = q.vec();
  q.w() = ch * w - sh * v[axis];
  q.vec()[axis] = ch * v[axis] + sh * w;
  q.vec()[a] = ch * v[a] + sh * v[b];
  q.vec()[b] = ch * v[b] - sh * v[a];
}

}  // namespace

FreeRotorDrift free_rotor_drift(const Quat& q0, const Vec3& angular_momentum_world, const Vec3& inverse_inertia_body,
                                double dt_s) {
  Quat q = q0;
  Vec3 pi = q.conjugate() * angular_momentum_world;  // body frame
  const double h = dt_s;
  rotate_about_body_axis(0, 0.5 * h, inverse_inertia_body, q, pi);
  rotate_about_body_axis(1, 0.5 * h, inverse_inertia_body, q, pi);
  rotate_about_body_axis(2, 0.5 * h, inverse_inertia_body, q, pi);
  // Middle of the symmetric sequence: a second-order estimate of the pose at
  // n+1/2, used for the mid-step angular velocity that dashpots read.
  const Vec3 w_mid_world = q * inverse_inertia_body.cwiseProduct(pi);
  rotate_about_body_axis(2, 0.5 * h, inverse_inertia_body, q, pi);
  rotate_about_body_axis(1, 0.5 * h, inverse_inertia_body, q, pi);
  rotate_about_body_axis(0, 0.5 * h, inverse_inertia_body, q, pi);
  q.normalize();
  return {q, w_mid_world};
}

void free_rotor_drift4(const Quat q0[4], const Vec3 angular_momentum_world[4], const Vec3 inverse_inertia_body[4],
                       double dt_s, int n, FreeRotorDrift out[4]) {
  switch (active_lane_isa()) {
#if FQ_HAVE_AVX512VL_KERNELS
    case LaneIsa::Avx512vl:
      return free_rotor_drift4_avx512vl(q0, angular_momentum_world, inverse_inertia_body, dt_s, n, out);
#endif
#if FQ_HAVE_AVX2_KERNELS
    case LaneIsa::Avx2:
      return free_rotor_drift4_avx2(q0, angular_momentum_world, inverse_inertia_body, dt_s, n, out);
#endif
    default:
      break;
  }
  free_rotor_drift4_sse2(q0, angular_momentum_world, inverse_inertia_body, dt_s, n, out);
}

}  // namespace fq
