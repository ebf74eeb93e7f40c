#pragma once
// Chi-square distribution for the consistency tests, without Boost:
//   P(a, x) = gamma(a, x) / Gamma(a), the regularized lower incomplete gamma function, by its
//             power series for x < a + 1 and by the continued fraction of Q = 1 - P otherwise
//             (Numerical Recipes 6.2; both converge to a relative 1e-15);
//   chi2_cdf(k, x) = P(k / 2, x / 2);
//   chi2_quantile(k, p) = the x with chi2_cdf(k, x) = p, by bisection (200 halvings: the
//             interval shrinks far below double resolution, so the result is the cdf's inverse
//             to the cdf's own accuracy).
// Checked against printed tables in tests/fusion/closed_loop_consistency_test.cpp
// (ChiSquare.Quantile_MatchesPrintedTables).
#include <cmath>
#include <limits>

namespace losmimo::test_support {

inline double regularized_lower_gamma(double a, double x) {
  constexpr int kMaxTerms = 100000;
  constexpr double kRelEps = 1e-16;
  constexpr double kTiny = 1e-300;
  if (!(a > 0.0) || !(x >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return 0.0;
  const double log_prefactor = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    // sum_n x^n / (a (a + 1) ... (a + n))
    double term = 1.0 / a, sum = term, denominator = a;
    for (int n = 0; n < kMaxTerms; ++n) {
      denominator += 1.0;
      term *= x / denominator;
      sum += term;
      if (std::abs(term) < std::abs(sum) * kRelEps) break;
    }
    return sum * std::exp(log_prefactor);
  }
  // Q(a, x) by the modified Lentz method on its continued fraction.
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxTerms; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kRelEps) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

inline double chi2_cdf(double dof, double x) { return regularized_lower_gamma(0.5 * dof, 0.5 * x); }

// p in (0, 1).
inline double chi2_quantile(double dof, double p) {
  constexpr int kHalvings = 200;
  double lo = 0.0, hi = dof + 100.0 * std::sqrt(2.0 * dof) + 100.0;  // cdf(hi) = 1 to double precision
  for (int i = 0; i < kHalvings; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_cdf(dof, mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The two-sided band of the average of n independent chi2(dof) samples at `confidence`:
// [chi2_quantile(dof n, (1 - confidence) / 2), chi2_quantile(dof n, (1 + confidence) / 2)] / n.
struct Chi2Band {
  double low = 0.0, high = 0.0;
  bool contains(double average) const { return average >= low && average <= high; }
};
inline Chi2Band chi2_average_band(double dof, double n, double confidence) {
  return {chi2_quantile(dof * n, 0.5 * (1.0 - confidence)) / n, chi2_quantile(dof * n, 0.5 * (1.0 + confidence)) / n};
}

}  // namespace losmimo::test_support
