#include "lanczos.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace losmimo::placement::detail {

Eigen::Index lanczos(const Eigen::MatrixXcd& G, Eigen::Index steps, Eigen::MatrixXcd& V, Eigen::VectorXd& alpha,
                     Eigen::VectorXd& beta) {
  const Eigen::Index n = G.cols();
  steps = std::min(steps, n);
  V.resize(n, steps);
  alpha.resize(steps);
  beta.resize(std::max<Eigen::Index>(steps - 1, 0));
  const double trace = G.diagonal().real().sum();
  Eigen::Index k_max = 0;
  G.colwise().squaredNorm().maxCoeff(&k_max);
  Eigen::VectorXcd w = G.col(k_max);
  Eigen::Index k = 0;
  for (; k < steps; ++k) {
    const double norm = w.norm();
    if (!(norm > 1e-12 * std::sqrt(std::abs(trace)))) break;  // an invariant subspace
    V.col(k) = w / norm;
    if (k > 0) beta(k - 1) = norm;
    // The three-term recurrence first, then one full reorthogonalisation pass, and a second
    // only when the first removed most of what was left (Daniel-Gragg-Kaufman-Stewart): after
    // the recurrence the earlier vectors' components are at rounding level, so one pass
    // usually suffices.
    w.noalias() = G * V.col(k);
    alpha(k) = V.col(k).dot(w).real();
    w -= alpha(k) * V.col(k);
    if (k > 0) w -= beta(k - 1) * V.col(k - 1);
    for (int pass = 0; pass < 2; ++pass) {
      const double before = w.norm();
      w.noalias() -= V.leftCols(k + 1) * (V.leftCols(k + 1).adjoint() * w);
      if (w.norm() > std::sqrt(0.5) * before) break;
    }
  }
  return k;
}

namespace {
// How many eigenvalues of T are below x (Sylvester's inertia of T - x I, via its LDL^T pivots).
int eigenvalues_below(const Eigen::VectorXd& alpha, const Eigen::VectorXd& beta, double x, double tiny) {
  int count = 0;
  double d = 1.0;
  for (Eigen::Index i = 0; i < alpha.size(); ++i) {
    d = alpha(i) - x - (i > 0 ? beta(i - 1) * beta(i - 1) / d : 0.0);
    if (d == 0.0) d = -tiny;  // x is an eigenvalue of the leading block: count it as crossed
    if (d < 0.0) ++count;
  }
  return count;
}
}  // namespace

Eigen::VectorXd smallest_tridiagonal_eigenvector(const Eigen::VectorXd& alpha, const Eigen::VectorXd& beta,
                                                 double* lambda) {
  const Eigen::Index n = alpha.size();
  // Gershgorin bounds of the spectrum.
  double lo = alpha(0), hi = alpha(0), scale = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double radius = (i > 0 ? std::abs(beta(i - 1)) : 0.0) + (i + 1 < n ? std::abs(beta(i)) : 0.0);
    lo = std::min(lo, alpha(i) - radius);
    hi = std::max(hi, alpha(i) + radius);
    scale = std::max(scale, std::abs(alpha(i)) + radius);
  }
  const double eps = std::numeric_limits<double>::epsilon();
  const double tiny = eps * std::max(scale, std::numeric_limits<double>::min());
  // lambda_min <= min_i alpha_i (a Rayleigh quotient of a unit vector).
  hi = std::min(hi, alpha.minCoeff());
  // Bisection (lo has no eigenvalue below it, hi at least one) to 1e-7 of ||T||: inverse
  // iteration from there gains ~1e-7 ||T|| / gap per solve, so five solves reach rounding for
  // any gap above ~1e-4 ||T||; bisecting to full precision took 4x as long (dependent divisions).
  for (int step = 0; step < 200 && hi - lo > 1e-7 * scale + tiny; ++step) {
    const double mid = 0.5 * (lo + hi);
    (eigenvalues_below(alpha, beta, mid, tiny) >= 1 ? hi : lo) = mid;
  }
  const double shift = 0.5 * (lo + hi);
  if (lambda) *lambda = shift;
  // Inverse iteration: (T - shift I) x_new = x, by Gaussian elimination along the band,
  // factorised once; a zero pivot (the shift is an eigenvalue to working precision) is
  // replaced by a tiny one, which only steers x further into the eigenvector.
  Eigen::VectorXd inverse_pivot(n), multiplier(n);
  double pivot = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    multiplier(i) = i > 0 ? beta(i - 1) * inverse_pivot(i - 1) : 0.0;
    const double d = alpha(i) - shift - (i > 0 ? multiplier(i) * beta(i - 1) : 0.0);
    pivot = std::abs(d) > tiny ? d : (d < 0.0 ? -tiny : tiny);
    inverse_pivot(i) = 1.0 / pivot;
  }
  Eigen::VectorXd x = Eigen::VectorXd::Ones(n);
  for (int solve = 0; solve < 5; ++solve) {
    for (Eigen::Index i = 1; i < n; ++i) x(i) -= multiplier(i) * x(i - 1);
    x(n - 1) *= inverse_pivot(n - 1);
    for (Eigen::Index i = n - 2; i >= 0; --i) x(i) = (x(i) - beta(i) * x(i + 1)) * inverse_pivot(i);
    x /= x.norm();
  }
  return x;
}

}  // namespace losmimo::placement::detail
