#include "dem_core/linearised_network.h"

#include "dem_core/force_provider.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace fq {

Vec6 mass_scaled_gradient(const BodyStore& bodies, BodyId i, const Vec3& arm_m, const Vec3& e) {
  Vec6 g;
  g.head<3>() = e * std::sqrt(bodies.inverse_mass_per_kg[std::size_t(i)]);
  const Mat3& r = bodies.rotation[std::size_t(i)];
  const Vec3 inv_sqrt_inertia = bodies.inverse_inertia_per_kgm2[std::size_t(i)].cwiseSqrt();
  g.tail<3>() = r * inv_sqrt_inertia.cwiseProduct(r.transpose() * arm_m.cross(e));
  return g;
}

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

double projection(const LinearisedSpring& r, const std::vector<Vec6>& x) {
  return (r.a == kNoBody ? 0.0 : r.ga.dot(x[std::size_t(r.a)])) +
         (r.b == kNoBody ? 0.0 : r.gb.dot(x[std::size_t(r.b)]));
}

double dot(const std::vector<Vec6>& u, const std::vector<Vec6>& v) {
  double s = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) s += u[i].dot(v[i]);
  return s;
}

// The network assembled once into 6x6 blocks: K~ = sum k g g^T and C~ =
// sum c g g^T, one block per body on the diagonal and one per pair of
// bodies that share a term off it (the block of (lo, hi), lo < hi; that of
// (hi, lo) is its transpose). Lanczos applies the operator a few hundred
// times. Applied term by term, each product read every term (144 bytes;
// 4.4 million terms on a frame-B-style grid of 97 606 bodies) and did 24
// multiply-adds per term; a joint's 12 springs, or a contact's up to 4
// points of 3 springs, all act on one pair, and that grid has 362 880
// pairs, so the blocks of K~ take 133 MB against the terms' 638 MB and a
// product does 30 million multiply-adds instead of 106 million. The sums
// run in another order than term by term: the estimate agrees to round-off
// (relative 4e-14 on that grid, 4.4e-16 on frames A-C).
struct NetworkBlocks {
  std::size_t nb = 0;
  std::vector<std::int32_t> lo, hi;  // pair p joins bodies lo[p] < hi[p]
  std::vector<Mat6> off_k, off_c;    // block (lo, hi) of K~ and of C~
  std::vector<Mat6> diag_k, diag_c;  // block (i, i)
  bool has_dashpots = false;         // C~ != 0 (else off_c and diag_c are empty)

  std::size_t bytes() const {
    return (lo.size() + hi.size()) * sizeof(std::int32_t) +
           (off_k.size() + off_c.size() + diag_k.size() + diag_c.size()) * sizeof(Mat6);
  }

  NetworkBlocks(const std::vector<LinearisedSpring>& rows, std::size_t n_bodies) : nb(n_bodies) {
    for (const LinearisedSpring& r : rows) has_dashpots = has_dashpots || r.c_Nspm != 0.0;
    auto two_bodies = [](const LinearisedSpring& r) { return r.a != kNoBody && r.b != kNoBody && r.a != r.b; };
    auto key = [](const LinearisedSpring& r) {
      return std::uint64_t(std::uint32_t(std::min(r.a, r.b))) << 32 | std::uint64_t(std::uint32_t(std::max(r.a, r.b)));
    };
    // The pairs: the terms of a joint or a contact come one after another,
    // so runs of one pair are merged before sorting.
    std::vector<std::uint64_t> keys;
    for (const LinearisedSpring& r : rows)
      if (two_bodies(r) && (keys.empty() || keys.back() != key(r))) keys.push_back(key(r));
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    lo.resize(keys.size());
    hi.resize(keys.size());
    for (std::size_t p = 0; p < keys.size(); ++p) {
      lo[p] = std::int32_t(keys[p] >> 32);
      hi[p] = std::int32_t(keys[p] & 0xffffffffu);
    }
    off_k.assign(keys.size(), Mat6::Zero());
    diag_k.assign(nb, Mat6::Zero());
    if (has_dashpots) {
      off_c.assign(keys.size(), Mat6::Zero());
      diag_c.assign(nb, Mat6::Zero());
    }
    auto add = [&](std::vector<Mat6>& k_blocks, std::vector<Mat6>& c_blocks, std::size_t at, const LinearisedSpring& r,
                   const Vec6& u, const Vec6& v) {  // the term's k u v^T and c u v^T
      k_blocks[at].noalias() += (r.k_Npm * u) * v.transpose();
      if (has_dashpots) c_blocks[at].noalias() += (r.c_Nspm * u) * v.transpose();
    };
    std::uint64_t last_key = ~std::uint64_t(0);
    std::size_t last_pair = 0;
    for (const LinearisedSpring& r : rows) {
      if (two_bodies(r)) {
        if (key(r) != last_key) {
          last_key = key(r);
          last_pair = std::size_t(std::lower_bound(keys.begin(), keys.end(), last_key) - keys.begin());
        }
        const bool a_low = r.a < r.b;
        add(off_k, off_c, last_pair, r, a_low ? r.ga : r.gb, a_low ? r.gb : r.ga);
        add(diag_k, diag_c, std::size_t(r.a), r, r.ga, r.ga);
        add(diag_k, diag_c, std::size_t(r.b), r, r.gb, r.gb);
      } else if (r.a != kNoBody && r.a == r.b) {  // both ends on one body: one gradient, their sum
        const Vec6 g = r.ga + r.gb;
        add(diag_k, diag_c, std::size_t(r.a), r, g, g);
      } else if (r.a != kNoBody) {
        add(diag_k, diag_c, std::size_t(r.a), r, r.ga, r.ga);
      } else if (r.b != kNoBody) {
        add(diag_k, diag_c, std::size_t(r.b), r, r.gb, r.gb);
      }
    }
  }
};

// The operator s_k K~ + s_c C~ on vectors of one Vec6 per body.
struct NetworkOperator {
  const NetworkBlocks& blocks;
  double s_k = 1.0, s_c = 0.0;

  std::size_t size() const { return blocks.nb; }
  Mat6 block(const std::vector<Mat6>& k, const std::vector<Mat6>& c, std::size_t i) const {
    if (s_c == 0.0) return s_k * k[i];
    if (s_k == 0.0) return s_c * c[i];
    return s_k * k[i] + s_c * c[i];
  }
  void apply(const std::vector<Vec6>& x, std::vector<Vec6>& y) const {
    const NetworkBlocks& n = blocks;
    if (s_c == 0.0 && s_k == 1.0) {  // K~ itself: the blocks as stored
      for (std::size_t i = 0; i < n.nb; ++i) y[i].noalias() = n.diag_k[i] * x[i];
      for (std::size_t p = 0; p < n.lo.size(); ++p) {
        const auto i = std::size_t(n.lo[p]), j = std::size_t(n.hi[p]);
        y[i].noalias() += n.off_k[p] * x[j];
        y[j].noalias() += n.off_k[p].transpose() * x[i];
      }
      return;
    }
    for (std::size_t i = 0; i < n.nb; ++i) y[i].noalias() = block(n.diag_k, n.diag_c, i) * x[i];
    for (std::size_t p = 0; p < n.lo.size(); ++p) {
      const auto i = std::size_t(n.lo[p]), j = std::size_t(n.hi[p]);
      const Mat6 b = block(n.off_k, n.off_c, p);
      y[i].noalias() += b * x[j];
      y[j].noalias() += b.transpose() * x[i];
    }
  }
};

// Largest eigenvalue of the symmetric tridiagonal matrix with diagonal
// alpha and off-diagonal beta (its first alpha.size() - 1 entries), not
// below `lower`, by bisection on the Sturm count (the number of negative
// pivots of T - x I in its LDL^T factorisation is the number of
// eigenvalues below x), from Gershgorin's upper bound to the last bits.
double top_tridiagonal_eigenvalue(const std::vector<double>& alpha, const std::vector<double>& beta, double lower) {
  const std::size_t k = alpha.size();
  double hi = -std::numeric_limits<double>::infinity(), lo = lower;
  for (std::size_t i = 0; i < k; ++i) {
    const double off = (i > 0 ? std::fabs(beta[i - 1]) : 0.0) + (i + 1 < k ? std::fabs(beta[i]) : 0.0);
    hi = std::max(hi, alpha[i] + off);
    lo = std::min(lo, alpha[i] - off);
  }
  auto all_below = [&](double x) {  // true when every eigenvalue is below x
    double d = 1.0;
    for (std::size_t i = 0; i < k; ++i) {
      const double b2 = i > 0 ? beta[i - 1] * beta[i - 1] : 0.0;
      d = alpha[i] - x - (i > 0 ? b2 / d : 0.0);
      if (d == 0.0) d = -1e-300;  // a pivot of exactly 0: count it as negative, the usual choice
      if (d > 0.0) return false;
    }
    return true;
  };
  for (int it = 0; it < 200 && hi - lo > 4e-16 * std::max(std::fabs(hi), std::fabs(lo)); ++it) {
    const double mid = 0.5 * (lo + hi);
    (all_below(mid) ? hi : lo) = mid;
  }
  return hi;
}

// Products and steps of the searches (NetworkStableStep).
struct LanczosWork {
  int steps = 0;
  int products = 0;
};

// Largest eigenvalue of the operator by the Lanczos recurrence, and its
// Ritz vector, normalised, left in x (which holds the start on entry, and
// the start normalised on return without want_vector).
// The top Ritz value of k steps is the largest eigenvalue of the k x k
// tridiagonal matrix T_k (alpha on the diagonal, beta beside it); it never
// exceeds lambda_max and grows towards it with k (Cauchy interlacing), as
// the power iteration's Rayleigh quotient did, but after far fewer products:
// the error of k steps falls like a Chebyshev polynomial of degree k, that
// of k power steps like (lambda_2 / lambda_1)^k (Golub and Van Loan, Matrix
// Computations, 4th ed., sections 10.1.5 and 10.1.6). Without
// reorthogonalisation, lost orthogonality only repeats converged Ritz
// values (Paige); the recurrence stops once the top value has settled.
// The Ritz vector sums the Lanczos vectors q_0..q_k-1 with weights known
// only at the end. The first max_kept of them are kept as the recurrence
// makes them (with want_vector); the rest, if any, are made again by
// repeating the recurrence from the last two kept, with the same numbers,
// so the vector is the same bits however many were kept. Returns NaN when
// a product overflowed.
double top_eigenpair(const NetworkOperator& op, std::vector<Vec6>& x, int max_steps, std::size_t max_kept,
                     LanczosWork& work, bool want_vector = true) {
  const std::size_t nb = op.size();
  const double norm0 = std::sqrt(dot(x, x));
  if (!(norm0 > 0.0) || !std::isfinite(norm0)) return 0.0;
  for (Vec6& v : x) v /= norm0;
  std::vector<std::vector<Vec6>> kept{x};  // q_0 .. q_kept-1 (q_0, the start, always)

  std::vector<Vec6> q_prev(nb, Vec6::Zero()), q = x, w(nb);
  std::vector<double> alpha, beta;  // beta[j]: between q_j and q_{j+1}
  double theta = 0.0;
  int settled_steps = 0;
  for (int j = 0; j < max_steps; ++j) {
    op.apply(q, w);
    ++work.products;
    ++work.steps;
    const double a = dot(q, w);
    if (!std::isfinite(a)) return std::numeric_limits<double>::quiet_NaN();
    const double b_prev = j == 0 ? 0.0 : beta.back();
    double ww = 0.0;  // dot(w, w), summed in the same order
    for (std::size_t i = 0; i < nb; ++i) {
      w[i] -= a * q[i] + b_prev * q_prev[i];
      ww += w[i].dot(w[i]);
    }
    const double b = std::sqrt(ww);
    if (!std::isfinite(b)) return std::numeric_limits<double>::quiet_NaN();
    alpha.push_back(a);
    beta.push_back(b);

    // Settled: the top value has grown by less than 1e-8 of itself in each
    // of 3 steps (in a top cluster the vector converges slowly while the
    // value already has), or the space is exhausted (an invariant subspace:
    // beta ~ 0, as in a scene of a few bodies).
    const double next = top_tridiagonal_eigenvalue(alpha, beta, theta);
    settled_steps = (j > 0 && next - theta <= 1e-8 * next) ? settled_steps + 1 : 0;
    theta = next;
    const bool breakdown = !(b > 1e-14 * std::max(theta, std::fabs(a)));
    if (settled_steps >= 3 || breakdown || !(theta > 0.0)) break;
    for (Vec6& v : w) v /= b;
    q_prev.swap(q);  // q_prev <- q, q <- w / b; w is overwritten by the next product
    q.swap(w);
    if (want_vector && kept.size() < max_kept) kept.push_back(q);
  }
  if (!(theta > 0.0)) return 0.0;
  if (!want_vector) return theta;

  // The Ritz vector, whose coefficients in q_0..q_k-1 are T_k's top
  // eigenvector: the kept vectors, then the rest made again.
  const std::size_t k = alpha.size();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tri;
  tri.computeFromTridiagonal(Eigen::Map<const Eigen::VectorXd>(alpha.data(), Eigen::Index(k)),
                             Eigen::Map<const Eigen::VectorXd>(beta.data(), Eigen::Index(k - 1)),
                             Eigen::ComputeEigenvectors);
  const Eigen::VectorXd ritz = tri.eigenvectors().col(Eigen::Index(k - 1));  // eigenvalues ascend
  for (std::size_t i = 0; i < nb; ++i) x[i] = ritz(0) * kept[0][i];
  std::size_t j = 1;
  for (; j < k && j < kept.size(); ++j)
    for (std::size_t i = 0; i < nb; ++i) x[i] += ritz(Eigen::Index(j)) * kept[j][i];
  if (j < k) {  // q_j from q_j-1 and q_j-2, as the recurrence made it
    q = kept[j - 1];
    if (j >= 2)
      q_prev = kept[j - 2];
    else
      for (Vec6& v : q_prev) v.setZero();
    kept.clear();
    for (; j < k; ++j) {
      op.apply(q, w);
      ++work.products;
      const double b_prev = j == 1 ? 0.0 : beta[j - 2];
      for (std::size_t i = 0; i < nb; ++i) {
        w[i] -= alpha[j - 1] * q[i] + b_prev * q_prev[i];
        q_prev[i] = q[i];
        q[i] = w[i] / beta[j - 1];
        x[i] += ritz(Eigen::Index(j)) * q[i];
      }
    }
  }
  const double norm = std::sqrt(dot(x, x));
  if (norm > 0.0)
    for (Vec6& v : x) v /= norm;
  return theta;
}

}  // namespace

NetworkStableStep network_stable_step(const std::vector<LinearisedSpring>& rows, std::size_t nb,
                                      std::optional<std::size_t> kept_vector_bytes) {
  NetworkStableStep result;
  result.stiffest = rows.size();
  if (rows.empty() || nb == 0) return result;

  const NetworkBlocks blocks(rows, nb);
  std::vector<Vec6> x(nb);
  // A deterministic start with a component along every mode: entries drawn
  // from [-1, 1) by a fixed hash of their index (splitmix64). A smooth
  // start (the earlier 1 + 0.1 sin(7 i + d + 1)) holds little of the
  // alternating top modes of a long chain: on one of 30 bodies even 400
  // power steps stopped 3e-3 short of omega_max.
  auto reset_start = [&] {
    for (std::size_t i = 0; i < nb; ++i)
      for (int d = 0; d < 6; ++d) {
        std::uint64_t z = std::uint64_t(6 * i + std::size_t(d)) + 0x9e3779b97f4a7c15ULL;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        z ^= z >> 31;
        x[i][d] = double(z >> 11) * 0x1.0p-52 - 1.0;
      }
  };
  constexpr int kMaxSteps = 300;
  // Lanczos vectors kept for the Ritz vectors (top_eigenpair): as many as
  // fit, with the blocks, in the memory the terms take (which the caller
  // holds), and at least 64 MiB's worth. On the frame-B-style grid of
  // 97 606 bodies the terms take 638 MB, the blocks 268 MB, and 79 vectors
  // of 4.7 MB are kept: the searches' 360 steps need 402 products instead
  // of 551.
  const std::size_t row_bytes = rows.size() * sizeof(LinearisedSpring);
  const std::size_t kept_bytes =
      kept_vector_bytes.value_or(std::max(row_bytes - std::min(row_bytes, blocks.bytes()), std::size_t(64) << 20));
  const std::size_t max_kept = std::max<std::size_t>(1, kept_bytes / (nb * sizeof(Vec6)));  // q_0 always
  LanczosWork work;
  reset_start();
  const double lambda_c = blocks.has_dashpots ? top_eigenpair(NetworkOperator{blocks, 0.0, 1.0}, x, kMaxSteps,
                                                              max_kept, work, /*want_vector=*/false)
                                              : 0.0;
  reset_start();
  const double omega2 =
      top_eigenpair(NetworkOperator{blocks, 1.0, 0.0}, x, kMaxSteps, max_kept, work);  // x: top stiffness mode
  result.lanczos_steps = work.steps;
  result.operator_products = work.products;
  if (std::isnan(omega2) || std::isnan(lambda_c)) {
    result.omega_radps = std::numeric_limits<double>::quiet_NaN();
    result.dt_crit_s = std::numeric_limits<double>::quiet_NaN();
    return result;
  }
  if (!(omega2 > 0.0)) return result;
  // The damped limit itself (header). The bound takes omega and lambda_C
  // from two different modes when the stiffest mode is not the most
  // damped: on the breaking-cantilever demo it gave 7.15e-5 s where the
  // iteration gives 7.78e-5 s, and runs with every mode excited are
  // bounded at 0.99 of the latter and not at 1.01 (docs/speed_accuracy.md).
  const double dt_bound = 2.0 / (std::sqrt(omega2 + 0.25 * lambda_c * lambda_c) + 0.5 * lambda_c);
  const double dt_undamped = 2.0 / std::sqrt(omega2);
  double dt_crit = dt_undamped;
  if (lambda_c > 0.0) {
    double dt = dt_bound;
    for (int outer = 0; outer < 12; ++outer) {
      // Warm start: the top vector of the previous dt (or of K~).
      const double top = top_eigenpair(NetworkOperator{blocks, dt * dt, 2.0 * dt}, x, kMaxSteps, max_kept, work);
      result.lanczos_steps = work.steps;
      result.operator_products = work.products;
      if (!(top > 0.0)) break;
      double a = 0.0, b = 0.0;
      for (const LinearisedSpring& r : rows) {
        const double proj = projection(r, x);
        a += r.k_Npm * proj * proj;
        b += r.c_Nspm * proj * proj;
      }
      const double xx = dot(x, x);
      if (!(xx > 0.0) || !(a > 0.0)) break;
      a /= xx;
      b /= xx;
      const double next = 2.0 / (std::sqrt(a + 0.25 * b * b) + 0.5 * b);  // root of a dt^2 + 2 b dt = 4
      // Settled to the precision of the eigenvalues themselves (each
      // Lanczos search stops once its value grows by less than 1e-8).
      const bool settled = std::fabs(next - dt) <= 1e-8 * dt;
      dt = next;
      if (settled) break;
    }
    dt_crit = std::clamp(dt, dt_bound, dt_undamped);
  }
  // The term storing most energy in the mode that sets the limit (the last
  // top eigenvector: of K~, or of dt^2 K~ + 2 dt C~ with dashpots).
  const double w_k = lambda_c > 0.0 ? dt_crit * dt_crit : 1.0, w_c = lambda_c > 0.0 ? 2.0 * dt_crit : 0.0;
  double best_energy = -1.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const LinearisedSpring& r = rows[k];
    const double proj = projection(r, x);
    const double energy = (w_k * r.k_Npm + w_c * r.c_Nspm) * proj * proj;
    if (energy > best_energy) {
      best_energy = energy;
      result.stiffest = k;
    }
  }
  result.dt_crit_s = dt_crit;
  result.omega_radps = lambda_c > 0.0 ? 2.0 / dt_crit : std::sqrt(omega2);  // undamped: omega itself, to the bit
  return result;
}

StiffestMode ForceProvider::stiffest_mode(const BodyStore& bodies) const {
  std::vector<LinearisedSpring> rows;
  linearised_springs(bodies, rows);
  const NetworkStableStep now = network_stable_step(rows, bodies.size());
  StiffestMode mode = later_stiffest_mode(bodies);
  if (now.omega_radps > mode.omega_radps || std::isnan(now.omega_radps)) {
    mode.omega_radps = now.omega_radps;
    mode.where = now.stiffest < rows.size() ? describe_linearised_spring(bodies, rows[now.stiffest].element)
                                            : std::string("a spring whose stiffness or body overflows");
  }
  return mode;
}

}  // namespace fq
