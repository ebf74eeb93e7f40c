#include "lanczos.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

namespace losmimo::placement::detail {

namespace {
constexpr int kL = kernels::kLanes;  // ld is a multiple: the loops below need no tails
using Lanes = Eigen::Array<double, kL, 1>;
using ConstLanes = Eigen::Map<const Lanes>;

// The sums below run in kL partial sums (Eigen vectorises the fixed-size arrays) added in a
// fixed order: the same bits on every build and call.
double squared_norm(const double* re, const double* im, int ld) {
  Lanes s = Lanes::Zero();
  for (int l = 0; l < ld; l += kL) s += ConstLanes(re + l).square() + ConstLanes(im + l).square();
  return s.sum();
}

// a^H b.
std::complex<double> dot(const double* ar, const double* ai, const double* br, const double* bi, int ld) {
  Lanes sr = Lanes::Zero(), si = Lanes::Zero();
  for (int l = 0; l < ld; l += kL) {
    const ConstLanes a_re(ar + l), a_im(ai + l), b_re(br + l), b_im(bi + l);
    sr += a_re * b_re + a_im * b_im;
    si += a_re * b_im - a_im * b_re;
  }
  return {sr.sum(), si.sum()};
}

// w -= a v.
void subtract_multiple(std::complex<double> a, const double* vr, const double* vi, double* wr, double* wi, int ld) {
  const double ar = a.real(), ai = a.imag();
  for (int l = 0; l < ld; ++l) {
    wr[l] -= ar * vr[l] - ai * vi[l];
    wi[l] -= ar * vi[l] + ai * vr[l];
  }
}
}  // namespace

Eigen::Index lanczos(const kernels::Kernels& kern, const kernels::GramPlanes& G, Eigen::Index steps,
                     LanczosBasis& basis) {
  const int n = G.n, ld = G.ld;
  steps = std::min<Eigen::Index>(steps, n);
  basis.ld = ld;
  basis.re.assign(static_cast<std::size_t>(ld) * steps, 0.0);
  basis.im.assign(static_cast<std::size_t>(ld) * steps, 0.0);
  basis.alpha.resize(steps);
  basis.beta.resize(std::max<Eigen::Index>(steps - 1, 0));
  double trace = 0.0, heaviest = -1.0;
  int k_max = 0;
  for (int c = 0; c < n; ++c) {
    const std::ptrdiff_t col = static_cast<std::ptrdiff_t>(c) * ld;
    trace += G.re[col + c];
    const double weight = squared_norm(G.re + col, G.im + col, ld);
    if (weight > heaviest) {
      heaviest = weight;
      k_max = c;
    }
  }
  thread_local std::vector<double> wr, wi;
  const std::ptrdiff_t heaviest_col = static_cast<std::ptrdiff_t>(k_max) * ld;
  wr.assign(G.re + heaviest_col, G.re + heaviest_col + ld);
  wi.assign(G.im + heaviest_col, G.im + heaviest_col + ld);
  const auto vr = [&](Eigen::Index j) { return basis.re.data() + j * ld; };
  const auto vi = [&](Eigen::Index j) { return basis.im.data() + j * ld; };
  double w2 = heaviest;  // |w|^2, carried from where it was last computed
  Eigen::Index k = 0;
  for (; k < steps; ++k) {
    const double norm = std::sqrt(w2);
    if (!(norm > 1e-12 * std::sqrt(std::abs(trace)))) break;  // an invariant subspace
    for (int l = 0; l < ld; ++l) {
      vr(k)[l] = wr[l] / norm;
      vi(k)[l] = wi[l] / norm;
    }
    if (k > 0) basis.beta(k - 1) = norm;
    // The three-term recurrence first, then one full reorthogonalisation pass, and a second
    // only when the first removed most of what was left (Daniel-Gragg-Kaufman-Stewart): after
    // the recurrence the earlier vectors' components are at rounding level, so one pass
    // usually suffices.
    kern.hermitian_matvec(G, vr(k), vi(k), wr.data(), wi.data());
    basis.alpha(k) = dot(vr(k), vi(k), wr.data(), wi.data(), ld).real();
    subtract_multiple(basis.alpha(k), vr(k), vi(k), wr.data(), wi.data(), ld);
    if (k > 0) subtract_multiple(basis.beta(k - 1), vr(k - 1), vi(k - 1), wr.data(), wi.data(), ld);
    double before = squared_norm(wr.data(), wi.data(), ld);
    for (int pass = 0; pass < 2; ++pass) {
      w2 = kern.reorthogonalise(basis.re.data(), basis.im.data(), ld, static_cast<int>(k) + 1, wr.data(), wi.data());
      if (w2 > 0.5 * before) break;
      before = w2;
    }
  }
  return k;
}

Eigen::VectorXcd combine(const LanczosBasis& basis, int n, const Eigen::VectorXd& s) {
  Eigen::VectorXcd v = Eigen::VectorXcd::Zero(n);
  for (Eigen::Index j = 0; j < s.size(); ++j) {
    const double* vr = basis.re.data() + j * basis.ld;
    const double* vi = basis.im.data() + j * basis.ld;
    for (int l = 0; l < n; ++l) v(l) += s(j) * std::complex<double>(vr[l], vi[l]);
  }
  return v;
}

DensePlanes::DensePlanes(const Eigen::MatrixXcd& G)
    : n_(static_cast<int>(G.cols())),
      ld_(kernels::padded(n_)),
      re_(static_cast<std::size_t>(ld_) * n_, 0.0),
      im_(static_cast<std::size_t>(ld_) * n_, 0.0) {
  for (int k = 0; k < n_; ++k) {
    for (int l = 0; l < n_; ++l) {
      re_[static_cast<std::size_t>(k) * ld_ + l] = G(l, k).real();
      im_[static_cast<std::size_t>(k) * ld_ + l] = G(l, k).imag();
    }
  }
}

namespace {
// How many eigenvalues of T are below each of x[0 .. kX - 1] (Sylvester's inertia of T - x I,
// via its LDL^T pivots). The kX recurrences are independent, interleaved so that their
// divisions overlap; each is the one-shift recurrence, operation for operation.
template <int kX>
void eigenvalues_below(const Eigen::VectorXd& alpha, const Eigen::VectorXd& beta, const double (&x)[kX], double tiny,
                       int (&count)[kX]) {
  double d[kX];
  for (int j = 0; j < kX; ++j) {
    d[j] = 1.0;
    count[j] = 0;
  }
  for (Eigen::Index i = 0; i < alpha.size(); ++i) {
    const double b2 = i > 0 ? beta(i - 1) * beta(i - 1) : 0.0;
    for (int j = 0; j < kX; ++j) {
      d[j] = alpha(i) - x[j] - (i > 0 ? b2 / d[j] : 0.0);
      if (d[j] == 0.0) d[j] = -tiny;  // x is an eigenvalue of the leading block: count it as crossed
      if (d[j] < 0.0) ++count[j];
    }
  }
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
  // Two halvings a round: the midpoint and both midpoints the next halving may take are counted
  // together, so lo and hi follow the one-halving-at-a-time sequence bit for bit.
  const auto more = [&](int step) { return step < 200 && hi - lo > 1e-7 * scale + tiny; };
  for (int step = 0; more(step); step += 2) {
    const double mid = 0.5 * (lo + hi);
    const double x[3] = {mid, 0.5 * (lo + mid), 0.5 * (mid + hi)};
    int below[3];
    eigenvalues_below(alpha, beta, x, tiny, below);
    const bool lower_half = below[0] >= 1;
    (lower_half ? hi : lo) = mid;
    if (!more(step + 1)) break;
    const int next = lower_half ? 1 : 2;  // 0.5 (lo + hi) of the halved interval
    (below[next] >= 1 ? hi : lo) = x[next];
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
