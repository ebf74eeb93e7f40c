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

void SwarmChannel::set_position(int m, const Eigen::Vector3d& q_m) { set_row(m, model_->row(q_m)); }

void SwarmChannel::set_row(int m, const Eigen::VectorXcd& x) {
  // G_lk = sum_n conj(H_nl) H_nk: remove the old row's outer product, add the new one.
  // G is Hermitian: update the upper triangle (column-major friendly) and mirror it.
  const Eigen::Index nt = x.size();
  for (Eigen::Index k = 0; k < nt; ++k) {
    const std::complex<double> xk = x(k);
    const std::complex<double> ok = H_(m, k);
    for (Eigen::Index l = 0; l <= k; ++l) {
      G_(l, k) += std::conj(x(l)) * xk - std::conj(H_(m, l)) * ok;
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
  const Eigen::VectorXcd x = swarm.H().row(m).transpose();
  // A = G - conj(x) x^T, stored conjugated: conj(A) = G^T... computed directly.
  A_conj_ = swarm.gram().conjugate();
  A_conj_.noalias() -= x * x.adjoint();
  A_diag_ = A_conj_.diagonal().real();
  F_A_ = A_conj_.squaredNorm() - A_diag_.squaredNorm();
}

double UavObjective::objective_of_row(const Eigen::VectorXcd& x) const {
  const Eigen::ArrayXd p = x.cwiseAbs2().array();
  const double s = p.sum();
  const double hermitian_form = x.dot(A_conj_ * x).real();
  return F_A_ + 2.0 * hermitian_form - 2.0 * (A_diag_.array() * p).sum() + s * s -
         p.square().sum();
}

double UavObjective::objective_at(const Eigen::Vector3d& q_m) const {
  return objective_of_row(model_->row(q_m));
}

Eigen::Vector3d UavObjective::gradient_at(const Eigen::Vector3d& q_m) const {
  const Eigen::VectorXcd x = model_->row(q_m);
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
