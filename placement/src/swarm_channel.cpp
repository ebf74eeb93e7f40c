#include "losmimo/placement/swarm_channel.h"

#include "losmimo/placement/metrics.h"

namespace losmimo::placement {

namespace {
// Rank-one updates drift by ~1e-16 relative each; a periodic exact rebuild bounds it.
constexpr int kRefreshEvery = 256;
}  // namespace

SwarmChannel::SwarmChannel(const ChannelModel& model, const Eigen::Matrix3Xd& q_m)
    : model_(&model), H_(model.matrix(q_m)) {
  refresh();
}

double SwarmChannel::objective() const { return G_.squaredNorm() - G_.diagonal().squaredNorm(); }

void SwarmChannel::set_position(int m, const Eigen::Vector3d& q_m) {
  thread_local Eigen::VectorXcd x;  // reused: no allocation per move
  model_->row(q_m, x);
  set_row(m, x);
}

namespace {
// G_lk += conj(x_l) x_k - conj(o_l) o_k over the whole matrix, in real arithmetic (conj(a) b has
// real part a.re b.re + a.im b.im and imaginary part a.re b.im - a.im b.re). Entry (k, l) gets
// the same products in the same order with the imaginary part's operands swapped, so exactly
// the conjugate: G stays Hermitian bit for bit, with no mirror pass, and the loop vectorises.
// GCC on x86-64 adds an AVX2 clone (no FMA: the same bits as the baseline).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void gram_row_update(double* __restrict g, const double* __restrict x, const double* __restrict o, int n) {
  for (int k = 0; k < n; ++k) {
    const double xr = x[2 * k], xi = x[2 * k + 1];
    const double orr = o[2 * k], oi = o[2 * k + 1];
    double* col = g + 2 * static_cast<std::ptrdiff_t>(k) * n;
    for (int l = 0; l < n; ++l) {
      const double ar = x[2 * l], ai = x[2 * l + 1];
      const double br = o[2 * l], bi = o[2 * l + 1];
      col[2 * l] += (ar * xr + ai * xi) - (br * orr + bi * oi);
      col[2 * l + 1] += (ar * xi - ai * xr) - (br * oi - bi * orr);
    }
  }
}
}  // namespace

void SwarmChannel::set_row(int m, const Eigen::VectorXcd& x) {
  // Remove the old row's outer product, add the new one: O(Nt^2).
  thread_local Eigen::VectorXcd old;
  old = H_.row(m).transpose();
  gram_row_update(reinterpret_cast<double*>(G_.data()), reinterpret_cast<const double*>(x.data()),
                  reinterpret_cast<const double*>(old.data()), static_cast<int>(x.size()));
  H_.row(m) = x.transpose();
  if (++updates_since_refresh_ >= kRefreshEvery) refresh();
}

void SwarmChannel::refresh() {
  G_.noalias() = H_.adjoint() * H_;
  // Exactly Hermitian from here on (the updates keep it so): the product need not be.
  for (Eigen::Index k = 0; k < G_.cols(); ++k) {
    G_(k, k) = G_(k, k).real();
    for (Eigen::Index l = k + 1; l < G_.rows(); ++l) G_(l, k) = std::conj(G_(k, l));
  }
  updates_since_refresh_ = 0;
}

namespace {
// y = (R + j I) x for real Nt x Nt matrices R, I (column-major) and x = xr + j xi: four real
// column sweeps that vectorise. GCC on x86-64 adds an AVX2 clone chosen at load time; no FMA
// in either clone, and the same operation order, so both give the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void complex_matvec(const double* __restrict R, const double* __restrict I, const double* __restrict xr,
                    const double* __restrict xi, double* __restrict yr, double* __restrict yi, int n) {
  for (int l = 0; l < n; ++l) yr[l] = yi[l] = 0.0;
  for (int k = 0; k < n; ++k) {
    const double a = xr[k], b = xi[k];
    const double* r = R + static_cast<std::ptrdiff_t>(k) * n;
    const double* i = I + static_cast<std::ptrdiff_t>(k) * n;
    for (int l = 0; l < n; ++l) {
      yr[l] += r[l] * a - i[l] * b;
      yi[l] += r[l] * b + i[l] * a;
    }
  }
}
}  // namespace

UavObjective::UavObjective(const SwarmChannel& swarm, int m) : model_(&swarm.model()) {
  // A = G - conj(x) x^T, stored conjugated: conj(A)_lk = conj(G_lk) - x_l conj(x_k), with
  // x_l conj(x_k) = (a c + b d, b c - a d) for x_l = a + jb, x_k = c + jd.
  const Eigen::MatrixXcd& H = swarm.H();
  const Eigen::MatrixXcd& G = swarm.gram();
  const Eigen::Index nt = G.cols();
  A_conj_re_.resize(nt, nt);
  A_conj_im_.resize(nt, nt);
  thread_local Eigen::VectorXcd x;
  x = H.row(m).transpose();
  const double* xn = reinterpret_cast<const double*>(x.data());
  A_diag_.resize(nt);
  for (Eigen::Index k = 0; k < nt; ++k) {
    const double c = xn[2 * k], d = xn[2 * k + 1];
    const double* g = reinterpret_cast<const double*>(G.col(k).data());
    double* re = A_conj_re_.col(k).data();
    double* im = A_conj_im_.col(k).data();
    for (Eigen::Index l = 0; l < nt; ++l) {
      const double xr = xn[2 * l], xi = xn[2 * l + 1];
      re[l] = g[2 * l] - (xr * c + xi * d);
      im[l] = -g[2 * l + 1] - (xi * c - xr * d);
    }
    A_diag_(k) = re[k];
  }
  F_A_ = A_conj_re_.squaredNorm() + A_conj_im_.squaredNorm() - A_diag_.squaredNorm();
}

void UavObjective::apply_conj_A(const Eigen::VectorXcd& x, Eigen::VectorXcd& Ax) const {
  const int nt = static_cast<int>(x.size());
  thread_local Eigen::VectorXd xr, xi, yr, yi;
  xr = x.real();
  xi = x.imag();
  yr.resize(nt);
  yi.resize(nt);
  complex_matvec(A_conj_re_.data(), A_conj_im_.data(), xr.data(), xi.data(), yr.data(), yi.data(), nt);
  Ax.resize(nt);
  Ax.real() = yr;
  Ax.imag() = yi;
}

double UavObjective::objective_given(const Eigen::VectorXcd& x, const Eigen::ArrayXd& p,
                                     const Eigen::VectorXcd& Ax) const {
  const double s = p.sum();
  const double hermitian_form = x.dot(Ax).real();
  return F_A_ + 2.0 * hermitian_form - 2.0 * (A_diag_.array() * p).sum() + s * s -
         p.square().sum();
}

double UavObjective::objective_of_row(const Eigen::VectorXcd& x) const {
  // Per-thread scratch instead of temporaries: a BF probe allocates nothing.
  thread_local Eigen::ArrayXd p;
  thread_local Eigen::VectorXcd Ax;
  p = x.cwiseAbs2().array();
  apply_conj_A(x, Ax);
  return objective_given(x, p, Ax);
}

double UavObjective::objective_at(const Eigen::Vector3d& q_m) const {
  thread_local Eigen::VectorXcd x;
  model_->row(q_m, x);
  return objective_of_row(x);
}

Eigen::Vector3d UavObjective::gradient_at(const Eigen::Vector3d& q_m, double* objective) const {
  thread_local Eigen::VectorXcd x, s, Ax;
  thread_local Eigen::Matrix3Xd U;
  thread_local Eigen::ArrayXd p;
  model_->row(q_m, x);
  model_->row_derivative_terms(q_m, s, U);
  p = x.cwiseAbs2().array();
  const double total_power = p.sum();
  apply_conj_A(x, Ax);
  if (objective) *objective = objective_given(x, p, Ax);
  // sum_{k != l} conj(B_lk) x_k = (conj(A) x)_l - conj(A)_ll x_l + x_l (S - |x_l|^2)
  Eigen::Vector3d grad = Eigen::Vector3d::Zero();
  for (Eigen::Index l = 0; l < x.size(); ++l) {
    const std::complex<double> inner =
        Ax(l) - A_diag_(l) * x(l) + x(l) * (total_power - p(l));
    const std::complex<double> Q = std::conj(x(l)) * inner;
    grad += 4.0 * (std::conj(s(l)) * Q).real() * U.col(l);
  }
  return grad;
}

}  // namespace losmimo::placement
