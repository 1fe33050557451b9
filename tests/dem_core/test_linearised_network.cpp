// The network's stable step (dem_core/linearised_network.h) against dense
// linear algebra on small networks, and the kept Lanczos vectors: the
// estimate sums the terms into 6x6 blocks per body and per pair of bodies
// and runs Lanczos on those; here every term is put into the full 6n x 6n
// matrices K~ and C~ one by one, whose top eigenvalue and damped limit
// GSL's symmetric eigensolver gives.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>

#include "dem_core/body_store.h"
#include "dem_core/linearised_network.h"

namespace fq {
namespace {

// Bodies of assorted sizes, densities and orientations; body 0 is fixed.
BodyStore assorted_bodies(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  BodyStore bodies;
  for (int i = 0; i < n; ++i) {
    BoxBodyDef box;
    for (int d = 0; d < 3; ++d) box.size_m[d] = 0.05 + 0.3 * unit(rng);  // drawn in order
    box.density_kg_per_m3 = 300.0 + 5000.0 * unit(rng);
    box.position_m = Vec3(i * 0.4, 0.0, 1.0);
    Eigen::Vector4d q;
    for (int d = 0; d < 4; ++d) q[d] = unit(rng) - 0.5;
    box.orientation = Quat(q[0], q[1], q[2], q[3]).normalized();
    box.fixed = i == 0;
    bodies.add_box(box);
  }
  bodies.update_rotations();
  return bodies;
}

// Terms as providers give them: several on one pair (a joint's corners, a
// contact's points), listed with either body first, some to the ground
// (kNoBody), some to the fixed body, one with both ends on one body.
std::vector<LinearisedSpring> assorted_terms(const BodyStore& bodies, bool dashpots, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int n = int(bodies.size());
  std::uniform_int_distribution<int> body(0, n - 1);
  auto centred = [&]() -> Vec3 {  // each in [-0.5, 0.5), drawn in order
    Vec3 v;
    for (int d = 0; d < 3; ++d) v[d] = unit(rng) - 0.5;
    return v;
  };
  auto direction = [&]() -> Vec3 { return centred().normalized(); };
  auto arm = [&]() -> Vec3 { return 0.2 * centred(); };
  std::vector<LinearisedSpring> rows;
  auto add = [&](BodyId a, BodyId b, int terms) {
    for (int t = 0; t < terms; ++t) {
      LinearisedSpring r;
      r.a = a;
      r.b = b;
      r.k_Npm = 1e4 * std::pow(100.0, unit(rng));
      r.c_Nspm = dashpots ? 100.0 * unit(rng) : 0.0;
      const Vec3 e = direction(), arm_a = arm(), arm_b = arm();
      if (a != kNoBody) r.ga = -mass_scaled_gradient(bodies, a, arm_a, e);
      if (b != kNoBody) r.gb = mass_scaled_gradient(bodies, b, arm_b, e);
      r.element = std::int64_t(rows.size());
      rows.push_back(r);
    }
  };
  for (int i = 1; i < n; ++i) add(BodyId(i - 1), BodyId(i), 4);  // a chain from the fixed body: connected
  for (int p = 0; p < 3 * n; ++p) {
    const int a = body(rng), b = body(rng);
    if (a != b) add(BodyId(a), BodyId(b), 1 + p % 4);
  }
  add(BodyId(n - 1), BodyId(n - 2), 3);  // a pair listed both ways round
  add(kNoBody, BodyId(2), 3);            // to the ground, either end
  add(BodyId(3), kNoBody, 2);
  add(BodyId(n / 2), BodyId(n / 2), 1);  // two points of one body
  return rows;
}

// The 6n x 6n matrix sum coef(term) g g^T, term by term.
template <class Coef>
Eigen::MatrixXd dense(const std::vector<LinearisedSpring>& rows, std::size_t n, const Coef& coef) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(Eigen::Index(6 * n), Eigen::Index(6 * n));
  for (const LinearisedSpring& r : rows) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(Eigen::Index(6 * n));
    if (r.a != kNoBody) g.segment<6>(6 * r.a) += r.ga;
    if (r.b != kNoBody) g.segment<6>(6 * r.b) += r.gb;
    m += coef(r) * g * g.transpose();
  }
  return m;
}

// The largest eigenvalue of a symmetric matrix by GSL's symmetric QR
// solver (gsl_eigen_symm), an implementation independent of the engine's
// Lanczos search. (Eigen's solver, compiled with this file at -O0 in the
// sanitizer build, took 14 s there for the bisections below.)
double top_eigenvalue(const Eigen::MatrixXd& m) {
  const std::size_t n = std::size_t(m.rows());
  Eigen::MatrixXd a = m;  // gsl_eigen_symm overwrites its input
  gsl_matrix_view view = gsl_matrix_view_array(a.data(), n, n);  // symmetric: row or column order alike
  gsl_vector* values = gsl_vector_alloc(n);
  gsl_eigen_symm_workspace* work = gsl_eigen_symm_alloc(n);
  const int status = gsl_eigen_symm(&view.matrix, values, work);
  const double top = gsl_vector_max(values);
  gsl_eigen_symm_free(work);
  gsl_vector_free(values);
  EXPECT_EQ(status, GSL_SUCCESS);
  return top;
}

// The damped limit: the dt where lambda_max(dt^2 K~ + 2 dt C~) = 4, by
// bisection (the left side grows with dt).
double dense_damped_limit(const Eigen::MatrixXd& k, const Eigen::MatrixXd& c) {
  double lo = 0.0, hi = 2.0 / std::sqrt(top_eigenvalue(k));
  for (int it = 0; it < 80; ++it) {
    const double dt = 0.5 * (lo + hi);
    (top_eigenvalue(dt * dt * k + 2.0 * dt * c) > 4.0 ? hi : lo) = dt;
  }
  return 0.5 * (lo + hi);
}

TEST(NetworkStableStep, BlocksGiveTheDenseTopEigenvalueAndDampedLimit) {
  std::mt19937 rng(20261127);
  for (int trial = 0; trial < 6; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const int n = 4 + 3 * trial;  // 4 to 19 bodies, 24 to 114 degrees of freedom
    const BodyStore bodies = assorted_bodies(n, rng);
    const bool dashpots = trial % 2 == 1;
    const std::vector<LinearisedSpring> rows = assorted_terms(bodies, dashpots, rng);
    const Eigen::MatrixXd k = dense(rows, bodies.size(), [](const LinearisedSpring& r) { return r.k_Npm; });
    const Eigen::MatrixXd c = dense(rows, bodies.size(), [](const LinearisedSpring& r) { return r.c_Nspm; });
    const NetworkStableStep s = network_stable_step(rows, bodies.size());
    ASSERT_LT(s.stiffest, rows.size());
    if (!dashpots) {
      const double omega = std::sqrt(top_eigenvalue(k));
      EXPECT_NEAR(s.omega_radps / omega, 1.0, 1e-11) << s.omega_radps << " rad/s against " << omega;
      EXPECT_NEAR(s.dt_crit_s * omega / 2.0, 1.0, 1e-11);
    } else {
      // The damped limit is iterated until a step moves it by less than
      // 1e-8 of itself (linearised_network.h), so it is known to that, not
      // to round-off: an audit (stop 42) found it 1.1e-9 above the dense
      // limit on one of 300 random networks, where this bound was 1e-10.
      const double dt = dense_damped_limit(k, c);
      EXPECT_NEAR(s.dt_crit_s / dt, 1.0, 1e-8) << s.dt_crit_s << " s against " << dt;
      EXPECT_NEAR(s.omega_radps * dt / 2.0, 1.0, 1e-8);
    }
  }
}

// Lanczos vectors that do not fit in the memory given are made again:
// more products, the same bits. A chain of 300 bodies with dashpots (about
// 300 steps over its three searches) with every vector kept, with none
// but the start, and with ten.
TEST(NetworkStableStep, KeptLanczosVectorsSaveProductsAndChangeNoBit) {
  const int n = 300;
  BodyStore bodies;
  BoxBodyDef box;
  box.size_m = Vec3(0.1, 0.1, 0.1);
  box.density_kg_per_m3 = 1000.0;
  for (int i = 0; i < n; ++i) {
    box.position_m = Vec3(0.2 * i, 0.0, 1.0);
    bodies.add_box(box);
  }
  std::vector<LinearisedSpring> rows;
  for (int i = 0; i <= n; ++i) {  // fixed-fixed chain along x, and a softer one along y
    const Vec3 axes[2] = {Vec3::UnitX(), Vec3::UnitY()};
    for (const Vec3& e : axes) {
      LinearisedSpring r;
      r.a = i == 0 ? kNoBody : BodyId(i - 1);
      r.b = i == n ? kNoBody : BodyId(i);
      r.k_Npm = e.x() > 0.5 ? 1.0e6 : 4.0e5;
      r.c_Nspm = 20.0;
      if (r.a != kNoBody) r.ga = -mass_scaled_gradient(bodies, r.a, Vec3::Zero(), e);
      if (r.b != kNoBody) r.gb = mass_scaled_gradient(bodies, r.b, Vec3::Zero(), e);
      rows.push_back(r);
    }
  }
  const NetworkStableStep all = network_stable_step(rows, bodies.size());
  const std::size_t vector_bytes = bodies.size() * sizeof(Vec6);
  const NetworkStableStep start_only = network_stable_step(rows, bodies.size(), 0);
  const NetworkStableStep ten = network_stable_step(rows, bodies.size(), 10 * vector_bytes);
  ASSERT_GT(all.lanczos_steps, 30);
  EXPECT_EQ(all.operator_products, all.lanczos_steps) << "every product is a Lanczos step";
  for (const NetworkStableStep* s : {&start_only, &ten}) {
    EXPECT_EQ(s->lanczos_steps, all.lanczos_steps);
    EXPECT_GT(s->operator_products, s->lanczos_steps);
    EXPECT_EQ(s->dt_crit_s, all.dt_crit_s);
    EXPECT_EQ(s->omega_radps, all.omega_radps);
    EXPECT_EQ(s->stiffest, all.stiffest);
  }
  EXPECT_LT(ten.operator_products, start_only.operator_products);
}

}  // namespace
}  // namespace fq
