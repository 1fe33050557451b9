// The plug through which joints and contacts take part in a time step.
//
// dem_core knows nothing of springs or contact geometry; it calls every
// provider once per stage (one virtual call per provider per step, never per
// spring). Contract of one step n (DESIGN.md "One time step"):
//   accumulate_forces: poses at n, velocities at n-1/2; add forces (N) and
//     torques about the centre of mass (N m), world frame, into
//     bodies.force_N / bodies.torque_Nm. Must not change topology. Events
//     found here (yield, deletion, break) are kept until finish_step.
//   finish_step: after the bodies moved to n+1; apply deferred topology
//     changes in ascending id and append their events to the log.
//   report_energy: add stored elastic energy at n and cumulative dissipated
//     energies to the ledger.
//   save_state / load_state (checkpoints, state_io.h): everything the
//     provider carries from one step to the next (laws' history, broken
//     flags, energy books, contact histories, caches whose content can
//     change results or outputs). load_state is called on a provider built
//     from the same definition, after Simulation::initialize(), and must
//     leave it exactly as the saving provider was, so that a resumed run is
//     bitwise identical to an uninterrupted one. The defaults refuse:
//     a provider that cannot be checkpointed says so.
#pragma once

#include <limits>
#include <string>

#include "dem_core/body_store.h"
#include "dem_core/energy_ledger.h"
#include "dem_core/events.h"
#include "dem_core/linearised_network.h"

namespace fq {

class StateWriter;  // dem_core/state_io.h
class StateReader;

struct StepInfo {
  std::int64_t step = 0;  // n
  double time_s = 0.0;    // t_n (s)
  double dt_s = 0.0;      // (s)
};

// The stiffest mode a provider knows of, for the stable-time-step estimate
// (central difference: dt_crit = 2 / omega_max).
struct StiffestMode {
  double omega_radps = 0.0;  // highest angular frequency (rad/s); 0 = none
  std::string where;         // which element, for the refusal message
};

class ForceProvider {
 public:
  virtual ~ForceProvider() = default;
  virtual const char* name() const = 0;
  // Once, before the first force evaluation, with the final body set.
  virtual void prepare(const BodyStore& /*bodies*/) {}
  virtual void accumulate_forces(BodyStore& bodies, const StepInfo& step) = 0;
  virtual void finish_step(const BodyStore& /*bodies*/, const StepInfo& /*step*/, EventLog& /*events*/) {}
  virtual void report_energy(EnergyLedger& /*ledger*/) const {}
  // The provider's stiffest mode on its own: by default the network of its
  // linearised_springs (as 2 / dt_crit) or its later_stiffest_mode,
  // whichever limits more (src/linearised_network.cpp); a provider that
  // knows its mode otherwise may say so directly.
  virtual StiffestMode stiffest_mode(const BodyStore& bodies) const;
  // For the estimate of the whole scene (io's estimate_stable_time_step):
  // the spring-dashpots acting now, linearised at the current pose
  // (linearised_network.h), appended to `out`; the scene's providers are
  // combined into one network, so that springs of different providers on
  // one body add. `describe_linearised_spring` names the element of a term
  // (its `element` field) for messages.
  virtual void linearised_springs(const BodyStore& /*bodies*/, std::vector<LinearisedSpring>& /*out*/) const {}
  virtual std::string describe_linearised_spring(const BodyStore& /*bodies*/, std::int64_t /*element*/) const {
    return name();
  }
  // Stiffest mode of springs that may form later and are not among
  // linearised_springs (contacts of falling debris); 0 = none.
  virtual StiffestMode later_stiffest_mode(const BodyStore& /*bodies*/) const { return {}; }
  // True when accumulate_forces may be called several times per step at
  // trial states (multi-stage integrators: rk4, gsl_rk8pd, integrator.h):
  // the forces must depend only on the poses, velocities and time passed in,
  // never on history committed by an earlier call (plastic laws, contact
  // tangential springs, events found on the way). The last call of a step
  // is always at the step's final state. Energy books that integrate
  // dashpot power assume one call per step and become approximate.
  virtual bool supports_trial_states() const { return false; }
  // When supports_trial_states() is false: what keeps history, in the
  // words of the case file (which law, which criterion), for the refusal's
  // message; "" names nothing beyond the provider.
  virtual std::string trial_state_obstacle() const { return ""; }
  virtual void save_state(StateWriter& /*out*/) const;
  virtual void load_state(StateReader& /*in*/);
};

}  // namespace fq
