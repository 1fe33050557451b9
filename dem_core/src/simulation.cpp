#include "dem_core/simulation.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "dem_core/rotation.h"

namespace fq {

const char* stage_name(Stage s) {
  switch (s) {
    case Stage::ExternalForces: return "external_forces";
    case Stage::Providers: return "providers";
    case Stage::Integrate: return "integrate";
    case Stage::FinishStep: return "finish_step";
    case Stage::Observe: return "observe";
    case Stage::Count: break;
  }
  return "unknown";
}

const char* run_status_name(RunStatus s) {
  switch (s) {
    case RunStatus::Completed: return "completed";
    case RunStatus::Stopped: return "stopped";
    case RunStatus::Unstable: return "unstable";
  }
  return "unknown";
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// Bodies are summed in fixed chunks and the chunk sums added in order, so the
// ledger is bitwise the same whatever the number of threads.
constexpr std::size_t kReductionChunk = 1024;

// Energy blow-up guard. With elastic energy >= 0 and dissipation >= 0 (every
// spring, dashpot and friction law of the design), the energy balance
// (energy_ledger.h) bounds the kinetic energy by what the system was given:
//   KE(t) <= available(t) = initial_stored + W_gravity(t) + W_ground(t) + W_external(t).
// A stable leapfrog run breaks this only by its integration error, a small
// fraction of the energies involved. The run is stopped as unstable when
//   KE(t) - available(t) > kBlowUpFactor * E_scale,
//   E_scale = max(|initial_stored|, |W_gravity|, |W_ground|, |W_external|, E_floor),
// E_scale deliberately not containing KE itself (a runaway KE would raise its
// own threshold). kBlowUpFactor = 1e6: no integration error of a run that
// still means anything is a million times the energy in play. E_floor is the
// kinetic energy of all free mass at 1 m/s, so with nothing else in play
// (no gravity, no ground motion) the guard fires only at rms speeds of
// 1000 m/s; a body falling 100 m reaches 44 m/s, nothing in a collapsing
// frame comes near. Cost: O(1) per step (the sums are made anyway); the
// O(n) search for the body to name runs only when it fires.
constexpr double kBlowUpFactor = 1.0e6;
constexpr double kFloorSpeed_mps = 1.0;


}  // namespace

Simulation::Simulation(BodyStore bodies, SimulationSettings settings, GroundMotion ground_motion)
    : bodies_(std::move(bodies)), settings_(settings), ground_motion_(std::move(ground_motion)) {
  if (!(settings_.dt_s > 0.0) || !std::isfinite(settings_.dt_s))
    throw std::invalid_argument("time step dt_s must be a positive number of seconds");
  if (!(settings_.duration_s >= 0.0) || !std::isfinite(settings_.duration_s))
    throw std::invalid_argument("duration_s must be a non-negative number of seconds");
  if (settings_.profile_every_steps < 1) settings_.profile_every_steps = 1;
}

void Simulation::add_force_provider(std::unique_ptr<ForceProvider> provider) {
  if (initialized_) throw std::logic_error("force providers must be added before the first step");
  providers_.push_back(std::move(provider));
  profile_.provider_seconds.push_back(0.0);
}

void Simulation::add_observer(StepObserver* observer, std::int64_t every_steps) {
  observers_.push_back({observer, std::max<std::int64_t>(1, every_steps)});
}

std::int64_t Simulation::total_steps() const {
  return static_cast<std::int64_t>(std::llround(settings_.duration_s / settings_.dt_s));
}

std::uint64_t Simulation::state_hash() const {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a 64-bit offset basis
  auto mix = [&h](const double* values, std::size_t count) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(values);
    for (std::size_t k = 0; k < count * sizeof(double); ++k) {
      h ^= bytes[k];
      h *= 1099511628211ull;  // FNV prime
    }
  };
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    mix(bodies_.position_m[i].data(), 3);
    mix(bodies_.orientation[i].coeffs().data(), 4);
    mix(bodies_.velocity_mps[i].data(), 3);
    mix(bodies_.angular_momentum_Nms[i].data(), 3);
  }
  return h;
}

double Simulation::wall_seconds() const { return wall_started_ ? seconds_between(wall_start_, Clock::now()) : 0.0; }

void Simulation::compute_forces() {
  const StepInfo info{step_, time_s(), settings_.dt_s};
  const bool timed = (step_ % settings_.profile_every_steps) == 0;
  const double scale = double(settings_.profile_every_steps);
  auto t0 = timed ? Clock::now() : Clock::time_point{};

  ground_acceleration_ = ground_motion_.acceleration(info.time_s);
  // Relative frame: every free body feels m (g - a_g).
  const Vec3 specific_force = settings_.gravity_mps2 - ground_acceleration_;
  const std::size_t n = bodies_.size();
  for (std::size_t i = 0; i < n; ++i) {
    bodies_.force_N[i] = bodies_.is_fixed[i] ? Vec3::Zero() : Vec3(bodies_.mass_kg[i] * specific_force);
    bodies_.torque_Nm[i].setZero();
  }
  if (timed) {
    auto t1 = Clock::now();
    profile_.seconds[int(Stage::ExternalForces)] += scale * seconds_between(t0, t1);
    t0 = t1;
  }
  for (std::size_t p = 0; p < providers_.size(); ++p) {
    providers_[p]->accumulate_forces(bodies_, info);
    if (timed) {
      auto t1 = Clock::now();
      const double s = scale * seconds_between(t0, t1);
      profile_.provider_seconds[p] += s;
      profile_.seconds[int(Stage::Providers)] += s;
      t0 = t1;
    }
  }
  forces_current_ = true;
}

void Simulation::initialize() {
  if (initialized_) return;
  initialized_ = true;
  if (!wall_started_) {
    wall_start_ = Clock::now();
    wall_started_ = true;
  }
  bodies_.update_rotations();
  for (auto& p : providers_) p->prepare(bodies_);
  compute_forces();

  // Ledger at t = 0, with the same definitions as at every later step
  // (energy_ledger.h): translational kinetic energy (KE(-1/2) + KE(+1/2)) / 2.
  ledger_ = EnergyLedger{};
  const std::size_t n = bodies_.size();
  const double half_dt = 0.5 * settings_.dt_s;
  double kinetic = 0.0, rotational = 0.0;
  Vec3 momentum = Vec3::Zero();  // sum m v0 (kg m/s)
  for (std::size_t i = 0; i < n; ++i) {
    if (bodies_.is_fixed[i]) continue;
    const Vec3 half_kick = (half_dt * bodies_.inverse_mass_per_kg[i]) * bodies_.force_N[i];
    const Vec3 v0 = bodies_.velocity_mps[i];
    kinetic += 0.25 * bodies_.mass_kg[i] * ((v0 - half_kick).squaredNorm() + (v0 + half_kick).squaredNorm());
    momentum += bodies_.mass_kg[i] * v0;
    rotational += 0.5 * bodies_.angular_momentum_Nms[i].dot(bodies_.angular_velocity_radps[i]);
    // Shift back half a step: v(-1/2) = v0 - (dt/2) F0/m, L(-1/2) = L0 - (dt/2) T0.
    bodies_.velocity_mps[i] = v0 - half_kick;
    bodies_.angular_momentum_Nms[i] -= half_dt * bodies_.torque_Nm[i];
    bodies_.angular_velocity_radps[i] =
        bodies_.angular_velocity_from_momentum(BodyId(i), bodies_.rotation[i], bodies_.angular_momentum_Nms[i]);
  }
  ledger_.kinetic_J = kinetic + rotational;
  ledger_.kinetic_rotational_J = rotational;
  // Work is counted from t = 0: step 0 adds only its second half,
  // dt F0 . v0 / 2, so the running sums start at minus that half.
  work_gravity_through_prev_J_ = -half_dt * settings_.gravity_mps2.dot(momentum);
  work_ground_through_prev_J_ = half_dt * ground_acceleration_.dot(momentum);
  for (auto& p : providers_) p->report_energy(ledger_);
  ledger_.initial_stored_J = ledger_.stored_J();
  ledger_.update_scale();
  double free_mass_kg = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    if (!bodies_.is_fixed[i]) free_mass_kg += bodies_.mass_kg[i];
  energy_floor_J_ = 0.5 * free_mass_kg * kFloorSpeed_mps * kFloorSpeed_mps;
}

bool Simulation::energy_blew_up() const {
  const EnergyLedger& l = ledger_;
  const double work_gravity_J = -l.gravity_potential_J;
  const double available_J = l.initial_stored_J + work_gravity_J + l.work_ground_motion_J + l.work_external_J;
  const double scale_J = std::max({std::abs(l.initial_stored_J), std::abs(work_gravity_J),
                                   std::abs(l.work_ground_motion_J), std::abs(l.work_external_J), energy_floor_J_});
  return l.kinetic_J - available_J > kBlowUpFactor * scale_J;
}

void Simulation::integrate() {
  const double dt = settings_.dt_s;
  const std::size_t n = bodies_.size();
  const std::size_t chunks = (n + kReductionChunk - 1) / kReductionChunk;
  std::vector<ChunkSums>& sums = chunk_sums_;
  if (sums.size() != chunks) sums.resize(chunks);  // once: no allocation in the step loop

#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (n >= 4 * kReductionChunk)
#endif
  for (std::size_t c = 0; c < chunks; ++c) {
    ChunkSums s{};
    const std::size_t end = std::min(n, (c + 1) * kReductionChunk);
    for (std::size_t i = c * kReductionChunk; i < end; ++i) {
      if (bodies_.is_fixed[i]) continue;
      const double m = bodies_.mass_kg[i];
      const Vec3 v_old = bodies_.velocity_mps[i];
      const Vec3 v_new = v_old + (dt * bodies_.inverse_mass_per_kg[i]) * bodies_.force_N[i];
      bodies_.velocity_mps[i] = v_new;
      bodies_.position_m[i] += dt * v_new;
      s.momentum_old += m * v_old;
      s.momentum_new += m * v_new;
      const double rot_old = 0.5 * bodies_.angular_momentum_Nms[i].dot(bodies_.angular_velocity_radps[i]);
      const Vec3 l_new = bodies_.angular_momentum_Nms[i] + dt * bodies_.torque_Nm[i];
      const FreeRotorDrift drift =
          free_rotor_drift(bodies_.orientation[i], l_new, bodies_.inverse_inertia_per_kgm2[i], dt);
      bodies_.angular_momentum_Nms[i] = l_new;
      bodies_.orientation[i] = drift.orientation_end;
      bodies_.angular_velocity_radps[i] = drift.angular_velocity_mid_world;
      const double rot_new = 0.5 * l_new.dot(drift.angular_velocity_mid_world);
      s.kinetic_old_J += 0.5 * m * v_old.squaredNorm() + rot_old;
      s.kinetic_new_J += 0.5 * m * v_new.squaredNorm() + rot_new;
      s.rotational_old_J += rot_old;
      s.rotational_new_J += rot_new;
    }
    s.finite = std::isfinite(s.kinetic_new_J) && s.momentum_new.allFinite();
    sums[c] = s;
  }

  ChunkSums total{};
  for (const ChunkSums& s : sums) {
    total.momentum_old += s.momentum_old;
    total.momentum_new += s.momentum_new;
    total.kinetic_old_J += s.kinetic_old_J;
    total.kinetic_new_J += s.kinetic_new_J;
    total.rotational_old_J += s.rotational_old_J;
    total.rotational_new_J += s.rotational_new_J;
    total.finite = total.finite && s.finite;
  }
  if (!total.finite) {
    forces_current_ = false;
    // Name the first body whose state is not finite.
    for (std::size_t i = 0; i < n; ++i) {
      if (!bodies_.velocity_mps[i].allFinite() || !bodies_.position_m[i].allFinite() ||
          !bodies_.force_N[i].allFinite() || !bodies_.torque_Nm[i].allFinite()) {
        Event e;
        e.time_s = time_s();
        e.step = step_;
        e.kind = EventKind::Instability;
        e.body_a = BodyId(i);
        e.mode = "non_finite_state";
        e.position_m = bodies_.position_m[i];
        events_.add(e);
        break;
      }
    }
    return;
  }

  // Work of gravity and of the ground-motion inertia force over this step:
  // dt F . v_n with v_n = (v(n-1/2) + v(n+1/2)) / 2 summed over bodies.
  const Vec3 momentum_mid = 0.5 * (total.momentum_old + total.momentum_new);
  const double work_gravity = dt * settings_.gravity_mps2.dot(momentum_mid);
  const double work_ground = -dt * ground_acceleration_.dot(momentum_mid);
  ledger_.kinetic_J = 0.5 * (total.kinetic_old_J + total.kinetic_new_J);
  ledger_.kinetic_rotational_J = 0.5 * (total.rotational_old_J + total.rotational_new_J);
  ledger_.gravity_potential_J = -(work_gravity_through_prev_J_ + 0.5 * work_gravity);
  ledger_.work_ground_motion_J = work_ground_through_prev_J_ + 0.5 * work_ground;
  work_gravity_through_prev_J_ += work_gravity;
  work_ground_through_prev_J_ += work_ground;
  bodies_.update_rotations();
  forces_current_ = false;
}

// Instability event for an energy blow-up found after step n = step_ - 1
// (the ledger then describes t_n), naming the body with the largest kinetic
// energy (the one running away). O(n), only when the guard fired.
void Simulation::record_blow_up() {
  const std::size_t n = bodies_.size();
  std::size_t worst = 0;
  double worst_J = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (bodies_.is_fixed[i]) continue;
    const double ke = 0.5 * bodies_.mass_kg[i] * bodies_.velocity_mps[i].squaredNorm() +
                      0.5 * bodies_.angular_momentum_Nms[i].dot(bodies_.angular_velocity_radps[i]);
    if (ke > worst_J) {
      worst_J = ke;
      worst = i;
    }
  }
  Event e;
  e.step = step_ - 1;
  e.time_s = double(e.step) * settings_.dt_s;
  e.kind = EventKind::Instability;
  e.body_a = BodyId(worst);
  e.mode = "energy_blow_up";
  e.position_m = bodies_.position_m[worst];
  events_.add(e);
}

void Simulation::finish_step() {
  const StepInfo info{step_, time_s(), settings_.dt_s};
  for (auto& p : providers_) p->finish_step(bodies_, info, events_);
}

// Provider energies are gathered only when someone looks.
void Simulation::gather_provider_energy() {
  ledger_.elastic_J = 0.0;
  ledger_.dissipated_viscous_J = 0.0;
  ledger_.dissipated_plastic_J = 0.0;
  ledger_.dissipated_friction_J = 0.0;
  for (auto& p : providers_) p->report_energy(ledger_);
  ledger_.update_scale();
}

void Simulation::observe(bool force_all) {
  bool any_due = force_all;
  for (const ObserverSlot& o : observers_) any_due = any_due || (step_ % o.every_steps) == 0;
  if (!any_due) return;
  const auto t0 = Clock::now();
  gather_provider_energy();
  for (const ObserverSlot& o : observers_)
    if (force_all || (step_ % o.every_steps) == 0) o.observer->on_sample(*this);
  profile_.seconds[int(Stage::Observe)] += seconds_between(t0, Clock::now());
}

void Simulation::observe_undue() {
  const auto t0 = Clock::now();
  gather_provider_energy();
  for (const ObserverSlot& o : observers_)
    if ((step_ % o.every_steps) != 0) o.observer->on_sample(*this);
  profile_.seconds[int(Stage::Observe)] += seconds_between(t0, Clock::now());
}

bool Simulation::step() {
  initialize();
  if (!forces_current_) compute_forces();
  const bool timed = (step_ % settings_.profile_every_steps) == 0;
  const double scale = double(settings_.profile_every_steps);
  auto t0 = timed ? Clock::now() : Clock::time_point{};
  integrate();
  if (!events_.all().empty() && events_.all().back().kind == EventKind::Instability &&
      events_.all().back().step == step_)
    return false;
  if (timed) {
    const auto t1 = Clock::now();
    profile_.seconds[int(Stage::Integrate)] += scale * seconds_between(t0, t1);
    t0 = t1;
  }
  finish_step();
  if (timed) profile_.seconds[int(Stage::FinishStep)] += scale * seconds_between(t0, Clock::now());
  ++step_;
  return true;
}

RunResult Simulation::run(const std::atomic<bool>* stop_requested) {
  if (!wall_started_) {
    wall_start_ = Clock::now();
    wall_started_ = true;
  }
  initialize();
  RunResult result;
  for (const ObserverSlot& o : observers_) o.observer->on_start(*this);
  if (step_ == 0) observe(true);
  const std::int64_t last = total_steps();
  while (step_ < last) {
    if (stop_requested && stop_requested->load(std::memory_order_relaxed)) {
      result.status = RunStatus::Stopped;
      break;
    }
    // The energy guard runs here, not in step(): run() is what users'
    // cases go through, while step() stays the bare scheme (tests drive it
    // past its stability limit on purpose).
    const bool stepped = step();
    const bool blew_up = stepped && energy_blew_up();
    if (blew_up) record_blow_up();
    if (!stepped || blew_up) {
      result.status = RunStatus::Unstable;
      const Event& e = events_.all().back();
      std::ostringstream msg;
      if (blew_up)
        msg << "kinetic energy " << ledger_.kinetic_J << " J exceeds a million times the energy put in at step "
            << e.step << " (t = " << e.time_s << " s), largest in body " << e.body_a << " '"
            << bodies_.info[e.body_a].name << "'";
      else
        msg << "state became non-finite at step " << e.step << " (t = " << e.time_s << " s), first in body "
            << e.body_a << " '" << bodies_.info[e.body_a].name << "'";
      result.message = msg.str();
      break;
    }
    observe(false);
  }
  // The last good state is sampled by every observer exactly once.
  if (result.status != RunStatus::Unstable) {
    bool all_due = true;
    for (const ObserverSlot& o : observers_) all_due = all_due && (step_ % o.every_steps) == 0;
    if (!all_due) observe_undue();
  }
  // Provider energies are otherwise gathered only when an observer samples.
  gather_provider_energy();
  result.steps = step_;
  result.simulated_s = time_s();
  result.wall_s = wall_seconds();
  for (const ObserverSlot& o : observers_) o.observer->on_finish(*this);
  return result;
}

}  // namespace fq
