// Orientation updates for aspherical rigid bodies.
//
// The central-difference (leapfrog) scheme of DESIGN.md treats rotation like
// translation: a "kick" of the world-frame angular momentum L by the torque,
// then a "drift" of the orientation with L held fixed. The drift is the
// torque-free motion of a rigid body with three different principal moments,
// whose exact solution needs elliptic functions. We integrate it with the
// symmetric splitting of Dullweber, Leimkuhler and McLachlan (J. Chem. Phys.
// 107, 5840, 1997): the free-rotor Hamiltonian T = sum_i pi_i^2 / (2 I_i)
// (pi = body-frame angular momentum) is split per axis; the flow of one term
// is an exact rotation about that body axis by angle h pi_i / I_i. The
// sequence x(h/2) y(h/2) z(h) y(h/2) x(h/2) is second order, time reversible
// and symplectic, keeps |L| and the world-frame L exact to round-off and
// keeps the kinetic energy within O(h^2) with no drift. The gyroscopic term
// (I_eta - I_zeta) w_eta w_zeta of seed 001 Eq. (2) is thereby integrated
// exactly within each sub-rotation instead of being added as a force.
#pragma once

#include "dem_core/types.h"

namespace fq {

struct FreeRotorDrift {
  Quat orientation_end;            // q(n+1), unit
  Vec3 angular_velocity_mid_world; // w at the middle of the step (rad/s), world frame
};

// Drift orientation `q` over `dt_s` with world-frame angular momentum
// `angular_momentum_world` held constant; `inverse_inertia_body` holds the
// inverse principal moments (1/(kg m^2)).
FreeRotorDrift free_rotor_drift(const Quat& q, const Vec3& angular_momentum_world, const Vec3& inverse_inertia_body,
                                double dt_s);

// The drifts of n <= 4 bodies at once (body k in lane k, dem_core/lanes.h),
// each bitwise what free_rotor_drift gives for that body: the same
// operations in the same order per lane. A lane whose sub-rotation angle
// leaves the range of fast_sincos's series is redone by free_rotor_drift.
// It runs the SIMD form lane_isa.h chooses; the forms, which give the same
// bits, are also callable by name (free_rotor_drift4_avx2 exists only when
// FQ_HAVE_AVX2_KERNELS, and must run only where AVX2 is available;
// free_rotor_drift4_avx512vl likewise with FQ_HAVE_AVX512VL_KERNELS and
// AVX-512VL).
void free_rotor_drift4(const Quat q[4], const Vec3 angular_momentum_world[4], const Vec3 inverse_inertia_body[4],
                       double dt_s, int n, FreeRotorDrift out[4]);
void free_rotor_drift4_sse2(const Quat q[4], const Vec3 angular_momentum_world[4],
                            const Vec3 inverse_inertia_body[4], double dt_s, int n, FreeRotorDrift out[4]);
void free_rotor_drift4_avx2(const Quat q[4], const Vec3 angular_momentum_world[4],
                            const Vec3 inverse_inertia_body[4], double dt_s, int n, FreeRotorDrift out[4]);
void free_rotor_drift4_avx512vl(const Quat q[4], const Vec3 angular_momentum_world[4],
                                const Vec3 inverse_inertia_body[4], double dt_s, int n, FreeRotorDrift out[4]);

// cos and sin of `angle` (rad); a Taylor series for small angles, where it is
// exact to double precision and several times faster than std::sin/cos.
void fast_sincos(double angle, double& out_cos, double& out_sin);

}  // namespace fq
