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

void SwarmChannel::set_row(int m, const Eigen::VectorXcd& x) {
  // G_lk = sum_n conj(H_nl) H_nk: remove the old row's outer product, add the new one.
  // G is Hermitian: update the upper triangle (column-major friendly) and mirror it.
  // In real arithmetic: the same operations as the complex expression
  //   G_lk += conj(x_l) x_k - conj(o_l) o_k   (o = the old row)
  // (conj(a) * b has real part a.re b.re + a.im b.im and imaginary part a.re b.im - a.im b.re,
  // bit for bit), without the NaN-recovery branch of the complex product.
  const Eigen::Index nt = x.size();
  thread_local Eigen::VectorXcd old;
  old = H_.row(m).transpose();
  const double* xn = reinterpret_cast<const double*>(x.data());
  const double* on = reinterpret_cast<const double*>(old.data());
  for (Eigen::Index k = 0; k < nt; ++k) {
    const double xr = xn[2 * k], xi = xn[2 * k + 1];
    const double orr = on[2 * k], oi = on[2 * k + 1];
    double* g = reinterpret_cast<double*>(G_.col(k).data());
    for (Eigen::Index l = 0; l <= k; ++l) {
      const double ar = xn[2 * l], ai = xn[2 * l + 1];
      const double br = on[2 * l], bi = on[2 * l + 1];
      const double t1r = ar * xr + ai * xi, t1i = ar * xi - ai * xr;
      const double t2r = br * orr + bi * oi, t2i = br * oi - bi * orr;
      g[2 * l] += t1r - t2r;
      g[2 * l + 1] += t1i - t2i;
    }
  }
  for (Eigen::Index k = 0; k < nt; ++k) {
    G_(k, k) = G_(k, k).real();
    for (Eigen::Index l = k + 1; l < nt; ++l) G_(l, k) = std::conj(G_(k, l));
  }
  H_.row(m) = x.transpose();
  if (++updates_since_refresh_ >= kRefreshEvery) refresh();
}

void SwarmChannel::refresh() {
  G_.noalias() = H_.adjoint() * H_;
  updates_since_refresh_ = 0;
}

UavObjective::UavObjective(const SwarmChannel& swarm, int m) : model_(&swarm.model()) {
  // A = G - conj(x) x^T, stored conjugated: conj(A)_lk = conj(G_lk) - x_l conj(x_k), in one
  // pass (the same operations, element by element, as conj(G) - x x^H).
  const Eigen::MatrixXcd& H = swarm.H();
  const Eigen::MatrixXcd& G = swarm.gram();
  const Eigen::Index nt = G.cols();
  // In real arithmetic (x_l conj(x_k) = (a c + b d, b c - a d) for x_l = a + jb, x_k = c + jd,
  // bit for bit as the complex product), without the complex product's NaN-recovery branch.
  A_conj_.resize(nt, nt);
  thread_local Eigen::VectorXcd x;
  x = H.row(m).transpose();
  const double* xn = reinterpret_cast<const double*>(x.data());
  for (Eigen::Index k = 0; k < nt; ++k) {
    const double c = xn[2 * k], d = xn[2 * k + 1];
    const double* g = reinterpret_cast<const double*>(G.col(k).data());
    double* a = reinterpret_cast<double*>(A_conj_.col(k).data());
    for (Eigen::Index l = 0; l < nt; ++l) {
      const double xr = xn[2 * l], xi = xn[2 * l + 1];
      a[2 * l] = g[2 * l] - (xr * c + xi * d);
      a[2 * l + 1] = -g[2 * l + 1] - (xi * c - xr * d);
    }
  }
  A_diag_ = A_conj_.diagonal().real();
  F_A_ = A_conj_.squaredNorm() - A_diag_.squaredNorm();
}

double UavObjective::objective_of_row(const Eigen::VectorXcd& x) const {
  // Per-thread scratch instead of temporaries (the same expressions and reductions, so the
  // same bits): a BF probe then allocates nothing.
  thread_local Eigen::ArrayXd p;
  thread_local Eigen::VectorXcd Ax;
  p = x.cwiseAbs2().array();
  const double s = p.sum();
  Ax.noalias() = A_conj_ * x;
  const double hermitian_form = x.dot(Ax).real();
  return F_A_ + 2.0 * hermitian_form - 2.0 * (A_diag_.array() * p).sum() + s * s -
         p.square().sum();
}

double UavObjective::objective_at(const Eigen::Vector3d& q_m) const {
  thread_local Eigen::VectorXcd x;
  model_->row(q_m, x);
  return objective_of_row(x);
}

Eigen::Vector3d UavObjective::gradient_at(const Eigen::Vector3d& q_m, double* objective) const {
  const Eigen::VectorXcd x = model_->row(q_m);
  if (objective) *objective = objective_of_row(x);
  Eigen::VectorXcd s;
  Eigen::Matrix3Xd U;
  model_->row_derivative_terms(q_m, s, U);
  const Eigen::ArrayXd p = x.cwiseAbs2().array();
  const double total_power = p.sum();
  // sum_{k != l} conj(B_lk) x_k = (conj(A) x)_l - conj(A)_ll x_l + x_l (S - |x_l|^2)
  const Eigen::VectorXcd Ax = A_conj_ * x;
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
