// Four quaternions in SIMD lanes (dem_core/lanes.h): the Eigen quaternion
// operations the step uses, written out in the order Eigen 3.4's SSE2 code
// evaluates them, so that each lane gives the bits of the Eigen call for
// that quaternion (tests/dem_core/test_quat_lanes.cpp checks every function
// against Eigen on random input). Coefficients (x, y, z, w) as Eigen stores them.
#pragma once

#include "dem_core/lanes.h"
#include "dem_core/types.h"

namespace fq::lanes {
inline namespace FQ_LANES_ISA {

struct QuatLanes {
  v4d x, y, z, w;
};

// Lane k from q[k] for k < n; the identity in the other lanes.
[[gnu::always_inline]] inline QuatLanes load_quats(const Quat* const q[4], int n) {
  static constexpr double kIdentity[4] = {0.0, 0.0, 0.0, 1.0};  // (x, y, z, w)
  const double* c[kWidth];
  for (int k = 0; k < kWidth; ++k) c[k] = k < n ? q[k]->coeffs().data() : kIdentity;
  // Each quaternion's four coefficients in one load, turned into lanes of x,
  // y, z and w by a transpose: a third of the instructions of sixteen
  // scalar loads put into lanes one by one.
  v4d x = load(c[0]), y = load(c[1]), z = load(c[2]), w = load(c[3]);
  transpose(x, y, z, w);
  return {x, y, z, w};
}

// a * b: Eigen's quat_product for double with SSE2 (Geometry_SIMD.h), whose
// paddsub(u, v) is (u0 - v0, u1 + v1).
[[gnu::always_inline]] inline QuatLanes product(const QuatLanes& a, const QuatLanes& b) {
  return {(a.w * b.x + a.y * b.z) - (a.z * b.y - a.x * b.w), (a.w * b.y + a.y * b.w) + (a.z * b.x - a.x * b.z),
          (a.w * b.z - a.y * b.x) + (a.z * b.w + a.x * b.y), (a.w * b.w - a.y * b.y) - (a.z * b.z + a.x * b.x)};
}

// a.dot(b) and squaredNorm(): Eigen sums the four products in two SSE2
// pairs, (x + z) + (y + w).
[[gnu::always_inline]] inline v4d dot(const QuatLanes& a, const QuatLanes& b) {
  return (a.x * b.x + a.z * b.z) + (a.y * b.y + a.w * b.w);
}

// q.normalize(): every coefficient divided by the norm when its square is > 0.
[[gnu::always_inline]] inline QuatLanes normalized(const QuatLanes& q) {
  const v4d norm2 = dot(q, q);
  const v4d norm = sqrt(norm2);
  const v4m positive = norm2 > 0.0;
  return {select(positive, q.x / norm, q.x), select(positive, q.y / norm, q.y), select(positive, q.z / norm, q.z),
          select(positive, q.w / norm, q.w)};
}

// q.toRotationMatrix(), column-major: m[3 c + r] is row r of column c.
[[gnu::always_inline]] inline void to_rotation_matrix(const QuatLanes& q, v4d m[9]) {
  const v4d tx = 2.0 * q.x, ty = 2.0 * q.y, tz = 2.0 * q.z;
  const v4d twx = tx * q.w, twy = ty * q.w, twz = tz * q.w;
  const v4d txx = tx * q.x, txy = ty * q.x, txz = tz * q.x;
  const v4d tyy = ty * q.y, tyz = tz * q.y, tzz = tz * q.z;
  m[0] = 1.0 - (tyy + tzz);
  m[3] = txy - twz;
  m[6] = txz + twy;
  m[1] = txy + twz;
  m[4] = 1.0 - (txx + tzz);
  m[7] = tyz - twx;
  m[2] = txz - twy;
  m[5] = tyz + twx;
  m[8] = 1.0 - (txx + tyy);
}

}  // namespace FQ_LANES_ISA
}  // namespace fq::lanes
