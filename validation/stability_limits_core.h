// Stability limits of the integrators (validation/README.md, "Stability
// limits"): the jointed chain and the instability test, shared by the
// stability_limits program and its test (tests/validation/
// test_stability_limits.cpp), so the test checks the code path behind the
// recorded table.
//
// Instability test. A run starts from rest positions with small velocities
// (mechanical energy E_0, all kinetic) and is unstable when its mechanical
// energy E_n = kinetic + elastic exceeds kEnergyGrowthFactor x E_0 at some
// step (or the state stops being finite). Why this and not a comparison of
// the run's second half with its first: an unstable mode grows by |R| per
// step (R the method's amplification factor) only while the motion is
// linear; on a jointed chain the growth saturates once the bodies spin
// (angles of radians, speeds of 1e6 rad/s), after which the amplitude
// stops growing. Far above the limit that happens within a few dozen steps,
// so both halves of a run hold the saturated motion and a half-against-
// half test calls the run stable (this is what let RK4 pass up to
// omega dt = 3.98 on the chain). An energy threshold does not depend on
// when the growth stops, only on the motion leaving the scale set by E_0:
//   - stable, linear regime: RK4 with |R| <= 1 never raises the energy
//     (in mass-normalised modal coordinates its step matrix is normal, so
//     E_n <= E_0); central difference, velocity Verlet and symplectic Euler
//     conserve a modified energy, and the true one exceeds E_0 at most by
//     1 / (1 - (omega dt / 2)^2) in a mode, which reaches 1e6 only within
//     5e-7 (relative) of omega dt = 2;
//   - unstable: a mode holding a share f of E_0 reaches 1e6 E_0 after
//     ln(1e6 / f) / (2 ln |R|) steps; in 4000 steps this is detected for
//     |R| > 1.0017 (f = 1) .. 1.0035 (f = 1e-6), i.e. omega dt within
//     2.4e-4 .. 4.9e-4 (relative) above 2 sqrt 2 for RK4 and 4e-7 .. 1.5e-6
//     above 2 for central difference: the criterion errs on the stable side
//     by less than that;
//   - the saturated motion of the chain holds far more than 1e6 E_0
//     (E_0 ~ 1e-9 J here), so saturation cannot hide the growth.
// 1e6 is also the factor of the engine's own energy guard in
// Simulation::run() (which step() bypasses).
#pragma once

#include <vector>

#include "dem_core/simulation.h"
#include "joints/joint_system.h"

namespace fq::stability {

constexpr double kEnergyGrowthFactor = 1e6;

// The 5-box chain of tests/joints/test_stable_time_step.cpp: boxes of
// different proportions on a fixed base (body 0), four-corner linear
// joints, undamped, started at rest positions with small random velocities
// (seeded, so every run starts from the same state) that excite every mode.
BodyStore chain_bodies(int links);
void add_chain_joints(JointSystem& joints, const BodyStore& bodies);
// Stiffest mode of the chain at rest (JointSystem::stiffest_mode).
StiffestMode chain_stiffest_mode(int links = 5);

// Mechanical energy of the state in the store (J): translational and
// rotational kinetic energy of every free body plus the elastic energy the
// providers report for their last force evaluation.
double mechanical_energy_J(const Simulation& sim, const std::vector<const ForceProvider*>& elastic);

struct GrowthRun {
  bool unstable = false;           // energy above kEnergyGrowthFactor x E_0, or non-finite
  int steps_run = 0;               // steps taken; the detection step when unstable and stopping there
  double max_energy_ratio = 0.0;   // max over n of E_n / E_0 (E_0 included, so >= 1)
  double max_displacement_m = 0.0; // largest distance of a body centre from its start
  // The former test, for the record: largest displacement in the second
  // half of the run over that in the first (meaningful when the whole run
  // was stepped).
  double halves_ratio = 0.0;
};

// Steps `sim` up to `steps` times from its current state and applies the
// instability test; with stop_when_unstable it returns at detection.
GrowthRun measure_growth(Simulation& sim, const std::vector<const ForceProvider*>& elastic, int steps,
                         bool stop_when_unstable = true, double factor = kEnergyGrowthFactor);

// The 5-box chain (no gravity) stepped with `method` at dt_s.
GrowthRun chain_growth(Integrator method, double dt_s, int steps, bool stop_when_unstable = true);

// Largest dt (s) at which chain_growth finds the chain stable over `steps`
// steps, by bisection in [0.5, 1.5] x estimate_s to 1e-4 relative.
double bisect_stable_dt(Integrator method, double estimate_s, int steps);

// The 5-box chain with a spring-level damping ratio on every spring: its
// stiffest mode (the damped estimate) and the largest distance (m) a body
// moves from its start in `steps` central-difference steps at dt_s
// (test::chain_amplitude: infinity when the step loop stops as unstable).
StiffestMode damped_chain_stiffest_mode(double damping_ratio);
double damped_chain_amplitude(double damping_ratio, double dt_s, int steps);
// test::largest_displacement for any simulation (stability_limits.cpp's
// case scenes): the largest distance (m) of a body from its start over up
// to `steps` steps, early once above stop_m, infinity when unstable.
double largest_displacement(Simulation& sim, int steps, double stop_m = 1.0);
// test::set_small_random_motion: small random velocities and spins (fixed
// seed) on every free body of `store`.
void set_small_random_motion(BodyStore& store);

// Modulus of RK4's amplification factor on the undamped oscillator at
// omega dt = x: |1 + z + z^2/2 + z^3/6 + z^4/24| at z = i x.
double rk4_amplification(double x);

}  // namespace fq::stability
