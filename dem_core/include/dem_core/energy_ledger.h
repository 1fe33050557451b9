// Energy ledger: where the energy of a run went, and how well it balances.
//
// Bookkeeping that is exact for the leapfrog scheme: with v_n = (v_{n-1/2} +
// v_{n+1/2}) / 2 one has, for every body, KE_{n+1/2} - KE_{n-1/2} =
// dt F_n . v_n. The ledger therefore reports the state at integer step n with
//   kinetic_J  = (KE_{n-1/2} + KE_{n+1/2}) / 2     (also at n = 0)
//   work terms = sum_{0<=k<n} dt (F_k . v_k + F_{k+1} . v_{k+1}) / 2
//              = sum_{k<n} dt F_k . v_k + (1/2) dt F_n . v_n - (1/2) dt F_0 . v_0
// (work from t = 0: only the second half of step 0 counts) so that, for
// forces the engine applies itself (gravity, ground motion), kinetic energy
// and work agree to round-off. Springs, dashpots, plasticity
// and friction book their own stored and dissipated energy (computed from
// their laws, not from the work they do); the mismatch that remains is the
// integration error, reported as the balance error.
//
//   balance_error_J = (stored_J - initial_stored_J) + dissipated_J - input_J
//   stored   = kinetic + gravity potential + elastic
//   input    = work of the ground-motion inertia force + other external work
//   gravity potential = - work of gravity since t = 0
#pragma once

namespace fq {

struct EnergyLedger {
  double kinetic_J = 0.0;               // translational + rotational
  double kinetic_rotational_J = 0.0;    // part of kinetic_J
  double gravity_potential_J = 0.0;     // relative to t = 0
  double elastic_J = 0.0;               // stored in springs (joints, contacts)
  double dissipated_viscous_J = 0.0;    // dashpots (joints, contacts), cumulative
  double dissipated_plastic_J = 0.0;    // plastic / hysteretic spring work, cumulative
  double dissipated_friction_J = 0.0;   // Coulomb sliding, cumulative
  double work_ground_motion_J = 0.0;    // work of -m a_g(t), cumulative
  double work_external_J = 0.0;         // other prescribed loads, cumulative
  double initial_stored_J = 0.0;        // stored_J at t = 0
  double scale_J = 0.0;                 // largest energy magnitude seen so far (for the relative error)

  double stored_J() const { return kinetic_J + gravity_potential_J + elastic_J; }
  double dissipated_J() const { return dissipated_viscous_J + dissipated_plastic_J + dissipated_friction_J; }
  double input_J() const { return work_ground_motion_J + work_external_J; }
  double balance_error_J() const { return (stored_J() - initial_stored_J) + dissipated_J() - input_J(); }
  // |balance error| / largest energy magnitude of the run (0 when nothing moved).
  double balance_error_relative() const;
  // Raise scale_J to the magnitudes present now.
  void update_scale();
};

}  // namespace fq
