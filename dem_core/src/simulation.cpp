#include "dem_core/simulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "dem_core/lane_isa.h"
#include "dem_core/parallel_for.h"
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

// Bodies are summed in chunks and the chunk sums added in order, so the
// ledger is bitwise the same whatever the number of threads
// (parallel_for.h, EqualChunks): about 1024 bodies a chunk, and above one
// chunk a multiple of 8 chunks of equal size, so that a static schedule
// gives each of 2, 4 or 8 threads the same number of bodies. (Chunks of
// exactly 1024 gave the 11 000 bodies of the 1e4-body lattice 6 144 on one
// thread and 4 856 on the other.)
constexpr std::size_t kReductionChunk = 1024;
constexpr std::size_t kChunkMultiple = 8;

// Force m (g - a_g) on every free body, zero torque: the start of each force
// evaluation. Threads only for large scenes.
void set_body_loads(BodyStore& bodies, const Vec3& specific_force) {
  const auto n = std::int64_t(bodies.size());
  parallel_for_static(n, n >= std::int64_t(4 * kReductionChunk), [&](std::int64_t bi) {
    const auto i = std::size_t(bi);
    bodies.force_N[i] = bodies.is_fixed[i] ? Vec3::Zero() : Vec3(bodies.mass_kg[i] * specific_force);
    bodies.torque_Nm[i].setZero();
  });
}

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
// (no gravity, no ground motion) this test fires only at rms speeds of
// 1000 m/s (the absolute ceiling below fires first, at 100 m/s); a body
// falling 100 m reaches 44 m/s, nothing in a collapsing frame comes near. Cost: O(1) per step (the sums are made anyway); the
// O(n) search for the body to name runs only when it fires.
// E_scale holds |W_gravity|, which a runaway that throws bodies up or down
// raises itself: a frame forced to 8.6 times its stable step reached rms
// speeds of 1 600 m/s and travelled 7 km without firing it (stress probe).
// So the run is also stopped when KE alone exceeds the larger of
// kCeilingSpeed_mps^2 E_floor / (1 m/s)^2 (an rms speed of 100 m/s) and
// kBlowUpFactor |initial_stored| (a million times what the start held).
// Gravity and a ground motion cannot bring a structure to 100 m/s rms (a
// fall of 510 m would; an earthquake puts in ~1 J/kg, 1.4 m/s). The
// ceiling was 1000 m/s until 2026-11-27: a rod pinned at its end, forced
// to 1.001 times its stable step, grew its energy 1e10-fold and levelled
// off at 195 m/s rms, spinning, and the run "completed" with exit 0
// (stable-step probe).
constexpr double kBlowUpFactor = 1.0e6;
constexpr double kFloorSpeed_mps = 1.0;
constexpr double kCeilingSpeed_mps = 100.0;


}  // namespace

// gsl_rk8pd: the GSL system and driver, allocated in initialize().
struct Simulation::GslWorkspace {
  gsl_odeiv2_system system{};
  gsl_odeiv2_driver* driver = nullptr;
  GslWorkspace() = default;
  GslWorkspace(const GslWorkspace&) = delete;
  GslWorkspace& operator=(const GslWorkspace&) = delete;
  ~GslWorkspace() {
    if (driver) gsl_odeiv2_driver_free(driver);
  }
};

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

Simulation::Simulation(BodyStore bodies, SimulationSettings settings, GroundMotion ground_motion)
    : bodies_(std::move(bodies)), settings_(settings), ground_motion_(std::move(ground_motion)) {
  if (!(settings_.dt_s > 0.0) || !std::isfinite(settings_.dt_s))
    throw std::invalid_argument("time step dt_s must be a positive number of seconds");
  if (!(settings_.duration_s >= 0.0) || !std::isfinite(settings_.duration_s))
    throw std::invalid_argument("duration_s must be a non-negative number of seconds");
  if (!(settings_.duration_s / settings_.dt_s <= kMaxSimulationSteps)) {
    std::ostringstream m;
    m << "duration_s / dt_s = " << settings_.duration_s << " s / " << settings_.dt_s << " s is "
      << settings_.duration_s / settings_.dt_s << " steps; at most " << kMaxSimulationSteps
      << " are accepted (check the units of dt_s and duration_s)";
    throw std::invalid_argument(m.str());
  }
  if (settings_.profile_every_steps < 1) settings_.profile_every_steps = 1;
  // The SIMD form of the lane kernels, read here, outside any parallel
  // region: a bad FRAMEQUAKE_SIMD throws now (lane_isa.h), not inside a step.
  (void)active_lane_isa();
  if (settings_.integrator == Integrator::GslRk8pd &&
      (!(settings_.reference_tolerance > 0.0) || !std::isfinite(settings_.reference_tolerance)))
    throw std::invalid_argument("reference_tolerance must be a positive number");
}

std::string Simulation::integrator_refusal() const {
  if (!integrator_is_multistage(settings_.integrator)) return "";
  for (const auto& p : providers_) {
    if (!p->supports_trial_states()) {
      std::ostringstream m;
      const std::string obstacle = p->trial_state_obstacle();
      m << "integrator " << integrator_name(settings_.integrator)
        << " evaluates forces at trial states within a step, but force provider '" << p->name()
        << "' keeps history between evaluations ("
        << (obstacle.empty() ? std::string("plastic or fracturing joint laws, joint strain limits, contacts") : obstacle)
        << "); use central_difference, velocity_verlet or symplectic_euler for this scene";
      return m.str();
    }
  }
  return "";
}

void Simulation::add_force_provider(std::unique_ptr<ForceProvider> provider) {
  if (initialized_) throw std::logic_error("force providers must be added before the first step");
  providers_.push_back(std::move(provider));
  profile_.provider_seconds.push_back(0.0);
}

void Simulation::add_observer(StepObserver* observer, std::int64_t every_steps) {
  observers_.push_back({observer, std::max<std::int64_t>(1, every_steps)});
}

void Simulation::add_step_monitor(StepObserver* monitor) { step_monitors_.push_back(monitor); }

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
  set_body_loads(bodies_, specific_force);
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
  if (const std::string why = integrator_refusal(); !why.empty()) throw std::invalid_argument(why);
  initialized_ = true;
  if (!wall_started_) {
    wall_start_ = Clock::now();
    wall_started_ = true;
  }
  bodies_.update_rotations();
  for (auto& p : providers_) p->prepare(bodies_);
  if (settings_.integrator != Integrator::CentralDifference) {
    initialize_synchronised();
    return;
  }
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
  const double ceiling = kCeilingSpeed_mps / kFloorSpeed_mps;
  const double absolute_J = std::max(ceiling * ceiling * energy_floor_J_, kBlowUpFactor * std::abs(l.initial_stored_J));
  return l.kinetic_J - available_J > kBlowUpFactor * scale_J || l.kinetic_J > absolute_J;
}

void Simulation::integrate() {
  const double dt = settings_.dt_s;
  const std::size_t n = bodies_.size();
  const EqualChunks chunking(n, kReductionChunk, kChunkMultiple);
  const std::size_t chunks = chunking.count;
  std::vector<ChunkSums>& sums = chunk_sums_;
  if (sums.size() != chunks) sums.resize(chunks);  // once: no allocation in the step loop

  parallel_for_static(std::int64_t(chunks), n >= 4 * kReductionChunk, [&](std::int64_t ci) {
    const auto c = std::size_t(ci);
    ChunkSums s{};
    const std::size_t end = chunking.begin(c + 1);
    // Free bodies in groups of four: the rotation drift runs in SIMD lanes
    // (free_rotor_drift4, bitwise the scalar drift), and the sums are
    // then taken body by body in index order, as before.
    std::size_t group[4];
    Quat q_old[4];
    Vec3 v_old[4], l_new[4], inverse_inertia[4];
    double rot_old[4];
    int count = 0;
    auto drift_group = [&]() {
      FreeRotorDrift drift[4];
      free_rotor_drift4(q_old, l_new, inverse_inertia, dt, count, drift);
      for (int k = 0; k < count; ++k) {
        const std::size_t i = group[k];
        const double m = bodies_.mass_kg[i];
        const Vec3& v_new = bodies_.velocity_mps[i];
        s.momentum_old += m * v_old[k];
        s.momentum_new += m * v_new;
        bodies_.angular_momentum_Nms[i] = l_new[k];
        bodies_.orientation[i] = drift[k].orientation_end;
        bodies_.angular_velocity_radps[i] = drift[k].angular_velocity_mid_world;
        const double rot_new = 0.5 * l_new[k].dot(drift[k].angular_velocity_mid_world);
        s.kinetic_old_J += 0.5 * m * v_old[k].squaredNorm() + rot_old[k];
        s.kinetic_new_J += 0.5 * m * v_new.squaredNorm() + rot_new;
        s.rotational_old_J += rot_old[k];
        s.rotational_new_J += rot_new;
      }
      count = 0;
    };
    for (std::size_t i = chunking.begin(c); i < end; ++i) {
      if (bodies_.is_fixed[i]) continue;
      const Vec3 v = bodies_.velocity_mps[i];
      const Vec3 v_new = v + (dt * bodies_.inverse_mass_per_kg[i]) * bodies_.force_N[i];
      bodies_.velocity_mps[i] = v_new;
      bodies_.position_m[i] += dt * v_new;
      group[count] = i;
      v_old[count] = v;
      rot_old[count] = 0.5 * bodies_.angular_momentum_Nms[i].dot(bodies_.angular_velocity_radps[i]);
      l_new[count] = bodies_.angular_momentum_Nms[i] + dt * bodies_.torque_Nm[i];
      q_old[count] = bodies_.orientation[i];
      inverse_inertia[count] = bodies_.inverse_inertia_per_kgm2[i];
      if (++count == 4) drift_group();
    }
    if (count > 0) drift_group();
    s.finite = std::isfinite(s.kinetic_new_J) && s.momentum_new.allFinite();
    sums[c] = s;
  });

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
  for (StepObserver* m : step_monitors_) m->on_sample(*this);
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
  if (settings_.integrator != Integrator::CentralDifference) return step_synchronised();
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
  const std::int64_t first = step_;  // 0, or the step a resumed run starts from
  run_first_step_ = first;
  for (StepObserver* m : step_monitors_) m->on_start(*this);
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
        msg << "kinetic energy " << ledger_.kinetic_J
            << " J exceeds a million times the energy put in (or an rms speed of 100 m/s) at step "
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
  result.steps_this_call = step_ - first;
  result.simulated_s = time_s();
  result.wall_s = wall_seconds();
  for (const ObserverSlot& o : observers_) o.observer->on_finish(*this);
  for (StepObserver* m : step_monitors_) m->on_finish(*this);
  return result;
}


// ---- integrators other than central difference -------------------------------
//
// Common frame (integrator.h): the body store holds the state at integer
// step n -- x_n, q_n, v_n, L_n and the instantaneous w_n = R I^-1 R^T L_n --
// with the forces F_n, T_n already evaluated. One step: the method's update
// to n+1 (integrate stage), FinishStep, then the forces at n+1 (which the
// next step reuses: velocity Verlet's second half kick needs them, and they
// are RK4's first stage), then the ledger at n+1. Observers therefore see
// poses, velocities, forces and ledger all at the same time t_{n+1}.
//
// Ledger (energy_ledger.h) for these integrators: kinetic energy of the
// state at n; gravity potential -g . sum m (x_n - x_0) (exact for uniform
// gravity, so the balance error shows the method's own energy error);
// ground-motion work by the trapezoid rule over each step, O(dt^2). Joint
// and contact dashpot/friction books assume the leapfrog (one evaluation
// per step, v at half steps) and are approximate, O(dt), here.

void Simulation::evaluate_forces_at(const StepInfo& info) {
  ground_acceleration_ = ground_motion_.acceleration(info.time_s);
  const Vec3 specific_force = settings_.gravity_mps2 - ground_acceleration_;
  set_body_loads(bodies_, specific_force);
  for (auto& p : providers_) p->accumulate_forces(bodies_, info);
}

namespace {

constexpr std::size_t kOdeDofPerBody = 13;  // x(3), q(4: w, x, y, z), v(3), L(3)

// Instantaneous world angular velocity from L at the pose of the store.
void refresh_angular_velocity(BodyStore& b, std::size_t i) {
  b.angular_velocity_radps[i] = b.angular_velocity_from_momentum(BodyId(i), b.rotation[i], b.angular_momentum_Nms[i]);
}

// q' = (1/2) (0, w) q for q body -> world and w in the world frame.
Quat quaternion_rate(const Vec3& w_world, const Quat& q) {
  const Quat wq(0.0, w_world.x(), w_world.y(), w_world.z());
  Quat r = wq * q;
  r.coeffs() *= 0.5;
  return r;
}

}  // namespace

int simulation_gsl_rhs(double t, const double y[], double dydt[], void* params) {
  auto* sim = static_cast<Simulation*>(params);
  sim->ode_derivative(t, y, dydt);
  for (std::size_t k = 0; k < sim->ode_y_.size(); ++k)
    if (!std::isfinite(dydt[k])) return GSL_EBADFUNC;
  return GSL_SUCCESS;
}

void Simulation::initialize_synchronised() {
  free_bodies_.clear();
  mass_moment0_m_kg_.setZero();
  double free_mass_kg = 0.0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_.is_fixed[i]) continue;
    free_bodies_.push_back(BodyId(i));
    refresh_angular_velocity(bodies_, i);  // L is the state; w follows from it
    mass_moment0_m_kg_ += bodies_.mass_kg[i] * bodies_.position_m[i];
    free_mass_kg += bodies_.mass_kg[i];
  }
  if (integrator_is_multistage(settings_.integrator)) {
    const std::size_t dim = kOdeDofPerBody * free_bodies_.size();
    ode_y_.assign(dim, 0.0);
    ode_tmp_.assign(dim, 0.0);
    for (auto& k : ode_k_) k.assign(dim, 0.0);
  }
  if (settings_.integrator == Integrator::GslRk8pd && !free_bodies_.empty()) {
    gsl_ = std::make_unique<GslWorkspace>();
    gsl_->system = gsl_odeiv2_system{simulation_gsl_rhs, nullptr, ode_y_.size(), this};
    gsl_->driver = gsl_odeiv2_driver_alloc_y_new(&gsl_->system, gsl_odeiv2_step_rk8pd, settings_.dt_s,
                                                 settings_.reference_tolerance, settings_.reference_tolerance);
    if (!gsl_->driver) throw std::runtime_error("gsl_rk8pd: GSL could not allocate its ODE driver");
  }
  compute_forces();
  ledger_ = EnergyLedger{};
  update_ledger_synchronised(true);
  for (auto& p : providers_) p->report_energy(ledger_);
  ledger_.initial_stored_J = ledger_.stored_J();
  ledger_.update_scale();
  energy_floor_J_ = 0.5 * free_mass_kg * kFloorSpeed_mps * kFloorSpeed_mps;
}

void Simulation::update_ledger_synchronised(bool first) {
  Vec3 momentum = Vec3::Zero(), mass_moment = Vec3::Zero();
  double kinetic = 0.0, rotational = 0.0;
  for (const BodyId b : free_bodies_) {
    const auto i = std::size_t(b);
    const double m = bodies_.mass_kg[i];
    momentum += m * bodies_.velocity_mps[i];
    mass_moment += m * bodies_.position_m[i];
    kinetic += 0.5 * m * bodies_.velocity_mps[i].squaredNorm();
    rotational += 0.5 * bodies_.angular_momentum_Nms[i].dot(bodies_.angular_velocity_radps[i]);
  }
  ledger_.kinetic_J = kinetic + rotational;
  ledger_.kinetic_rotational_J = rotational;
  ledger_.gravity_potential_J = -settings_.gravity_mps2.dot(mass_moment - mass_moment0_m_kg_);
  if (first) {
    ledger_.work_ground_motion_J = 0.0;
  } else {
    // Power of the inertia force -m a_g is -a_g . P; trapezoid over the step.
    ledger_.work_ground_motion_J -=
        0.5 * settings_.dt_s * (ground_acceleration_prev_.dot(momentum_prev_) + ground_acceleration_.dot(momentum));
  }
  momentum_prev_ = momentum;
  ground_acceleration_prev_ = ground_acceleration_;
}

bool Simulation::record_non_finite() {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_.position_m[i].allFinite() && bodies_.velocity_mps[i].allFinite() &&
        bodies_.orientation[i].coeffs().allFinite() && bodies_.angular_momentum_Nms[i].allFinite())
      continue;
    Event e;
    e.time_s = time_s();
    e.step = step_;
    e.kind = EventKind::Instability;
    e.body_a = BodyId(i);
    e.mode = "non_finite_state";
    e.position_m = bodies_.position_m[i];
    events_.add(e);
    return true;
  }
  return false;
}

bool Simulation::step_synchronised() {
  initialize();
  if (!forces_current_) compute_forces();
  const bool timed = (step_ % settings_.profile_every_steps) == 0;
  const double scale = double(settings_.profile_every_steps);
  auto t0 = timed ? Clock::now() : Clock::time_point{};
  switch (settings_.integrator) {
    case Integrator::RungeKutta4: integrate_runge_kutta4(); break;
    case Integrator::GslRk8pd: integrate_gsl(); break;
    default: integrate_synchronised(); break;
  }
  forces_current_ = false;
  if (record_non_finite()) return false;
  if (timed) {
    const auto t1 = Clock::now();
    profile_.seconds[int(Stage::Integrate)] += scale * seconds_between(t0, t1);
    t0 = t1;
  }
  finish_step();
  if (timed) profile_.seconds[int(Stage::FinishStep)] += scale * seconds_between(t0, Clock::now());
  ++step_;
  compute_forces();
  after_forces_synchronised();
  return true;
}

void Simulation::integrate_synchronised() {
  const double dt = settings_.dt_s;
  const Integrator method = settings_.integrator;
  for (const BodyId b : free_bodies_) {
    const auto i = std::size_t(b);
    const Vec3 accel = bodies_.inverse_mass_per_kg[i] * bodies_.force_N[i];
    if (method == Integrator::ForwardEuler) {
      // Everything from the state at n.
      bodies_.position_m[i] += dt * bodies_.velocity_mps[i];
      bodies_.velocity_mps[i] += dt * accel;
      const Vec3 w = bodies_.angular_velocity_radps[i];
      const double angle = w.norm() * dt;
      if (angle > 0.0)
        bodies_.orientation[i] = (Quat(Eigen::AngleAxisd(angle, w.normalized())) * bodies_.orientation[i]).normalized();
      bodies_.angular_momentum_Nms[i] += dt * bodies_.torque_Nm[i];
      continue;
    }
    // Kick (full: symplectic Euler; half: velocity Verlet), then drift.
    const double kick = method == Integrator::VelocityVerlet ? 0.5 * dt : dt;
    bodies_.velocity_mps[i] += kick * accel;
    bodies_.position_m[i] += dt * bodies_.velocity_mps[i];
    bodies_.angular_momentum_Nms[i] += kick * bodies_.torque_Nm[i];
    const FreeRotorDrift drift =
        free_rotor_drift(bodies_.orientation[i], bodies_.angular_momentum_Nms[i], bodies_.inverse_inertia_per_kgm2[i], dt);
    bodies_.orientation[i] = drift.orientation_end;
    // Velocity Verlet evaluates the next forces with mid-step velocities
    // (v(n+1/2), w(n+1/2)), as central difference does.
    bodies_.angular_velocity_radps[i] = drift.angular_velocity_mid_world;
  }
  bodies_.update_rotations();
  if (method != Integrator::VelocityVerlet)
    for (const BodyId b : free_bodies_) refresh_angular_velocity(bodies_, std::size_t(b));
}

void Simulation::after_forces_synchronised() {
  if (settings_.integrator == Integrator::VelocityVerlet) {
    const double half_dt = 0.5 * settings_.dt_s;
    for (const BodyId b : free_bodies_) {
      const auto i = std::size_t(b);
      bodies_.velocity_mps[i] += (half_dt * bodies_.inverse_mass_per_kg[i]) * bodies_.force_N[i];
      bodies_.angular_momentum_Nms[i] += half_dt * bodies_.torque_Nm[i];
      refresh_angular_velocity(bodies_, i);
    }
  }
  update_ledger_synchronised(false);
}

void Simulation::ode_store(double* y) const {
  for (const BodyId b : free_bodies_) {
    const auto i = std::size_t(b);
    const Quat& q = bodies_.orientation[i];
    const double v[kOdeDofPerBody] = {bodies_.position_m[i].x(), bodies_.position_m[i].y(), bodies_.position_m[i].z(),
                                      q.w(), q.x(), q.y(), q.z(),
                                      bodies_.velocity_mps[i].x(), bodies_.velocity_mps[i].y(), bodies_.velocity_mps[i].z(),
                                      bodies_.angular_momentum_Nms[i].x(), bodies_.angular_momentum_Nms[i].y(),
                                      bodies_.angular_momentum_Nms[i].z()};
    std::copy(v, v + kOdeDofPerBody, y);
    y += kOdeDofPerBody;
  }
}

void Simulation::ode_load(const double* y) {
  for (const BodyId b : free_bodies_) {
    const auto i = std::size_t(b);
    bodies_.position_m[i] = Vec3(y[0], y[1], y[2]);
    // The quaternion drifts off the unit sphere by the truncation error of
    // the method; the pose uses its normalised value.
    bodies_.orientation[i] = Quat(y[3], y[4], y[5], y[6]).normalized();
    bodies_.rotation[i] = bodies_.orientation[i].toRotationMatrix();
    bodies_.velocity_mps[i] = Vec3(y[7], y[8], y[9]);
    bodies_.angular_momentum_Nms[i] = Vec3(y[10], y[11], y[12]);
    refresh_angular_velocity(bodies_, i);
    y += kOdeDofPerBody;
  }
}

namespace {

// dy/dt of the ODE state from the store (poses, velocities, forces of one state).
void ode_rate_from_store(const BodyStore& bodies, const std::vector<BodyId>& free_bodies, double* dydt) {
  for (const BodyId b : free_bodies) {
    const auto i = std::size_t(b);
    const Quat qd = quaternion_rate(bodies.angular_velocity_radps[i], bodies.orientation[i]);
    const Vec3 a = bodies.inverse_mass_per_kg[i] * bodies.force_N[i];
    const Vec3& v = bodies.velocity_mps[i];
    const Vec3& t = bodies.torque_Nm[i];
    const double r[kOdeDofPerBody] = {v.x(), v.y(), v.z(), qd.w(), qd.x(), qd.y(), qd.z(),
                                      a.x(), a.y(), a.z(), t.x(), t.y(), t.z()};
    std::copy(r, r + kOdeDofPerBody, dydt);
    dydt += kOdeDofPerBody;
  }
}

}  // namespace

void Simulation::ode_derivative(double t_s, const double* y, double* dydt) {
  ode_load(y);
  evaluate_forces_at(StepInfo{step_, t_s, settings_.dt_s});
  ode_rate_from_store(bodies_, free_bodies_, dydt);
}

void Simulation::integrate_runge_kutta4() {
  const double dt = settings_.dt_s, t = time_s();
  const std::size_t dim = ode_y_.size();
  double* y = ode_y_.data();
  double* tmp = ode_tmp_.data();
  ode_store(y);
  ode_rate_from_store(bodies_, free_bodies_, ode_k_[0].data());  // forces at n are current
  const double stage_c[3] = {0.5, 0.5, 1.0};
  for (int s = 1; s < 4; ++s) {
    const double* k_prev = ode_k_[s - 1].data();
    for (std::size_t k = 0; k < dim; ++k) tmp[k] = y[k] + stage_c[s - 1] * dt * k_prev[k];
    ode_derivative(t + stage_c[s - 1] * dt, tmp, ode_k_[s].data());
  }
  const double* k1 = ode_k_[0].data();
  const double* k2 = ode_k_[1].data();
  const double* k3 = ode_k_[2].data();
  const double* k4 = ode_k_[3].data();
  for (std::size_t k = 0; k < dim; ++k) y[k] += dt / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]);
  ode_load(y);
}

void Simulation::integrate_gsl() {
  if (!gsl_) return;  // nothing free to move
  double* y = ode_y_.data();
  ode_store(y);
  double t = time_s();
  const int status = gsl_odeiv2_driver_apply(gsl_->driver, &t, time_s() + settings_.dt_s, y);
  if (status != GSL_SUCCESS)
    for (std::size_t k = 0; k < ode_y_.size(); ++k) y[k] = std::numeric_limits<double>::quiet_NaN();
  ode_load(y);
  // The quaternion in y is renormalised by ode_load; keep the driver's
  // state on the unit sphere too (it is restarted from y each step).
  gsl_odeiv2_driver_reset(gsl_->driver);
}

}  // namespace fq
