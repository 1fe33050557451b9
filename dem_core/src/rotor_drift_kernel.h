// free_rotor_drift4 (rotation.h), written once and compiled once per SIMD
// form (dem_core/lanes.h): by rotor_drift_sse2.cpp for the x86-64 baseline,
// by rotor_drift_avx2.cpp with -mavx2 and by rotor_drift_avx512vl.cpp with
// -mavx512f -mavx512vl; FQ_LANE_KERNEL(name) names each form's function. No
// include guard: this file is the body of those translation units and is
// included by nothing else.
//
// Each function below is the lane form of the scalar code of rotation.cpp
// (and of Eigen's quaternion operations it calls), operation for operation.
#include "dem_core/quat_lanes.h"
#include "dem_core/rotation.h"
#include "rotation_series.h"

#ifndef FQ_LANE_KERNEL
#error "define FQ_LANE_KERNEL(name) before including rotor_drift_kernel.h"
#endif

namespace fq {

namespace {

using lanes::v4d;
using lanes::v4m;
using namespace rotation_series;

// a x b as Eigen's cross3_impl writes it.
[[gnu::always_inline]] inline void cross(const v4d a[3], const v4d b[3], v4d out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

// q * v for a unit quaternion (vec, w): Eigen's QuaternionBase::_transformVector,
// uv = vec x v, uv += uv, v + w uv + vec x uv.
[[gnu::always_inline]] inline void rotate_vector(const v4d vec[3], v4d w, const v4d v[3], v4d out[3]) {
  v4d uv[3];
  cross(vec, v, uv);
  for (int r = 0; r < 3; ++r) uv[r] = uv[r] + uv[r];
  v4d c[3];
  cross(vec, uv, c);
  for (int r = 0; r < 3; ++r) out[r] = v[r] + w * uv[r] + c[r];
}

// fast_sincos's series branch; `valid` loses the lanes outside its range.
[[gnu::always_inline]] inline void sincos_series(v4d angle, v4d& out_cos, v4d& out_sin, v4m& valid) {
  valid = valid & (lanes::abs(angle) < kSeriesAngle);
  const v4d a2 = angle * angle;
  out_sin = angle * (1.0 - a2 * k6 * (1.0 - a2 * k20 * (1.0 - a2 * k42)));
  out_cos = 1.0 - a2 * 0.5 * (1.0 - a2 * k12 * (1.0 - a2 * k30));
}

// rotate_about_body_axis; q holds (x, y, z, w).
[[gnu::always_inline]] inline void rotate_about_body_axis(int axis, double h, const v4d inverse_inertia[3], v4d q[4],
                                                          v4d pi[3], v4m& valid) {
  const v4d theta = h * pi[axis] * inverse_inertia[axis];
  v4d ch, sh;
  sincos_series(0.5 * theta, ch, sh, valid);
  const v4d c = 1.0 - 2.0 * sh * sh, s = 2.0 * sh * ch;
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const v4d pa = pi[a], pb = pi[b];
  pi[a] = c * pa + s * pb;
  pi[b] = -s * pa + c * pb;
  const v4d w = q[3];
  const v4d v[3] = {q[0], q[1], q[2]};
  q[3] = ch * w - sh * v[axis];
  q[axis] = ch * v[axis] + sh * w;
  q[a] = ch * v[a] + sh * v[b];
  q[b] = ch * v[b] - sh * v[a];
}

}  // namespace

void FQ_LANE_KERNEL(free_rotor_drift4_)(const Quat q0[4], const Vec3 angular_momentum_world[4], const Vec3 inverse_inertia_body[4],
                       double dt_s, int n, FreeRotorDrift out[4]) {
  // Lanes past n hold the identity at rest (harmless, and never written out).
  const Quat* qp[lanes::kWidth];
  static const Vec3 zero = Vec3::Zero();
  const Vec3 *lp[lanes::kWidth], *ip[lanes::kWidth];
  for (int k = 0; k < lanes::kWidth; ++k) {
    qp[k] = &q0[k < n ? k : 0];
    lp[k] = k < n ? &angular_momentum_world[k] : &zero;
    ip[k] = k < n ? &inverse_inertia_body[k] : &zero;
  }
  const lanes::QuatLanes start = lanes::load_quats(qp, n);
  v4d q[4] = {start.x, start.y, start.z, start.w}, momentum[3], inverse_inertia[3];
  for (int r = 0; r < 3; ++r) {
    momentum[r] = lanes::make((*lp[0])[r], (*lp[1])[r], (*lp[2])[r], (*lp[3])[r]);
    inverse_inertia[r] = lanes::make((*ip[0])[r], (*ip[1])[r], (*ip[2])[r], (*ip[3])[r]);
  }

  // pi = q^-1 L (the conjugate's vector part negated, exactly as Eigen's conjugate()).
  const v4d conj_vec[3] = {-q[0], -q[1], -q[2]};
  v4d pi[3];
  rotate_vector(conj_vec, q[3], momentum, pi);
  const double h = dt_s;
  v4m valid = lanes::mask(true, true, true, true);
  rotate_about_body_axis(0, 0.5 * h, inverse_inertia, q, pi, valid);
  rotate_about_body_axis(1, 0.5 * h, inverse_inertia, q, pi, valid);
  rotate_about_body_axis(2, 0.5 * h, inverse_inertia, q, pi, valid);
  const v4d w_body[3] = {inverse_inertia[0] * pi[0], inverse_inertia[1] * pi[1], inverse_inertia[2] * pi[2]};
  v4d w_mid[3];
  rotate_vector(q, q[3], w_body, w_mid);
  rotate_about_body_axis(2, 0.5 * h, inverse_inertia, q, pi, valid);
  rotate_about_body_axis(1, 0.5 * h, inverse_inertia, q, pi, valid);
  rotate_about_body_axis(0, 0.5 * h, inverse_inertia, q, pi, valid);
  // q.normalize()
  const lanes::QuatLanes unit = lanes::normalized({q[0], q[1], q[2], q[3]});
  q[0] = unit.x, q[1] = unit.y, q[2] = unit.z, q[3] = unit.w;

  double res[7][lanes::kWidth];
  for (int c = 0; c < 4; ++c) lanes::store(res[c], q[c]);
  for (int r = 0; r < 3; ++r) lanes::store(res[4 + r], w_mid[r]);
  for (int k = 0; k < n; ++k) {
    if (!lanes::lane(valid, k)) {
      out[k] = free_rotor_drift(q0[k], angular_momentum_world[k], inverse_inertia_body[k], dt_s);
      continue;
    }
    out[k].orientation_end = Quat(res[3][k], res[0][k], res[1][k], res[2][k]);
    out[k].angular_velocity_mid_world = Vec3(res[4][k], res[5][k], res[6][k]);
  }
}

}  // namespace fq
