// SwarmChannel and UavObjective on the UAV side: swarms smaller than the BS array (Nr < Nt).
//
// With fewer UAVs than antennas the streams are the UAVs (metrics.h), the Gram matrix is
// K = H H^H (Nr x Nr) and the objective f = sum_{j != l} |K_jl|^2, zero exactly when the rows
// are orthogonal (ICN 1 over the Nr singular values). The column objective would not do: it has
// the floor Nr Nt (Nt - Nr) in the far field (H^H H has rank Nr), and its O(Nt^2) cost per probe
// grows with the array. UAV m's view with row x in place of its own:
//   c_j = sum_k conj(H_jk) x_k  (j != m, = K_mj),   f(x) = F_others + 2 sum_{j != m} |c_j|^2
//   grad f = 4 sum_k u_k Re(conj(s_k) conj(x_k) y_k),   y_k = sum_{j != m} H_jk c_j
// with F_others = sum_{j != l; j, l != m} |K_jl|^2 and s_k, u_k from
// ChannelModel::row_derivative_terms: O(Nr Nt) per probe, gradient included.
//
// Plain scalar loops over the swarm's split planes (the readable definition; not vectorised).
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

#include "losmimo/placement/swarm_channel.h"

namespace losmimo::placement {

using cd = std::complex<double>;

void SwarmChannel::rebuild_uav_gram() {
  const int nr = num_uavs();
  uav_gram_.resize(nr, nr);
  for (int j = 0; j < nr; ++j) update_uav_gram(j);
}

void SwarmChannel::update_uav_gram(int m) {
  // Row and column m from the rows' planes; K stays exactly Hermitian (K_jm = conj(K_mj)).
  const int nr = num_uavs(), nt = model_->num_antennas();
  const double* xr = row_re(m);
  const double* xi = row_im(m);
  for (int j = 0; j < nr; ++j) {
    const double* hr = row_re(j);
    const double* hi = row_im(j);
    double re = 0.0, im = 0.0;
    for (int k = 0; k < nt; ++k) {
      re += xr[k] * hr[k] + xi[k] * hi[k];
      im += xi[k] * hr[k] - xr[k] * hi[k];
    }
    uav_gram_(m, j) = j == m ? cd(re, 0.0) : cd(re, im);
    uav_gram_(j, m) = j == m ? cd(re, 0.0) : cd(re, -im);
  }
}

double SwarmChannel::uav_gram_objective() const {
  double f = 0.0;
  for (Eigen::Index l = 0; l < uav_gram_.cols(); ++l) {
    for (Eigen::Index j = 0; j < uav_gram_.rows(); ++j) {
      if (j != l) f += std::norm(uav_gram_(j, l));
    }
  }
  return f;
}

double UavObjective::uav_side_others_energy() const {
  const Eigen::MatrixXcd& K = swarm_->gram();
  double f = 0.0;
  for (Eigen::Index l = 0; l < K.cols(); ++l) {
    for (Eigen::Index j = 0; j < K.rows(); ++j) {
      if (j != l && j != m_ && l != m_) f += std::norm(K(j, l));
    }
  }
  return f;
}

double UavObjective::uav_side_objective(const double* xr, const double* xi, std::vector<cd>* c) const {
  const int nr = swarm_->num_uavs(), nt = swarm_->model().num_antennas();
  if (c) c->assign(nr, cd(0.0, 0.0));
  double cross = 0.0;
  for (int j = 0; j < nr; ++j) {
    if (j == m_) continue;
    const double* hr = swarm_->row_re(j);
    const double* hi = swarm_->row_im(j);
    double re = 0.0, im = 0.0;
    for (int k = 0; k < nt; ++k) {
      re += hr[k] * xr[k] + hi[k] * xi[k];
      im += hr[k] * xi[k] - hi[k] * xr[k];
    }
    cross += re * re + im * im;
    if (c) (*c)[j] = cd(re, im);
  }
  return leave_one_out_energy() + 2.0 * cross;
}

double UavObjective::uav_side_objective_at(const Eigen::Vector3d& q_m) const {
  const int ld = swarm_->model().geometry().ld;
  thread_local std::vector<double> re, im;
  re.resize(ld);
  im.resize(ld);
  swarm_->model().row_planes(q_m, re.data(), im.data());
  return uav_side_objective(re.data(), im.data(), nullptr);
}

double UavObjective::uav_side_gradient(const Eigen::Vector3d& q_m, double* grad) const {
  const ChannelModel& model = swarm_->model();
  const int nr = swarm_->num_uavs(), nt = model.num_antennas(), ld = model.geometry().ld;
  thread_local std::vector<double> xr, xi;
  thread_local std::vector<cd> c;
  thread_local Eigen::VectorXcd s;
  thread_local Eigen::Matrix3Xd U;
  xr.resize(ld);
  xi.resize(ld);
  model.row_planes(q_m, xr.data(), xi.data());
  const double f = uav_side_objective(xr.data(), xi.data(), &c);
  model.row_derivative_terms(q_m, s, U);
  grad[0] = grad[1] = grad[2] = 0.0;
  for (int k = 0; k < nt; ++k) {
    cd y(0.0, 0.0);
    for (int j = 0; j < nr; ++j) {
      if (j != m_) y += cd(swarm_->row_re(j)[k], swarm_->row_im(j)[k]) * c[j];
    }
    const double w = 4.0 * (std::conj(s(k)) * cd(xr[k], -xi[k]) * y).real();
    for (int i = 0; i < 3; ++i) grad[i] += w * U(i, k);
  }
  return f;
}

}  // namespace losmimo::placement
