// icn_below (run.h): the cheap proof that ICN(G) < threshold, on an Eigen matrix or on a
// swarm's cached Gram matrix (whose products go through the kernels' hermitian_matvec).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <optional>
#include <vector>

#include "losmimo/placement/run.h"
#include "lanczos.h"

namespace losmimo::placement {

namespace {
// The L D L^H factorisation of G - sI (Cholesky's, without its square roots) fails only if
// lambda_min(G - sI) <= c n^2 eps ||G||: so a failure with this margin (far above that
// rounding) proves lambda_min(G) < s. On a failure at pivot k, *witness (if given) gets
// z = (-L11^-H l^H, 1, 0 ...), l the computed part of the unit L's row k, for which
// z^H (G - sI) z is that pivot (<= 0): a vector with Rayleigh quotient <= s.
//
// The factorisation is the kernels' shifted_ldl (left-looking on G's split planes, each
// column summed in whole vectors at the instruction set's width), not Eigen's unblocked LDL^T:
// that makes a matrix-vector call per column, whose setup costs more than its arithmetic at
// 16 x 16, on a dense copy of G converted from the planes.
bool ldl_fails(const kernels::Kernels& kern, const kernels::GramPlanes& G, double s,
               Eigen::VectorXcd* witness = nullptr) {
  const int n = G.n, ld = G.ld;
  thread_local std::vector<double> Lr, Li;
  Lr.resize(static_cast<std::size_t>(ld) * n);
  Li.resize(Lr.size());
  const int j = kern.shifted_ldl(G, s, Lr.data(), Li.data());
  if (j < 0 || j == n) return false;  // a NaN pivot proves nothing; G - sI > 0 neither
  if (witness) {
    // z = (y, 1, 0 ...) with L11^H y = -l^H, l = L's row j (its computed part; L11 unit).
    const auto L = [&](int i, int c) {
      const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(c) * ld + i;
      return std::complex<double>(Lr[at], Li[at]);
    };
    witness->setZero(n);
    (*witness)(j) = 1.0;
    for (int i = j - 1; i >= 0; --i) {
      std::complex<double> sum = -std::conj(L(j, i));
      for (int c = i + 1; c < j; ++c) sum -= std::conj(L(c, i)) * (*witness)(c);
      (*witness)(i) = sum;
    }
  }
  return true;
}

// v / |v| into out, or false if |v| is zero or not finite.
bool normalized_into(const Eigen::VectorXcd& v, Eigen::VectorXcd& out) {
  const double norm = v.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return false;
  out = v / norm;
  return true;
}

// The shift s below which lambda_min must lie for ICN(G)^2 = lambda_min / lambda_max < t^2,
// given a lower bound lambda_lo <= lambda_max: s = t^2 (lambda_lo - margin) - margin, margin =
// 1e-8 trace(G) (>> the rounding of what follows, ~n^2 eps trace).
struct ShiftBelow {
  double margin;
  double t2;  // threshold^2
  double operator()(double lambda_lo) const { return t2 * (lambda_lo - margin) - margin; }
};

// Stage 0: the warm vectors' Rayleigh quotients. A non-finite entry of G makes both quotients
// non-finite (every entry enters G v), so that case falls through to the caller's check.
// Where G changes wholesale between calls (the URA's every UAV moving by many wavelengths) the
// vectors carry nothing over and this stage never proves anything: after kMisses failures in
// a row it runs only every kMisses-th call (stage 1 keeps both vectors current meanwhile).
// Raises lambda_lo to the top quotient and takes one power step on each vector; true when the
// bottom quotient proves ICN < threshold.
template <typename MatVec>
bool warm_quotients_prove(IcnWarmStart* warm, Eigen::Index n, double trace, const ShiftBelow& shift_below,
                          MatVec& matvec, double& lambda_lo) {
  constexpr int kMisses = 8;
  const bool stage0 = warm && warm->top.size() == n && warm->bottom.size() == n && std::isfinite(trace) &&
                      (warm->stage0_misses < kMisses || warm->stage0_misses % kMisses == 0);
  if (warm && !stage0) ++warm->stage0_misses;
  if (!stage0) return false;
  thread_local Eigen::VectorXcd Gv, Gu;
  ++warm->stage0_misses;  // until it proves
  matvec(warm->top, Gv);
  matvec(warm->bottom, Gu);
  const double r_top = warm->top.dot(Gv).real() / warm->top.squaredNorm();
  const double r_bottom = warm->bottom.dot(Gu).real() / warm->bottom.squaredNorm();
  if (!std::isfinite(r_top) || !std::isfinite(r_bottom)) return false;
  lambda_lo = std::max(lambda_lo, r_top);
  // One power step each for the next call: G's top, and the top of lambda_lo I - G (G's bottom).
  Gu = lambda_lo * warm->bottom - Gu;
  if (!normalized_into(Gu, warm->bottom)) warm->bottom.resize(0);
  if (!normalized_into(Gv, warm->top)) warm->top.resize(0);
  if (r_bottom + shift_below.margin < shift_below(lambda_lo)) {
    warm->stage0_misses = 0;
    return true;
  }
  return false;
}

// Stage 1's lower bound on lambda_max: two power iterations from the warm start (the last
// call's top vector: G changes little between iterations) raise lambda_lo to their Rayleigh
// quotients. The warm start (if any) then holds the iterate as its top vector and, when it had
// none, the unit vector of G's smallest diagonal entry as its bottom one (R = min G_jj; stage 0
// refines it). False when an iterate vanishes or is not finite (nothing proved).
template <typename MatVec>
bool power_iterations(const Eigen::VectorXd& diag, IcnWarmStart* warm, MatVec& matvec, double& lambda_lo) {
  const Eigen::Index n = diag.size();
  constexpr int kPowerIterations = 2;
  thread_local Eigen::VectorXcd v, Gv;
  if (warm && warm->top.size() == n && warm->top.allFinite() && warm->top.squaredNorm() > 0.0) {
    v = warm->top;
  } else {
    matvec(Eigen::VectorXcd::Ones(n), v);  // any start; the warm start takes over from the next call
  }
  for (int i = 0; i < kPowerIterations; ++i) {
    const double vv = v.squaredNorm();
    if (!(vv > 0.0)) return false;
    matvec(v, Gv);
    lambda_lo = std::max(lambda_lo, v.dot(Gv).real() / vv);
    if (!normalized_into(Gv, v)) return false;
  }
  if (warm) {
    warm->top = v;
    if (warm->bottom.size() != n) {
      Eigen::Index j = 0;
      diag.minCoeff(&j);
      warm->bottom = Eigen::VectorXcd::Unit(n, j);
    }
  }
  return true;
}

// Stage 2: Lanczos (full reorthogonalisation) from G's heaviest column (not from stage 1's
// vector, which may nearly be an eigenvector, a one-dimensional Krylov space): the extreme Ritz
// values satisfy theta_max <= lambda_max and theta_min >= lambda_min (to a few eps ||G||), and
// theta_max converges fast even when the top of the spectrum is clustered. True when theta_min
// or a factorisation at the shift below theta_max (if above s1, where stage 1's failed)
// proves ICN < threshold.
bool lanczos_proves(const kernels::Kernels& kern, const kernels::GramPlanes& G, const ShiftBelow& shift_below,
                    double lambda_lo, double s1) {
  thread_local detail::LanczosBasis basis;
  const Eigen::Index k = detail::lanczos(kern, G, 8, basis);
  if (k == 0) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz;
  Eigen::VectorXd ritz_diag = basis.alpha.head(k);
  Eigen::VectorXd sub = basis.beta.head(k - 1);
  ritz.computeFromTridiagonal(ritz_diag, sub, Eigen::EigenvaluesOnly);
  const double theta_min = ritz.eigenvalues()(0);
  const double theta_max = std::max(ritz.eigenvalues()(k - 1), lambda_lo);
  const double s2 = shift_below(theta_max);
  if (!(s2 > 0.0)) return false;
  if (theta_min + shift_below.margin < s2) return true;
  return s2 > s1 && ldl_fails(kern, G, s2);
}

// What the proof needs of G: its real diagonal, y = G x, whether every entry is finite, and
// its split planes (Cholesky, Lanczos), asked for only when the products did not settle it.
// Stages 0 to 2 each raise the lower bound lambda_lo <= lambda_max (from G_jj <= lambda_max)
// and try to prove lambda_min below the shift it gives.
template <typename MatVec, typename IsFinite, typename Planes>
bool icn_below_impl(const Eigen::VectorXd& diag, int num_rows, double threshold, IcnWarmStart* warm, MatVec&& matvec,
                    IsFinite&& is_finite, const kernels::Kernels& kern, Planes&& planes) {
  const Eigen::Index n = diag.size();
  if (num_rows < n || n == 0) return threshold > 0.0;  // ICN is 0
  if (!(threshold > 0.0)) return false;
  const double trace = diag.sum();
  const ShiftBelow shift_below{1e-8 * trace, threshold * threshold};
  double lambda_lo = diag.maxCoeff();  // G_jj <= lambda_max
  if (warm_quotients_prove(warm, n, trace, shift_below, matvec, lambda_lo)) return true;
  if (!is_finite()) return false;

  // Stage 1: the power iterations' bound, then the factorisation at the shift below it.
  if (!power_iterations(diag, warm, matvec, lambda_lo)) return false;
  const kernels::GramPlanes G = planes();
  const double s1 = shift_below(lambda_lo);
  thread_local Eigen::VectorXcd z;
  if (s1 > 0.0 && ldl_fails(kern, G, s1, warm ? &z : nullptr)) {
    // The failure's witness (R(z) <= s1) as the next call's bottom vector: G changes little.
    if (warm) normalized_into(z, warm->bottom);
    return true;
  }
  return lanczos_proves(kern, G, shift_below, lambda_lo, s1);
}
}  // namespace

bool icn_below(const Eigen::MatrixXcd& G, int num_rows, double threshold, IcnWarmStart* warm) {
  const Eigen::VectorXd diag = G.diagonal().real();
  std::optional<detail::DensePlanes> dense;
  return icn_below_impl(
      diag, num_rows, threshold, warm, [&](const Eigen::VectorXcd& x, Eigen::VectorXcd& y) { y.noalias() = G * x; },
      [&] { return G.allFinite(); }, kernels::active_kernels(), [&] { return dense.emplace(G).planes(); });
}

bool icn_below(const SwarmChannel& channel, double threshold, IcnWarmStart* warm) {
  if (channel.gram_side() == SwarmChannel::GramSide::kUavs) {
    return icn_below(channel.gram(), channel.num_uavs(), threshold, warm);
  }
  const kernels::GramPlanes G = channel.gram_planes();
  Eigen::VectorXd diag(G.n);
  for (int l = 0; l < G.n; ++l) diag(l) = G.re[l + static_cast<std::ptrdiff_t>(l) * G.ld];
  const kernels::Kernels& k = channel.model().kernels();
  const auto matvec = [&](const Eigen::VectorXcd& x, Eigen::VectorXcd& y) {
    thread_local std::vector<double> xr, xi, yr, yi;
    xr.assign(G.ld, 0.0);
    xi.assign(G.ld, 0.0);
    yr.resize(G.ld);
    yi.resize(G.ld);
    for (int l = 0; l < G.n; ++l) {
      xr[l] = x(l).real();
      xi[l] = x(l).imag();
    }
    k.hermitian_matvec(G, xr.data(), xi.data(), yr.data(), yi.data());
    y.resize(G.n);
    for (int l = 0; l < G.n; ++l) y(l) = {yr[l], yi[l]};
  };
  return icn_below_impl(
      diag, channel.num_uavs(), threshold, warm, matvec, [&] { return channel.gram_is_finite(); }, k,
      [&] { return G; });
}

}  // namespace losmimo::placement
