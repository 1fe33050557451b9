// Four doubles in SIMD lanes, for loops whose items are independent and
// alike: the points of a joint (joints/src/joint_lane_kernels.h; a
// four-corner joint is one v4d) and the rotation drift of four bodies
// (dem_core/src/rotor_drift_kernel.h).
//
// Two forms of the same types and operations:
//   - SSE2 (the x86-64 baseline every build targets): two registers per v4d,
//     written with intrinsics, because GCC's generic vectors wider than the
//     target build their scalar broadcasts and lane masks through the stack,
//     where mismatched store and load widths stall the pipeline;
//   - AVX2 (one 256-bit register per v4d), used where the translation unit
//     is compiled with -mavx2: the kernels are compiled once in each form
//     and chosen at run time (dem_core/lane_isa.h). The AVX-512VL form is
//     this code compiled with -mavx512f -mavx512vl as well (32 registers);
//     it has its own namespace but no code of its own here.
// Each form lives in its own inline namespace, so the forms never meet at
// link time.
//
// Every operation is the IEEE operation of one lane, and comparisons are
// the ordered ones of C (false when either side is NaN), so a lane gives
// the bits that the scalar code gives for one item, written in the same
// order (FMA contraction is off, top-level CMakeLists.txt), in either form.
#pragma once

#include <immintrin.h>

#include <cstdint>

// The inline namespace of this translation unit's form (quat_lanes.h and
// the kernels put their own lane helpers in it too).
#if defined(__AVX512VL__)
#define FQ_LANES_ISA avx512vl
#elif defined(__AVX2__)
#define FQ_LANES_ISA avx2
#else
#define FQ_LANES_ISA sse2
#endif

#define FQ_LANES_INLINE [[gnu::always_inline]] inline

namespace fq::lanes {

constexpr int kWidth = 4;

inline namespace FQ_LANES_ISA {

// ---- what each form writes with its own registers -------------------------
#if defined(__AVX2__)

struct v4d {
  __m256d v;
  double operator[](int i) const {
    alignas(32) double lanes[kWidth];
    _mm256_store_pd(lanes, v);
    return lanes[i];
  }
};
// Lane masks: all bits set (true) or clear (false) per lane.
struct v4m {
  __m256d v;
};

FQ_LANES_INLINE v4d splat(double x) { return {_mm256_set1_pd(x)}; }
FQ_LANES_INLINE v4d load(const double* p) { return {_mm256_loadu_pd(p)}; }
FQ_LANES_INLINE v4d make(double l0, double l1, double l2, double l3) { return {_mm256_set_pd(l3, l2, l1, l0)}; }
FQ_LANES_INLINE void store(double* p, v4d v) { _mm256_storeu_pd(p, v.v); }
FQ_LANES_INLINE v4d operator+(v4d a, v4d b) { return {_mm256_add_pd(a.v, b.v)}; }
FQ_LANES_INLINE v4d operator-(v4d a, v4d b) { return {_mm256_sub_pd(a.v, b.v)}; }
FQ_LANES_INLINE v4d operator*(v4d a, v4d b) { return {_mm256_mul_pd(a.v, b.v)}; }
FQ_LANES_INLINE v4d operator/(v4d a, v4d b) { return {_mm256_div_pd(a.v, b.v)}; }
FQ_LANES_INLINE v4d operator-(v4d a) { return {_mm256_xor_pd(a.v, _mm256_set1_pd(-0.0))}; }
FQ_LANES_INLINE v4d abs(v4d a) { return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)}; }
FQ_LANES_INLINE v4d sqrt(v4d a) { return {_mm256_sqrt_pd(a.v)}; }
// SSE2's cmpgt / cmplt / cmpge predicates (_OS: ordered, signalling, as C's
// relational operators).
FQ_LANES_INLINE v4m operator>(v4d a, v4d b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OS)}; }
FQ_LANES_INLINE v4m operator<(v4d a, v4d b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OS)}; }
FQ_LANES_INLINE v4m operator>=(v4d a, v4d b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GE_OS)}; }
FQ_LANES_INLINE v4m operator|(v4m a, v4m b) { return {_mm256_or_pd(a.v, b.v)}; }
FQ_LANES_INLINE v4m operator&(v4m a, v4m b) { return {_mm256_and_pd(a.v, b.v)}; }
FQ_LANES_INLINE v4m and_not(v4m a, v4m b) { return {_mm256_andnot_pd(b.v, a.v)}; }
FQ_LANES_INLINE v4d select(v4m m, v4d a, v4d b) {
  return {_mm256_or_pd(_mm256_and_pd(m.v, a.v), _mm256_andnot_pd(m.v, b.v))};
}
FQ_LANES_INLINE v4m mask(bool l0, bool l1, bool l2, bool l3) {
  auto bits = [](bool x) { return x ? std::int64_t(-1) : std::int64_t(0); };
  return {_mm256_castsi256_pd(_mm256_set_epi64x(bits(l3), bits(l2), bits(l1), bits(l0)))};
}
FQ_LANES_INLINE bool all_of(v4m m) { return _mm256_movemask_pd(m.v) == 15; }
FQ_LANES_INLINE bool lane(v4m m, int i) { return (_mm256_movemask_pd(m.v) >> i) & 1; }
// p[3 i] = x[i], p[3 i + 1] = y[i], p[3 i + 2] = z[i] for the four lanes
// (twelve doubles: lanes of three columns to records of three).
FQ_LANES_INLINE void store_interleaved3(double* p, v4d x, v4d y, v4d z) {
  const __m256d xy = _mm256_unpacklo_pd(x.v, y.v);      // x0 y0 | x2 y2
  const __m256d zx = _mm256_blend_pd(z.v, x.v, 0b1010);  // z0 x1 | z2 x3
  const __m256d yz = _mm256_unpackhi_pd(y.v, z.v);      // y1 z1 | y3 z3
  _mm256_storeu_pd(p, _mm256_permute2f128_pd(xy, zx, 0x20));
  _mm256_storeu_pd(p + 4, _mm256_permute2f128_pd(yz, xy, 0x30));
  _mm256_storeu_pd(p + 8, _mm256_permute2f128_pd(zx, yz, 0x31));
}
// Rows to columns: afterwards a = (a0, b0, c0, d0), b = (a1, b1, c1, d1), ...
FQ_LANES_INLINE void transpose(v4d& a, v4d& b, v4d& c, v4d& d) {
  const __m256d ab_lo = _mm256_unpacklo_pd(a.v, b.v), ab_hi = _mm256_unpackhi_pd(a.v, b.v);
  const __m256d cd_lo = _mm256_unpacklo_pd(c.v, d.v), cd_hi = _mm256_unpackhi_pd(c.v, d.v);
  a.v = _mm256_permute2f128_pd(ab_lo, cd_lo, 0x20);
  b.v = _mm256_permute2f128_pd(ab_hi, cd_hi, 0x20);
  c.v = _mm256_permute2f128_pd(ab_lo, cd_lo, 0x31);
  d.v = _mm256_permute2f128_pd(ab_hi, cd_hi, 0x31);
}

#else  // SSE2

struct v4d {
  __m128d lo, hi;
  double operator[](int i) const {
    const __m128d h = i < 2 ? lo : hi;
    return (i & 1) ? _mm_cvtsd_f64(_mm_unpackhi_pd(h, h)) : _mm_cvtsd_f64(h);
  }
};
// Lane masks: all bits set (true) or clear (false) per lane.
struct v4m {
  __m128d lo, hi;
};

FQ_LANES_INLINE v4d splat(double x) {
  const __m128d v = _mm_set1_pd(x);
  return {v, v};
}
FQ_LANES_INLINE v4d load(const double* p) { return {_mm_loadu_pd(p), _mm_loadu_pd(p + 2)}; }
// Lanes from four scalars. Built in registers: four 8-byte stores read back
// by a 16-byte load would miss store-to-load forwarding and stall.
FQ_LANES_INLINE v4d make(double l0, double l1, double l2, double l3) { return {_mm_set_pd(l1, l0), _mm_set_pd(l3, l2)}; }
FQ_LANES_INLINE void store(double* p, v4d v) {
  _mm_storeu_pd(p, v.lo);
  _mm_storeu_pd(p + 2, v.hi);
}
FQ_LANES_INLINE v4d operator+(v4d a, v4d b) { return {_mm_add_pd(a.lo, b.lo), _mm_add_pd(a.hi, b.hi)}; }
FQ_LANES_INLINE v4d operator-(v4d a, v4d b) { return {_mm_sub_pd(a.lo, b.lo), _mm_sub_pd(a.hi, b.hi)}; }
FQ_LANES_INLINE v4d operator*(v4d a, v4d b) { return {_mm_mul_pd(a.lo, b.lo), _mm_mul_pd(a.hi, b.hi)}; }
FQ_LANES_INLINE v4d operator/(v4d a, v4d b) { return {_mm_div_pd(a.lo, b.lo), _mm_div_pd(a.hi, b.hi)}; }
// -a: the sign bit flipped, as the scalar unary minus does.
FQ_LANES_INLINE v4d operator-(v4d a) {
  const __m128d sign = _mm_set1_pd(-0.0);
  return {_mm_xor_pd(a.lo, sign), _mm_xor_pd(a.hi, sign)};
}
FQ_LANES_INLINE v4d abs(v4d a) {
  const __m128d sign = _mm_set1_pd(-0.0);
  return {_mm_andnot_pd(sign, a.lo), _mm_andnot_pd(sign, a.hi)};
}
FQ_LANES_INLINE v4d sqrt(v4d a) { return {_mm_sqrt_pd(a.lo), _mm_sqrt_pd(a.hi)}; }
FQ_LANES_INLINE v4m operator>(v4d a, v4d b) { return {_mm_cmpgt_pd(a.lo, b.lo), _mm_cmpgt_pd(a.hi, b.hi)}; }
FQ_LANES_INLINE v4m operator<(v4d a, v4d b) { return {_mm_cmplt_pd(a.lo, b.lo), _mm_cmplt_pd(a.hi, b.hi)}; }
FQ_LANES_INLINE v4m operator>=(v4d a, v4d b) { return {_mm_cmpge_pd(a.lo, b.lo), _mm_cmpge_pd(a.hi, b.hi)}; }
FQ_LANES_INLINE v4m operator|(v4m a, v4m b) { return {_mm_or_pd(a.lo, b.lo), _mm_or_pd(a.hi, b.hi)}; }
FQ_LANES_INLINE v4m operator&(v4m a, v4m b) { return {_mm_and_pd(a.lo, b.lo), _mm_and_pd(a.hi, b.hi)}; }
// a and not b
FQ_LANES_INLINE v4m and_not(v4m a, v4m b) { return {_mm_andnot_pd(b.lo, a.lo), _mm_andnot_pd(b.hi, a.hi)}; }
// m ? a : b, per lane
FQ_LANES_INLINE v4d select(v4m m, v4d a, v4d b) {
  return {_mm_or_pd(_mm_and_pd(m.lo, a.lo), _mm_andnot_pd(m.lo, b.lo)),
          _mm_or_pd(_mm_and_pd(m.hi, a.hi), _mm_andnot_pd(m.hi, b.hi))};
}
FQ_LANES_INLINE v4m mask(bool l0, bool l1, bool l2, bool l3) {
  auto bits = [](bool x) { return x ? std::int64_t(-1) : std::int64_t(0); };
  return {_mm_castsi128_pd(_mm_set_epi64x(bits(l1), bits(l0))),
          _mm_castsi128_pd(_mm_set_epi64x(bits(l3), bits(l2)))};
}
FQ_LANES_INLINE bool all_of(v4m m) { return (_mm_movemask_pd(m.lo) & _mm_movemask_pd(m.hi)) == 3; }
FQ_LANES_INLINE bool lane(v4m m, int i) {
  return ((i < 2 ? _mm_movemask_pd(m.lo) : _mm_movemask_pd(m.hi)) >> (i & 1)) & 1;
}
FQ_LANES_INLINE void store_interleaved3(double* p, v4d x, v4d y, v4d z) {
  _mm_storeu_pd(p, _mm_unpacklo_pd(x.lo, y.lo));       // x0 y0
  _mm_storeu_pd(p + 2, _mm_move_sd(x.lo, z.lo));       // z0 x1
  _mm_storeu_pd(p + 4, _mm_unpackhi_pd(y.lo, z.lo));   // y1 z1
  _mm_storeu_pd(p + 6, _mm_unpacklo_pd(x.hi, y.hi));   // x2 y2
  _mm_storeu_pd(p + 8, _mm_move_sd(x.hi, z.hi));       // z2 x3
  _mm_storeu_pd(p + 10, _mm_unpackhi_pd(y.hi, z.hi));  // y3 z3
}
FQ_LANES_INLINE void transpose(v4d& a, v4d& b, v4d& c, v4d& d) {
  const v4d a0 = a, b0 = b, c0 = c, d0 = d;
  a = {_mm_unpacklo_pd(a0.lo, b0.lo), _mm_unpacklo_pd(c0.lo, d0.lo)};
  b = {_mm_unpackhi_pd(a0.lo, b0.lo), _mm_unpackhi_pd(c0.lo, d0.lo)};
  c = {_mm_unpacklo_pd(a0.hi, b0.hi), _mm_unpacklo_pd(c0.hi, d0.hi)};
  d = {_mm_unpackhi_pd(a0.hi, b0.hi), _mm_unpackhi_pd(c0.hi, d0.hi)};
}

#endif

// ---- the same in both forms, from the above --------------------------------

// n (< kWidth) values from p, zeros in the other lanes; and back.
FQ_LANES_INLINE v4d load_partial(const double* p, int n) {
  double tmp[kWidth] = {0.0, 0.0, 0.0, 0.0};
  for (int i = 0; i < n; ++i) tmp[i] = p[i];
  return load(tmp);
}
FQ_LANES_INLINE void store_partial(double* p, v4d v, int n) {
  double tmp[kWidth];
  store(tmp, v);
  for (int i = 0; i < n; ++i) p[i] = tmp[i];
}

FQ_LANES_INLINE v4d operator+(double a, v4d b) { return splat(a) + b; }
FQ_LANES_INLINE v4d operator-(double a, v4d b) { return splat(a) - b; }
FQ_LANES_INLINE v4d operator*(double a, v4d b) { return splat(a) * b; }
FQ_LANES_INLINE v4d operator+(v4d a, double b) { return a + splat(b); }
FQ_LANES_INLINE v4d operator-(v4d a, double b) { return a - splat(b); }
FQ_LANES_INLINE v4d operator*(v4d a, double b) { return a * splat(b); }
FQ_LANES_INLINE v4d operator/(v4d a, double b) { return a / splat(b); }
FQ_LANES_INLINE v4m operator>(v4d a, double b) { return a > splat(b); }
FQ_LANES_INLINE v4m operator<(v4d a, double b) { return a < splat(b); }
FQ_LANES_INLINE v4m operator>=(v4d a, double b) { return a >= splat(b); }

}  // namespace FQ_LANES_ISA

}  // namespace fq::lanes

#undef FQ_LANES_INLINE
