// The step loop: explicit central difference (Cundall's scheme) for a set of
// rigid boxes driven by gravity, a ground motion and force providers.
//
// Stages of one step n, in this order (DESIGN.md "One time step", STYLE.md 3.2):
//   1. ExternalForces  clear F and T; add m g and the inertia force -m a_g(t_n)
//   2. Providers       each ForceProvider adds its forces (joints, then contacts)
//   3. Integrate       v(n+1/2) = v(n-1/2) + dt F/m,  x(n+1) = x(n) + dt v(n+1/2);
//                      L(n+1/2) = L(n-1/2) + dt T, orientation drifted with L
//                      fixed (rotation.h); energy bookkeeping of this step
//   4. FinishStep      providers apply deferred topology changes, emit events
//   5. Observe         observers that are due (history rows, frames) run
// Starting: the first half step uses v(-1/2) = v0 - (dt/2) a(0), which makes
// the scheme exact for constant acceleration (free fall, projectile).
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dem_core/body_store.h"
#include "dem_core/bonded_pairs.h"
#include "dem_core/energy_ledger.h"
#include "dem_core/events.h"
#include "dem_core/force_provider.h"
#include "dem_core/ground_motion.h"
#include "dem_core/integrator.h"

namespace fq {

// The most steps a simulation accepts (duration_s / dt_s, rounded): 1e12
// steps take weeks even at a microsecond each, so a larger count is a
// mistake in the units of dt_s or duration_s; and the step counter and
// t = step dt stay exact integers and times far below it (2^53).
inline constexpr double kMaxSimulationSteps = 1e12;

struct SimulationSettings {
  double dt_s = 1e-5;                                  // time step (s)
  double duration_s = 1.0;                             // simulated time (s)
  Vec3 gravity_mps2 = Vec3(0.0, 0.0, -kStandardGravity_mps2);  // (m/s^2)
  // Stage timers run on one step in this many; summary figures are scaled
  // up. Reading a clock every stage of every step would cost more than a
  // small frame's whole step.
  int profile_every_steps = 64;
  // Time integrator (integrator.h). Central difference is the default and
  // the only one the comments above describe step by step.
  Integrator integrator = Integrator::CentralDifference;
  // gsl_rk8pd: absolute and relative error tolerance per internal step.
  double reference_tolerance = 1e-12;
};

enum class Stage : int { ExternalForces = 0, Providers, Integrate, FinishStep, Observe, Count };
const char* stage_name(Stage s);

class Simulation;
class StateWriter;  // dem_core/state_io.h
class StateReader;

// Something that looks at the state every so many steps (history writer,
// frame writer, progress display). Called after FinishStep of step n, with
// the ledger at step n and poses at n+1 (the time reported is t_{n+1}).
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  virtual void on_start(const Simulation& /*sim*/) {}
  virtual void on_sample(const Simulation& sim) = 0;
  virtual void on_finish(const Simulation& /*sim*/) {}
};

enum class RunStatus { Completed, Stopped, Unstable };
const char* run_status_name(RunStatus s);

struct RunResult {
  RunStatus status = RunStatus::Completed;
  std::int64_t steps = 0;            // the run's step count (from its start, across a resume)
  std::int64_t steps_this_call = 0;  // the steps this call of run() took (a resumed run: since the checkpoint)
  double simulated_s = 0.0;
  double wall_s = 0.0;               // wall time of this call
  std::string message;  // for Unstable: where and when it started
};

struct StageProfile {
  std::array<double, static_cast<int>(Stage::Count)> seconds{};  // estimated total per stage (s)
  std::vector<double> provider_seconds;                           // estimated per provider (s)
};

class Simulation {
 public:
  Simulation(BodyStore bodies, SimulationSettings settings, GroundMotion ground_motion = {});
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  // Why the chosen integrator cannot run with the providers added ("" when
  // it can): multi-stage methods need every provider to support trial
  // states. initialize() throws std::invalid_argument with this text.
  std::string integrator_refusal() const;

  // Providers run in the order added (joints before contacts).
  void add_force_provider(std::unique_ptr<ForceProvider> provider);
  // Observer called every `every_steps` steps (and at the start and end).
  void add_observer(StepObserver* observer, std::int64_t every_steps);
  // Monitor called after every step of run() (and at its start), before
  // the observers: for cheap reads of the poses that must not miss a step
  // (a storey's peak drift). Unlike an observer due at that step it does
  // not make the providers gather their energies, and its time is not
  // profiled. It gets on_start and on_finish like an observer (before the
  // observers' on_start, after their on_finish): a progress display is one,
  // asked every step so that it can redraw on wall time whatever the
  // output intervals.
  void add_step_monitor(StepObserver* monitor);

  // Prepares providers, evaluates forces at t = 0 and shifts velocities back
  // half a step. Called by run() and step() if not done yet.
  void initialize();
  // One step; false when the state became non-finite (the step is kept out
  // of the ledger and an Instability event names the first bad body).
  bool step();
  // Runs to settings.duration_s, or until *stop_requested becomes true.
  // Also stops as Unstable when, after a step, the kinetic energy exceeds a
  // million times the energy put in (event mode "energy_blow_up" naming the
  // body with the largest kinetic energy; kBlowUpFactor in simulation.cpp).
  RunResult run(const std::atomic<bool>* stop_requested = nullptr);

  const BodyStore& bodies() const { return bodies_; }
  BodyStore& bodies() { return bodies_; }
  const SimulationSettings& settings() const { return settings_; }
  const GroundMotion& ground_motion() const { return ground_motion_; }
  const EnergyLedger& ledger() const { return ledger_; }
  const EventLog& events() const { return events_; }
  EventLog& events() { return events_; }
  BondedPairs& bonded_pairs() { return bonded_pairs_; }
  const BondedPairs& bonded_pairs() const { return bonded_pairs_; }
  const std::vector<std::unique_ptr<ForceProvider>>& providers() const { return providers_; }
  const StageProfile& profile() const { return profile_; }

  std::int64_t steps_done() const { return step_; }
  double time_s() const { return double(step_) * settings_.dt_s; }  // t of the current poses
  std::int64_t total_steps() const;
  Vec3 ground_acceleration_mps2() const { return ground_acceleration_; }  // a_g at the last force evaluation
  double wall_seconds() const;
  // Steps taken since run() last began (a resumed run: since its checkpoint),
  // for a summary written when run() did not return (an output failure).
  std::int64_t steps_this_run() const { return step_ - run_first_step_; }
  // FNV-1a hash of the bits of every body's position, orientation,
  // velocity and angular momentum: equal hashes mean bitwise-equal states
  // (determinism checks across thread counts and runs).
  std::uint64_t state_hash() const;

  // Checkpoints (dem_core/state_io.h, simulation_state.cpp). save_state
  // writes everything the step loop carries from one step to the next:
  // step counter, flags, ledger and the work sums behind it, ground
  // acceleration, every body's pose, velocities, angular momentum, forces,
  // the event log, the bonded pairs, then each provider's own state (in
  // provider order, under its name). load_state expects a simulation built
  // from the same definition (same bodies and providers, same dt; checked:
  // throws StateFormatError saying what differs) and leaves it exactly in
  // the saved state, so that step()/run() continue bitwise as the saving
  // run would have. Call load_state before the first step (it initializes
  // first); observers are not part of the state.
  void save_state(StateWriter& out) const;
  void load_state(StateReader& in);

 private:
  void compute_forces();
  void evaluate_forces_at(const StepInfo& info);  // external + providers, no timing
  void integrate();
  // Other integrators (integrator.h): velocities at integer steps, forces
  // evaluated at the end of each step (reused by the next), the ledger
  // describing the current poses. See simulation.cpp.
  void initialize_synchronised();
  bool step_synchronised();
  void integrate_synchronised();
  void integrate_runge_kutta4();
  void integrate_gsl();
  void after_forces_synchronised();  // second half kick (velocity Verlet), ledger
  void update_ledger_synchronised(bool first);
  bool record_non_finite();  // Instability event for the first non-finite body; false if all finite
  // ODE form for rk4 / gsl_rk8pd: per free body x(3), q(4), v(3), L(3).
  void ode_load(const double* y);  // writes poses and velocities into the body store
  void ode_store(double* y) const;
  void ode_derivative(double t_s, const double* y, double* dydt);
  friend int simulation_gsl_rhs(double t, const double y[], double dydt[], void* params);

  void finish_step();
  void observe(bool force_all);
  void observe_undue();
  void gather_provider_energy();  // observers not due at this step (final sample)
  bool energy_blew_up() const;    // kinetic energy beyond any physical bound (O(1))
  void record_blow_up();          // Instability event naming the most energetic body

  // Per-chunk partial sums of the integrate stage (chunks of 1024 bodies,
  // added in order so the ledger does not depend on the thread count).
  struct ChunkSums {
    Vec3 momentum_old = Vec3::Zero();  // sum m v(n-1/2) (kg m/s)
    Vec3 momentum_new = Vec3::Zero();  // sum m v(n+1/2)
    double kinetic_old_J = 0.0;        // translational + rotational at n-1/2
    double kinetic_new_J = 0.0;
    double rotational_old_J = 0.0;
    double rotational_new_J = 0.0;
    bool finite = true;
  };

  BodyStore bodies_;
  SimulationSettings settings_;
  GroundMotion ground_motion_;
  std::vector<std::unique_ptr<ForceProvider>> providers_;
  struct ObserverSlot {
    StepObserver* observer;
    std::int64_t every_steps;
  };
  std::vector<ObserverSlot> observers_;
  std::vector<StepObserver*> step_monitors_;
  EnergyLedger ledger_;
  EventLog events_;
  BondedPairs bonded_pairs_;
  std::vector<ChunkSums> chunk_sums_;
  StageProfile profile_;

  bool initialized_ = false;
  bool forces_current_ = false;  // forces at step_ already in the body store
  std::int64_t step_ = 0;
  Vec3 ground_acceleration_ = Vec3::Zero();
  // Work through step n-1, and this step's increment (see energy_ledger.h).
  double work_gravity_through_prev_J_ = 0.0;
  double work_ground_through_prev_J_ = 0.0;
  std::chrono::steady_clock::time_point wall_start_;
  bool wall_started_ = false;
  std::int64_t run_first_step_ = 0;  // step_ when run() last began
  double energy_floor_J_ = 0.0;  // kinetic energy of all free mass at 1 m/s (blow-up guard)

  // Integrators other than central difference.
  std::vector<BodyId> free_bodies_;      // ODE order
  std::vector<double> ode_y_, ode_k_[4], ode_tmp_;
  Vec3 mass_moment0_m_kg_ = Vec3::Zero();  // sum m x at t = 0 (gravity potential)
  Vec3 momentum_prev_ = Vec3::Zero();      // sum m v at the previous step (ground-motion work)
  Vec3 ground_acceleration_prev_ = Vec3::Zero();
  struct GslWorkspace;
  std::unique_ptr<GslWorkspace> gsl_;
};

}  // namespace fq
