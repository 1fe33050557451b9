// Time integrators of the step loop (simulation.h), chosen by
// SimulationSettings::integrator, the case key `time.integrator` or
// `framequake run --integrator NAME`.
//
//   central_difference  Cundall's leapfrog (the default, unchanged): velocities
//                       at half steps, one force evaluation per step, 2nd order
//   velocity_verlet     the same positions as central difference in exact
//                       arithmetic, velocities reported at integer steps
//                       (half kick, drift, forces, half kick), 2nd order
//   symplectic_euler    kick with F(x_n, v_n), then drift with v_{n+1}; no
//                       half-step start, so positions are 1st order
//   forward_euler       x and v both from the state at n; 1st order and
//                       unstable for every dt on an undamped oscillator
//                       (|1 + i w dt| > 1): a teaching reference only
//   rk4                 classical Runge-Kutta, 4 force evaluations per step
//                       (the 4th is reused as the 1st of the next), 4th order
//   gsl_rk8pd           GSL's adaptive Prince-Dormand 8(9) (gsl_odeiv2) with
//                       tolerances SimulationSettings::reference_tolerance:
//                       a reference for small problems, dt is only the
//                       output interval
//
// Multi-stage methods (rk4, gsl_rk8pd) evaluate forces at trial states, so
// every force provider must say it can (ForceProvider::supports_trial_states).
#pragma once

#include <string>
#include <vector>

namespace fq {

enum class Integrator {
  CentralDifference = 0,
  VelocityVerlet,
  SymplecticEuler,
  RungeKutta4,
  ForwardEuler,
  GslRk8pd,
};

// Case-file name ("central_difference", "velocity_verlet", ...).
const char* integrator_name(Integrator integrator);
// False when `name` is none of the names above.
bool parse_integrator(const std::string& name, Integrator& out_integrator);
// "central_difference, velocity_verlet, ..." for error messages.
std::string integrator_names_list();
// The same names, one per element.
std::vector<std::string> integrator_names();
// True for methods that evaluate forces at trial states within a step.
bool integrator_is_multistage(Integrator integrator);

// Stability limit of the method on an undamped linear oscillator of angular
// frequency w: stable for w dt <= factor. Central difference, velocity
// Verlet and symplectic Euler (the same one-step map up to the velocity
// reported): 2. RK4: 2 sqrt(2) (where its stability polynomial
// 1 + z + z^2/2 + z^3/6 + z^4/24 leaves the unit disc on the imaginary
// axis). Forward Euler: 0 (|1 + i w dt| > 1 for every dt > 0). gsl_rk8pd:
// infinity (it chooses its own internal steps).
double integrator_stability_factor(Integrator integrator);

}  // namespace fq
