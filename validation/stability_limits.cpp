// Stability limits of every integrator on a jointed chain, against theory.
//
// Scene and instability test: stability_limits_core.h (the 5-box chain of
// tests/joints/test_stable_time_step.cpp, undamped, started at rest
// positions with small random velocities; a run of `steps` steps is
// unstable when its mechanical energy exceeds 1e6 times the initial one or
// the state stops being finite). For each integrator the largest stable dt
// is found by bisection. Theory: dt = factor / omega_max, omega_max from
// JointSystem::stiffest_mode (Lanczos on M^-1/2 K M^-1/2), factor
// 2 for central difference, velocity Verlet and symplectic Euler, 2 sqrt 2
// for RK4 (integrator.h); forward Euler is checked to grow at every dt.
// A second table shows RK4 above its limit: steps to the energy threshold
// against the closed-form growth |R|^2 per step, and the verdict of the
// former half-against-half test, which saturation fooled.
// A third table checks the damped estimate (dashpots read at v(n-1/2):
// the limit is where lambda_max(dt^2 K~ + 2 dt C~) = 4, joint_system.cpp)
// on the chain with spring-level damping ratios 0.05-1 and on the portal
// frame and breaking cantilever demos (cases/), each without gravity and
// ground motion and started with small random velocities on every body,
// so that every mode is excited: central-difference runs of 20 000 steps,
// unstable when a body moves 1 cm from where it started (a stable run
// stays within about 1e-5 m). A strongly damped mode just above its limit
// grows slowly (|r| - 1 ~ delta / (2 zeta omega dt) per step for a margin
// delta in lambda_max), so the run is long and the threshold low.
// Without gravity a contact is not pressed, and a contact mode past its
// limit clamps at once and moves nothing, so a fourth table loads the
// cases (the demos and frames A, B, C) by their own gravity: the same
// random start, no ground motion, 4000 steps of the estimate in simulated
// time, unstable when the kinetic energy of the last fifth exceeds 10
// times that of the run at half the estimate (loaded_case_late_kinetic_J).
// Lightly pressed contacts chatter within their preload past their limit
// and leave the rest settled, so this measures how conservative the
// estimate is for them (docs/speed_accuracy.md).
//
// Usage: stability_limits [OUT_PREFIX]   (default stability_limits, in the
// working folder) writes OUT_PREFIX.csv and OUT_PREFIX.md and prints the
// markdown table; --help prints the usage, any other option is refused
// (exit 2). The recorded sitting is validation/results/stability_limits: a
// default there would overwrite it, and the former default,
// validation/stability_limits, put the tables among the sources (and failed
// outside the repository root).
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

#include "fq_config.h"
#include "io/atomic_file.h"
#include "io/case_file.h"
#include "io/case_runner.h"
#include "io/name_hint.h"
#include "stability_limits_core.h"

namespace {

constexpr const char* kUsage =
    "usage: stability_limits [OUT_PREFIX]\n"
    "  writes OUT_PREFIX.csv and OUT_PREFIX.md (default stability_limits, in the working folder; the folder\n"
    "  must exist) and prints the markdown table; validation/results/stability_limits is the recorded sitting,\n"
    "  which that prefix overwrites\n"
    "  --help  this text\n";

// Largest displacement (m) of any body over `steps` central-difference
// steps of the case at dt, with gravity and ground motion removed and small
// random velocities (1e-4 m/s, 1e-3 rad/s per component) on every free
// body; infinity when the step loop stops as unstable.
double damped_case_amplitude(fq::CaseDef def, double dt_s, int steps) {
  def.time.dt_s = dt_s;
  def.time.duration_s = dt_s * steps;
  def.time.gravity_mps2 = fq::Vec3::Zero();
  def.ground_motion.reset();
  fq::Scene scene = fq::build_scene(def);
  fq::Simulation& sim = *scene.simulation;
  fq::stability::set_small_random_motion(sim.bodies());
  return fq::stability::largest_displacement(sim, steps);
}

// The cases as they ship, loaded by their own gravity (contacts pressed
// together, as in a run), with no ground motion and the same small random
// velocities: the kinetic energy (J) of the last fifth of `duration_s`
// simulated seconds at dt, at its largest; +inf when the run stops as
// unstable. A stable run keeps the settling motion the load starts, the
// same at every stable dt; a contact or joint mode past its limit grows
// until the compression-only contacts clamp it and then chatters, which
// raises it. (Without gravity such a mode clamps at zero preload and moves
// nothing: the previous test, above, cannot see contact modes.)
double loaded_case_late_kinetic_J(fq::CaseDef def, double dt_s, double duration_s) {
  def.time.dt_s = dt_s;
  def.time.duration_s = duration_s;
  def.ground_motion.reset();
  fq::Scene scene = fq::build_scene(def);
  fq::Simulation& sim = *scene.simulation;
  fq::stability::set_small_random_motion(sim.bodies());
  const std::int64_t steps = sim.total_steps();
  double late = 0.0;
  for (std::int64_t n = 0; n < steps; ++n) {
    if (!sim.step()) return HUGE_VAL;
    if (5 * n < 4 * steps) continue;
    const double ke = fq::stability::mechanical_energy_J(sim, {});  // kinetic only: no elastic providers
    if (!std::isfinite(ke)) return HUGE_VAL;
    late = std::max(late, ke);
  }
  return late;
}

// A case shipped with the sources: from the working folder when it is the
// repository root, else from the source tree this program was built from.
std::filesystem::path source_path(const char* relative) {
  if (std::filesystem::exists(relative)) return relative;
  return std::filesystem::path(FQ_SOURCE_DIR) / relative;
}

int usage_error(const std::string& msg) {
  std::cerr << "stability_limits: error: " << msg << "\n" << kUsage;
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace fq;
  using namespace fq::stability;
  std::string prefix = "stability_limits";
  if (argc > 1) {
    const std::string a = argv[1];
    if (a == "-h" || a == "--help") {
      std::cout << kUsage;
      return 0;
    }
    if (a.empty() || a[0] == '-') return usage_error(fq::unknown_option_message(a, kUsage));
    if (argc > 2) return usage_error("one output prefix expected, got " + std::to_string(argc - 1) + " arguments");
    prefix = a;
  }
  // Checked before the study runs, not after it.
  const std::filesystem::path folder = std::filesystem::path(prefix).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder))
    return usage_error("output folder '" + folder.string() + "' (from OUT_PREFIX '" + prefix + "') does not exist");
  const StiffestMode mode = chain_stiffest_mode();
  const double omega = mode.omega_radps;
  const int steps = 4000;
  std::ostringstream md, csv;
  md << "Jointed chain, omega_max = " << omega << " rad/s (" << mode.where << "), " << steps
     << " steps per trial, unstable when the mechanical energy exceeds " << kEnergyGrowthFactor
     << " x its initial value, bisection to 1e-4 relative\n\n";
  md << "| integrator | bisected dt (s) | omega dt | theory omega dt | estimate dt (s) | bisected / estimate |\n";
  md << "|---|---|---|---|---|---|\n";
  csv << "integrator,dt_bisected_s,omega_dt,omega_dt_theory,dt_estimate_s,ratio,steps_to_energy_threshold\n";
  for (Integrator m : {Integrator::CentralDifference, Integrator::VelocityVerlet, Integrator::SymplecticEuler,
                       Integrator::RungeKutta4}) {
    const double factor = integrator_stability_factor(m);
    const double estimate = factor / omega;
    const double dt = bisect_stable_dt(m, estimate, steps);
    md << "| " << integrator_name(m) << " | " << std::setprecision(6) << dt << " | " << omega * dt << " | " << factor
       << " | " << estimate << " | " << dt / estimate << " |\n";
    csv << integrator_name(m) << "," << std::setprecision(10) << dt << "," << omega * dt << "," << factor << ","
        << estimate << "," << dt / estimate << ",\n";
  }
  // Forward Euler: growth at every dt, here at a tenth of the CD limit.
  const double fe_dt = 0.2 / omega;
  const GrowthRun fe = chain_growth(Integrator::ForwardEuler, fe_dt, steps);
  md << "| forward_euler | none (energy x " << std::setprecision(3) << kEnergyGrowthFactor << " after " << fe.steps_run
     << " steps at omega dt = 0.2) | - | 0 | 0 | - |\n";
  csv << "forward_euler,0,0,0,0,0," << fe.steps_run << "\n";

  // RK4 above its limit, every run stepped to the end. Closed form: the top
  // mode's energy grows by |R|^2 per step, so a mode holding all of E_0
  // reaches the threshold after ln(1e6) / (2 ln |R|) steps, one holding a
  // share f after ln(1e6 / f) / (2 ln |R|): if the chain's top mode grows as
  // linear theory says, the share implied by the observed step count is
  // about the same at every omega dt.
  md << "\nRK4 above its limit (each run stepped through all " << steps << " steps):\n\n";
  md << "| omega dt | closed-form abs(R) | steps to 1e6 E_0, top mode alone | steps to 1e6 E_0, chain | "
        "top-mode share of E_0 implied | largest E / E_0 | largest displacement (m) | "
        "former test: second-half / first-half peak |\n";
  md << "|---|---|---|---|---|---|---|---|\n";
  for (double wdt : {2.80, 2.85, 2.9, 3.0, 3.5, 3.9}) {
    const double r = rk4_amplification(wdt);
    const GrowthRun full = chain_growth(Integrator::RungeKutta4, wdt / omega, steps, false);
    const GrowthRun first = chain_growth(Integrator::RungeKutta4, wdt / omega, steps, true);
    md << "| " << std::setprecision(4) << wdt << " | " << r << " | ";
    if (r > 1.0)
      md << std::setprecision(4) << std::log(kEnergyGrowthFactor) / (2.0 * std::log(r));
    else
      md << "never";
    md << " | " << (first.unstable ? std::to_string(first.steps_run) : std::string("not within the run")) << " | ";
    // Share f of E_0 in the top mode that makes f |R|^(2 n) = 1e6 at the observed n.
    if (first.unstable && r > 1.0)
      md << std::setprecision(2) << kEnergyGrowthFactor / std::pow(r, 2.0 * first.steps_run);
    else
      md << "-";
    md << " | " << std::setprecision(3) << full.max_energy_ratio << " | " << full.max_displacement_m << " | "
       << (full.halves_ratio > 0.0 ? full.halves_ratio : HUGE_VAL) << " |\n";
  }
  // The damped estimate (header).
  const int damped_steps = 20000;
  const double damped_threshold_m = 1e-2;
  md << "\nCentral difference with dashpots, every mode excited (no gravity, no ground motion, small random "
        "velocities; unstable when a body moves "
     << damped_threshold_m << " m within " << damped_steps << " steps), bisection to 1e-4 relative:\n\n";
  md << "| scene | estimate dt (s), set by | bisected dt (s) | bisected / estimate |\n|---|---|---|---|\n";
  auto damped_row = [&](const std::string& scene, double estimate, const std::string& where, auto unstable_at) {
    double lo = 0.5 * estimate, hi = 2.0 * estimate;
    while (hi - lo > 1e-4 * lo) {
      const double mid = 0.5 * (lo + hi);
      (unstable_at(mid) ? hi : lo) = mid;
    }
    md << "| " << scene << " | " << std::setprecision(6) << estimate << ", " << where << " | " << lo << " | "
       << lo / estimate << " |\n";
  };
  for (double zeta : {0.05, 0.2, 0.5, 1.0}) {
    const StiffestMode m = damped_chain_stiffest_mode(zeta);
    std::ostringstream name;
    name << "jointed chain, spring damping ratio " << zeta;
    damped_row(name.str(), 2.0 / m.omega_radps, m.where,
               [&](double dt) { return !(damped_chain_amplitude(zeta, dt, damped_steps) < damped_threshold_m); });
  }
  for (const char* file : {"cases/demo_portal_frame.yaml", "cases/demo_breaking_cantilever.yaml"}) {
    if (!std::filesystem::exists(source_path(file))) {
      md << "| " << file << " | not found | - | - |\n";
      continue;
    }
    try {
      const CaseDef def = load_case_file(source_path(file));
      CaseDef still = def;
      still.time.gravity_mps2 = Vec3::Zero();
      still.time.duration_s = 1.0;
      still.ground_motion.reset();
      const Scene scene = build_scene(still);
      damped_row(file, scene.stable_time_step.dt_crit_s, scene.stable_time_step.stiffest_element,
                 [&](double dt) { return !(damped_case_amplitude(def, dt, damped_steps) < damped_threshold_m); });
    } catch (const std::exception& e) {
      std::cerr << "stability_limits: error: " << e.what() << "\n";
      return 1;
    }
  }
  // The cases loaded by gravity (loaded_case_late_kinetic_J): unstable
  // when the late kinetic energy exceeds 10 times that of the run at half
  // the estimate over the same simulated time (4000 steps of the estimate).
  const double loaded_factor = 10.0;
  md << "\nCentral difference with dashpots, the cases loaded by their own gravity (contacts pressed as in a run; "
        "no ground motion, the same small random velocities; unstable when the kinetic energy of the last fifth "
        "of the run exceeds "
     << loaded_factor
     << " times that of a run at half the estimate over the same simulated time, 4000 estimate steps), bisection "
        "to 1e-3 relative:\n\n";
  md << "| scene | estimate dt (s), set by | bisected dt (s) | bisected / estimate |\n|---|---|---|---|\n";
  for (const char* file : {"cases/demo_portal_frame.yaml", "cases/demo_breaking_cantilever.yaml",
                           "cases/demo_falling_block.yaml", "cases/frame_A.yaml", "cases/frame_B.yaml",
                           "cases/frame_C.yaml"}) {
    if (!std::filesystem::exists(source_path(file))) {
      md << "| " << file << " | not found | - | - |\n";
      continue;
    }
    try {
      CaseDef def = load_case_file(source_path(file));
      def.ground_motion.reset();
      def.time.duration_s = 1.0;
      const Scene scene = build_scene(def);
      const double estimate = scene.stable_time_step.dt_crit_s;
      const double duration = 4000.0 * estimate;
      const double reference = loaded_case_late_kinetic_J(def, 0.5 * estimate, duration);
      double lo = 0.5 * estimate, hi = 3.0 * estimate;
      while (hi - lo > 1e-3 * lo) {
        const double mid = 0.5 * (lo + hi);
        (loaded_case_late_kinetic_J(def, mid, duration) > loaded_factor * reference ? hi : lo) = mid;
      }
      md << "| " << file << " | " << std::setprecision(6) << estimate << ", " << scene.stable_time_step.stiffest_element
         << " | " << lo << " | " << lo / estimate << " |\n";
    } catch (const std::exception& e) {
      std::cerr << "stability_limits: error: " << e.what() << "\n";
      return 1;
    }
  }
  try {
    fq::detail::write_file_atomically(prefix + ".csv", csv.str());
    fq::detail::write_file_atomically(prefix + ".md", md.str());
  } catch (const std::exception& e) {
    std::cerr << "stability_limits: error: " << e.what() << "\n";
    return 1;
  }
  std::cout << md.str();
  return 0;
}
