// The stable time step of a scene's springs and dashpots, linearised at the
// current pose (issue 6: "the engine estimates the critical time step of a
// scene from its stiffest translational and rotational modes").
//
// Every spring-dashpot of the scene (a joint spring, the normal or a
// tangential spring of a contact point) is one rank-one term: a stiffness k
// (N/m) and a dashpot c (N s/m) acting on the relative displacement of its
// two ends along a unit direction e. In mass-scaled coordinates (M^1/2
// times the bodies' velocities) that displacement's gradient is
// g = (e / sqrt(m), I^-1/2 (r x e)) per body (r the arm from the centre, I
// the world inertia tensor; zero for a fixed body), with a minus sign on
// body a. The scene's mass-scaled stiffness and dashpot matrices are
//   K~ = sum k g g^T,   C~ = sum c g g^T.
// Providers contribute their terms (ForceProvider::linearised_springs) and
// the estimate treats them as one network, so that a body held by a joint
// and resting on the ground gets the sum of both stiffnesses, and every
// dashpot counts with the mode it damps.
//
// Central difference with a dashpot read at v(n-1/2): with x(n) = (-1)^n
// phi the update gives -4 phi = -(dt^2 K~ + 2 dt C~) phi, so the step's
// amplification has a root at -1 exactly when 4 is an eigenvalue of
// dt^2 K~ + 2 dt C~. The limit is the dt where lambda_max(dt^2 K~ + 2 dt C~)
// = 4; for one mode of frequency omega and damping ratio zeta it is
// (2 / omega)(sqrt(1 + zeta^2) - zeta), and without dashpots 2 / omega.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "dem_core/body_store.h"
#include "dem_core/types.h"

namespace fq {

using Vec6 = Eigen::Matrix<double, 6, 1>;

struct LinearisedSpring {
  BodyId a = kNoBody;      // kNoBody: a fixed surface (the ground)
  BodyId b = kNoBody;
  double k_Npm = 0.0;      // stiffness (N/m)
  double c_Nspm = 0.0;     // dashpot (N s/m)
  Vec6 ga = Vec6::Zero();  // mass-scaled gradient on a (sign included)
  Vec6 gb = Vec6::Zero();  // on b
  std::int64_t element = 0;  // the provider's own index, for naming (ForceProvider::describe_linearised_spring)
};

// Mass-scaled gradient of a point displacement along unit e at world arm r
// from the centre of body i: (e / sqrt(m), I^-1/2 (r x e)) with the world
// inverse inertia (zero for a fixed body).
Vec6 mass_scaled_gradient(const BodyStore& bodies, BodyId i, const Vec3& arm_m, const Vec3& e);

struct NetworkStableStep {
  // Central-difference limit (s); +inf when the network has no stiffness.
  double dt_crit_s = std::numeric_limits<double>::infinity();
  // 2 / dt_crit_s: the frequency an undamped mode would need to set that
  // limit (rad/s); without dashpots exactly the top frequency. 0 = none.
  // NaN (and dt_crit_s NaN) when a product overflowed (a stiffness of
  // 1e308, a mass of 1e-300): no limit can be computed, which callers must
  // not take for "no stiffness".
  double omega_radps = 0.0;
  // The term storing most energy (dt^2 k + 2 dt c weighted) in the mode
  // that sets the limit; rows.size() when none.
  std::size_t stiffest = 0;
  // The work of the eigenvalue searches: Lanczos steps over all of them,
  // and products of the network's operator (each reads every block). The
  // products exceed the steps only where a search's Lanczos vectors did
  // not all fit in the memory kept for them (network_stable_step) and some
  // were made again to sum its Ritz vector.
  int lanczos_steps = 0;
  int operator_products = 0;
};

// The limit of the network `rows` over `n_bodies` bodies. The terms are
// summed once into 6x6 blocks (one per body, one per pair of bodies that
// share a term), and the top eigenvalues are found by the Lanczos
// recurrence on those blocks (from a deterministic pseudo-random start
// with a component along every degree of freedom), whose top Ritz value
// converges from below; it stops once that value grows by less than 1e-8
// of itself in each of 3 steps, or after 300 products (a chain of 3000
// bodies, whose top two modes differ by 3e-7, is then within 3e-6:
// tests/joints/test_stable_time_step.cpp). With dashpots, dt is iterated
// to the root of a dt^2 + 2 b dt = 4 (a, b the Rayleigh quotients of K~
// and C~ in the top eigenvector of dt^2 K~ + 2 dt C~ at the current dt),
// its only fixed point, which lies between the lower bound
//   2 / (sqrt(omega^2 + lambda_C^2 / 4) + lambda_C / 2)
// (lambda_max(A + B) <= lambda_max(A) + lambda_max(B)) and 2 / omega.
// kept_vector_bytes: the memory for the Lanczos vectors kept to sum each
// search's Ritz vector; those that do not fit are made again by repeating
// the recurrence (the same bits, one more product each). Without it: what
// the blocks leave of the memory the terms take, at least 64 MiB.
NetworkStableStep network_stable_step(const std::vector<LinearisedSpring>& rows, std::size_t n_bodies,
                                      std::optional<std::size_t> kept_vector_bytes = std::nullopt);

}  // namespace fq
