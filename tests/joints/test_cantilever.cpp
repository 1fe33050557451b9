// Cantilever of N rigid elements joined by calibrated joints
// (calibrated_beam_layout) on a fixed base, against beam theory.
//
// Discrete closed form (derived here, the reference for the static test).
// Elements of length L = l/N; joint i at z_i = i L. The base joint stands
// for the half segment between the base and the first element's centre
// (segment length L/2, stiffness 2EI/L, 2 kappa G A/L); the others for one
// segment L (EI/L, kappa G A/L). Under a tip load P the moment at joint i
// is P (l - z_i); its rotation M_i / K_i turns everything above it, moving
// the tip by theta_i (l - z_i); each shear spring slips P / K_s,i:
//   bending: P/EI [ (L/2) l^2 + L sum_{i=1}^{N-1} (l - iL)^2 ]
//          = P L^3 / EI [ N^2/2 + (N-1) N (2N-1)/6 ] = P L^3 (2N^3 + N) / (6 EI)
//          = (P l^3 / 3EI) (1 + 1/(2N^2))
//   shear:   P/(kappa G A) [ L/2 + (N-1) L ] = (P l / kappa G A)(1 - 1/(2N))
// (the top half element is rigid). Against Timoshenko (P l^3/3EI + P l/kGA)
// the relative error is e_b/(2N^2) - e_s/(2N), e_b and e_s the bending and
// shear fractions, so |error| <= 1/(2N^2) + e_s/(2N).
//
// First frequency: the chain is compared with the exact eigenvalue of the
// same chain written independently as a planar model (lateral u_i and
// rotation theta_i per element, the springs above, element mass m and
// rotary inertia m (L^2 + b^2)/12), and that eigenvalue with Euler-Bernoulli
// w1 = 1.8751^2 sqrt(EI / (rho A l^4)). The chain is a midpoint-rule
// quadrature of the beam's strain energy with exact rigid-element inertia,
// so its eigenvalue error is O(L^2): for the first mode the midpoint error of
// int (w'')^2 is (L^2/24) int f'' / int f with f'' / f ~ 4 beta1^2 / l^2,
// i.e. ~ 0.6 / N^2 on w^2, ~ 0.3 / N^2 on w; shear and rotary inertia
// (Timoshenko/Rayleigh) lower w by ~ (1/2) beta1^2 (r/l)^2 (1 + E/kappa G).
// Asserted bound: |w_chain / w_EB - 1| <= 1/N^2 + beta1^2 (r/l)^2 (1 + E/kappa G).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>
#include <cmath>
#include <cstdio>

#include "dem_core/simulation.h"
#include "joint_test_util.h"

namespace fq {
namespace {

constexpr double kE = 1e10, kG = kE / 16.0;  // softwood along the grain: G ~ E/16
constexpr double kBeta1 = 1.87510407;

struct Chain {
  test::ChainSpec spec;
  BeamSection sec;
  double L = 0.0;
  explicit Chain(int n) {
    spec.n = n;
    sec = rectangular_section(spec.width_m, spec.depth_m);
    L = spec.length_m / n;
  }
  JointLayout layout(int i) const { return calibrated_beam_layout(sec, kE, kG, i == 0 ? 0.5 * L : L); }
};

// Tip deflection along x from a static solve of the chain's force routine.
double static_tip_deflection(const Chain& c, double p_N) {
  BondedPairs bonded;
  BodyStore store = test::chain_bodies(c.spec);
  JointSystem js(&bonded);
  test::add_chain_joints(js, store, c.spec, [&](int i) { return c.layout(i); });
  js.prepare(store);
  const Eigen::MatrixXd k = test::system_stiffness(js, store, 1e-9, 1e-8);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(k.rows());
  const Eigen::Index last = 6 * (c.spec.n - 1);
  f(last + 0) = p_N;              // P along x at the tip point (z = l)
  f(last + 4) = 0.5 * c.L * p_N;  // its moment about the last centre: (L/2) z x P x = (L/2) P y
  const Eigen::VectorXd u = k.partialPivLu().solve(f);
  return u(last + 0) + u(last + 4) * 0.5 * c.L;
}

TEST(Cantilever, StaticTipDeflectionMatchesDiscreteClosedFormAndConverges) {
  const double p = 1.0;
  double err10 = 0.0;
  for (int n : {10, 40}) {
    const Chain c(n);
    const double ei = kE * c.sec.inertia_2_m4, kga = c.sec.shear_coefficient * kG * c.sec.area_m2;
    const double l = c.spec.length_m;
    const double bend = p * l * l * l / (3 * ei), shear = p * l / kga;
    const double discrete = bend * (1 + 1.0 / (2.0 * n * n)) + shear * (1 - 1.0 / (2.0 * n));
    const double tip = static_tip_deflection(c, p);
    // Finite-difference stiffness of linear springs: exact up to round-off.
    EXPECT_NEAR(tip, discrete, 1e-6 * discrete) << "N = " << n;
    const double timoshenko = bend + shear;
    const double err = tip / timoshenko - 1.0;
    const double es = shear / timoshenko;
    EXPECT_LE(std::abs(err), 1.0 / (2.0 * n * n) + es / (2.0 * n)) << "N = " << n;
    std::printf(
        "cantilever static N=%d: tip %.6e m, Timoshenko %.6e m, EB %.6e m, error vs Timoshenko %.3e, vs EB %.3e\n", n,
        tip, timoshenko, bend, err, tip / bend - 1.0);
    if (n == 10)
      err10 = err;
    else
      EXPECT_LT(std::abs(err), std::abs(err10));
  }
}

// Planar reference chain: exact first eigenvalue and mode (u_i, theta_i).
struct Mode {
  double omega_radps = 0.0;
  Eigen::VectorXd shape;
};
Mode planar_chain_mode(const Chain& c) {
  const int n = c.spec.n;
  const double L = c.L, b = c.spec.width_m;
  const double ei = kE * c.sec.inertia_2_m4, kga = c.sec.shear_coefficient * kG * c.sec.area_m2;
  const double m = c.spec.density_kg_per_m3 * b * c.spec.depth_m * L;
  const double j = m * (L * L + b * b) / 12.0;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(2 * n, 2 * n), mm = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int i = 0; i < n; ++i) {
    mm(2 * i, 2 * i) = m;
    mm(2 * i + 1, 2 * i + 1) = j;
    const double kb = (i == 0 ? 2.0 : 1.0) * ei / L, ks = (i == 0 ? 2.0 : 1.0) * kga / L;
    // slip s = u_i - theta_i L/2 - u_{i-1} - theta_{i-1} L/2; jump r = theta_i - theta_{i-1}.
    Eigen::VectorXd gs = Eigen::VectorXd::Zero(2 * n), gr = Eigen::VectorXd::Zero(2 * n);
    gs(2 * i) = 1.0;
    gs(2 * i + 1) = -0.5 * L;
    gr(2 * i + 1) = 1.0;
    if (i > 0) {
      gs(2 * i - 2) = -1.0;
      gs(2 * i - 1) = -0.5 * L;
      gr(2 * i - 1) = -1.0;
    }
    k += ks * gs * gs.transpose() + kb * gr * gr.transpose();
  }
  // K x = omega^2 M x by GSL's symmetric-definite solver (gsl_eigen_gensymmv;
  // Eigen's GeneralizedSelfAdjointEigenSolver made this file the costliest
  // test file to compile, 16 s). Symmetric matrices read alike in GSL's
  // row order and Eigen's column order; the shape's scale does not matter
  // (the run scales it by its tip).
  const std::size_t dofs = std::size_t(2 * n);
  gsl_matrix_view kv = gsl_matrix_view_array(k.data(), dofs, dofs);  // both overwritten
  gsl_matrix_view mv = gsl_matrix_view_array(mm.data(), dofs, dofs);
  gsl_vector* values = gsl_vector_alloc(dofs);
  gsl_matrix* vectors = gsl_matrix_alloc(dofs, dofs);
  gsl_eigen_gensymmv_workspace* work = gsl_eigen_gensymmv_alloc(dofs);
  EXPECT_EQ(gsl_eigen_gensymmv(&kv.matrix, &mv.matrix, values, vectors, work), GSL_SUCCESS);
  gsl_eigen_gensymmv_sort(values, vectors, GSL_EIGEN_SORT_VAL_ASC);
  Mode first{std::sqrt(gsl_vector_get(values, 0)), Eigen::VectorXd(2 * n)};
  for (std::size_t i = 0; i < dofs; ++i) first.shape(Eigen::Index(i)) = gsl_matrix_get(vectors, i, 0);
  gsl_eigen_gensymmv_free(work);
  gsl_matrix_free(vectors);
  gsl_vector_free(values);
  return first;
}

double simulated_first_frequency(const Chain& c, const Mode& mode) {
  BodyStore bodies = test::chain_bodies(c.spec);
  double omega_max = 0.0;
  {
    JointSystem probe(nullptr);
    test::add_chain_joints(probe, bodies, c.spec, [&](int i) { return c.layout(i); });
    omega_max = probe.stiffest_mode(bodies).omega_radps;
  }
  SimulationSettings settings;
  settings.gravity_mps2 = Vec3::Zero();
  // dt = 0.5 * 2/omega_max (central difference stability limit 2/omega_max).
  settings.dt_s = 1.0 / omega_max;
  Simulation sim(std::move(bodies), settings);
  auto js = std::make_unique<JointSystem>(&sim.bonded_pairs());
  test::add_chain_joints(*js, sim.bodies(), c.spec, [&](int i) { return c.layout(i); });
  // Start from the first mode (tip amplitude 1e-4 l: small deformations).
  BodyStore& b = sim.bodies();
  const int n = c.spec.n;
  const double scale = 1e-4 * c.spec.length_m / (mode.shape(2 * n - 2) + mode.shape(2 * n - 1) * 0.5 * c.L);
  for (int i = 0; i < n; ++i) {
    b.position_m[std::size_t(i + 1)].x() += scale * mode.shape(2 * i);
    b.orientation[std::size_t(i + 1)] = Quat(Eigen::AngleAxisd(scale * mode.shape(2 * i + 1), Vec3::UnitY()));
  }
  sim.add_force_provider(std::move(js));
  const double dt = settings.dt_s;
  const double period = 2.0 * M_PI / mode.omega_radps;
  // Starting at the extreme, crossings fall at T/4, 3T/4, 5T/4: 1.35 periods give three.
  const auto steps = std::int64_t(1.35 * period / dt);
  // Tip x from the last element's pose.
  auto tip_x = [&]() {
    const BodyStore& s = sim.bodies();
    return s.to_world(BodyId(n), Vec3(0, 0, 0.5 * c.L)).x();
  };
  sim.initialize();
  std::vector<double> crossings;
  double prev = tip_x(), t_prev = 0.0;
  for (std::int64_t k = 0; k < steps; ++k) {
    sim.step();
    const double x = tip_x(), t = sim.time_s();
    if ((prev > 0.0) != (x > 0.0)) crossings.push_back(t_prev + (t - t_prev) * prev / (prev - x));
    prev = x;
    t_prev = t;
  }
  EXPECT_GE(crossings.size(), 3u);
  if (crossings.size() < 3) return 0.0;
  const std::size_t last = crossings.size() % 2 == 1 ? crossings.size() - 1 : crossings.size() - 2;
  const double t_period = (crossings[last] - crossings[0]) / (0.5 * double(last));
  return 2.0 * M_PI / t_period;
}

TEST(Cantilever, FirstFrequencyApproachesEulerBernoulli) {
  for (int n : {10, 40}) {
    const Chain c(n);
    const Mode mode = planar_chain_mode(c);
    const double l = c.spec.length_m;
    const double ei = kE * c.sec.inertia_2_m4;
    const double rho_a = c.spec.density_kg_per_m3 * c.sec.area_m2;
    const double w_eb = kBeta1 * kBeta1 * std::sqrt(ei / (rho_a * l * l * l * l));
    const double r2 = c.sec.inertia_2_m4 / c.sec.area_m2 / (l * l);
    const double bound = 1.0 / (n * n) + kBeta1 * kBeta1 * r2 * (1.0 + kE / (c.sec.shear_coefficient * kG));
    EXPECT_LE(std::abs(mode.omega_radps / w_eb - 1.0), bound) << "N = " << n;
    const double w_sim = simulated_first_frequency(c, mode);
    // Leapfrog period error (w dt)^2/24 with w1 dt << 0.01 and linear
    // interpolation of the crossings: far below 1e-3.
    EXPECT_NEAR(w_sim, mode.omega_radps, 1e-3 * mode.omega_radps) << "N = " << n;
    std::printf(
        "cantilever frequency N=%d: simulated %.6f rad/s, chain eigenvalue %.6f, Euler-Bernoulli %.6f, "
        "error vs EB %.3e (bound %.3e)\n",
        n, w_sim, mode.omega_radps, w_eb, w_sim / w_eb - 1.0, bound);
  }
}

}  // namespace
}  // namespace fq
