// Stability limits of every integrator on a jointed chain, against theory.
//
// Scene: the 5-box chain of tests/joints/test_stable_time_step.cpp (boxes
// of different proportions on a fixed base, four-corner linear joints,
// undamped), started with small random velocities that excite every mode.
// For each integrator the largest stable dt is found by bisection: a run of
// `steps` steps is unstable when the largest displacement from rest in its
// second half exceeds twice that of its first half (or the state stops
// being finite). Theory: dt = factor / omega_max, omega_max from
// JointSystem::stiffest_mode (power iteration on M^-1/2 K M^-1/2), factor
// 2 for central difference, velocity Verlet and symplectic Euler, 2 sqrt 2
// for RK4 (integrator.h); forward Euler is checked to grow at every dt.
//
// Usage: stability_limits [OUT_PREFIX]   (default validation/stability_limits)
// writes OUT_PREFIX.csv and OUT_PREFIX.md and prints the markdown table.
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>
#include <string>

#include "dem_core/simulation.h"
#include "joints/joint_layout.h"
#include "joints/joint_system.h"

namespace {

using namespace fq;

BodyStore chain_bodies(int n) {
  BodyStore store;
  BoxBodyDef base;
  base.name = "base";
  base.size_m = Vec3(0.05, 0.05, 0.02);
  base.density_kg_per_m3 = 500;
  base.position_m = Vec3(0, 0, -0.01);
  base.fixed = true;
  store.add_box(base);
  double z = 0.0;
  for (int i = 0; i < n; ++i) {
    BoxBodyDef b;
    b.name = "link_" + std::to_string(i);
    const double h = 0.1 + 0.02 * i;
    b.size_m = Vec3(0.02 + 0.002 * i, 0.03, h);
    b.density_kg_per_m3 = 500;
    b.position_m = Vec3(0, 0, z + 0.5 * h);
    z += h;
    store.add_box(b);
  }
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  store.update_rotations();
  for (BodyId b = 1; b < BodyId(store.size()); ++b) {
    store.velocity_mps[b] = 1e-4 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 w = 1e-3 * Vec3(u(rng), u(rng), u(rng));
    const Mat3& r = store.rotation[b];
    store.angular_velocity_radps[b] = w;
    store.angular_momentum_Nms[b] = r * store.principal_inertia_kgm2[b].asDiagonal() * (r.transpose() * w);
  }
  return store;
}

void add_chain_joints(JointSystem& js, const BodyStore& store) {
  double z = 0.0;
  for (BodyId b = 1; b < BodyId(store.size()); ++b) {
    JointDef d;
    d.body_a = b - 1;
    d.body_b = b;
    d.origin_m = Vec3(0, 0, z);
    d.layout = four_corner_layout(0.01, 0.015, 1.0, linear_spring(2e4 * double(b), 0.0), linear_spring(5e4, 0.0));
    js.add_joint(store, d);
    z += 2.0 * store.half_extents_m[b].z();
  }
}

// Peak displacement of the second half of the run over that of the first.
double growth(Integrator method, double dt_s, int steps) {
  BodyStore store = chain_bodies(5);
  const std::vector<Vec3> rest = store.position_m;
  SimulationSettings s;
  s.dt_s = dt_s;
  s.duration_s = dt_s * steps;
  s.gravity_mps2 = Vec3::Zero();
  s.integrator = method;
  Simulation sim(std::move(store), s);
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs());
  add_chain_joints(*js, sim.bodies());
  sim.add_force_provider(std::move(js));
  double first = 0.0, second = 0.0;
  for (int n = 0; n < steps; ++n) {
    if (!sim.step()) return HUGE_VAL;
    double peak = 0.0;
    for (std::size_t b = 1; b < sim.bodies().size(); ++b)
      peak = std::max(peak, (sim.bodies().position_m[b] - rest[b]).norm());
    if (!std::isfinite(peak) || peak > 1.0) return HUGE_VAL;
    (n < steps / 2 ? first : second) = std::max(n < steps / 2 ? first : second, peak);
  }
  return second / first;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string prefix = argc > 1 ? argv[1] : "validation/stability_limits";
  BodyStore probe_store = chain_bodies(5);
  JointSystem probe(nullptr);
  add_chain_joints(probe, probe_store);
  const StiffestMode mode = probe.stiffest_mode(probe_store);
  const double omega = mode.omega_radps;
  const int steps = 4000;
  std::ostringstream md, csv;
  md << "Jointed chain, omega_max = " << omega << " rad/s (" << mode.where << "), " << steps
     << " steps per trial, bisection to 1e-4 relative\n\n";
  md << "| integrator | bisected dt (s) | omega dt | theory omega dt | estimate dt (s) | bisected / estimate |\n";
  md << "|---|---|---|---|---|---|\n";
  csv << "integrator,dt_bisected_s,omega_dt,omega_dt_theory,dt_estimate_s,ratio\n";
  for (Integrator m : {Integrator::CentralDifference, Integrator::VelocityVerlet, Integrator::SymplecticEuler,
                       Integrator::RungeKutta4}) {
    const double factor = integrator_stability_factor(m);
    const double estimate = factor / omega;
    double lo = 0.5 * estimate, hi = 1.5 * estimate;
    while (hi - lo > 1e-4 * lo) {
      const double mid = 0.5 * (lo + hi);
      (growth(m, mid, steps) < 2.0 ? lo : hi) = mid;
    }
    const double dt = 0.5 * (lo + hi);
    md << "| " << integrator_name(m) << " | " << std::setprecision(6) << dt << " | " << omega * dt << " | " << factor
       << " | " << estimate << " | " << dt / estimate << " |\n";
    csv << integrator_name(m) << "," << std::setprecision(10) << dt << "," << omega * dt << "," << factor << ","
        << estimate << "," << dt / estimate << "\n";
  }
  // Forward Euler: growth at every dt, here at a tenth of the CD limit.
  const double fe_dt = 0.2 / omega;
  const double fe_growth = growth(Integrator::ForwardEuler, fe_dt, steps);
  md << "| forward_euler | none (grows by " << std::setprecision(4) << fe_growth << " at omega dt = 0.2) | - | 0 | 0 | - |\n";
  csv << "forward_euler,0,0,0,0," << fe_growth << "\n";
  std::ofstream(prefix + ".csv") << csv.str();
  std::ofstream(prefix + ".md") << md.str();
  std::cout << md.str();
  return 0;
}
