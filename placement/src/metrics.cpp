#include "losmimo/placement/metrics.h"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <cmath>
#include <limits>

namespace losmimo::placement {

double inverse_condition_number(const Eigen::MatrixXcd& H) {
  if (H.size() == 0) return 0.0;
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXcd>(H).singularValues();
  const double sigma_max = sv(0);
  return sigma_max > 0.0 ? sv(sv.size() - 1) / sigma_max : 0.0;
}

double objective(const Eigen::MatrixXcd& H) {
  if (H.rows() < H.cols()) return objective(H.transpose());  // the UAVs' Gram matrix
  const Eigen::MatrixXcd G = H.adjoint() * H;
  return G.squaredNorm() - G.diagonal().squaredNorm();
}

StreamSinr stream_sinr(const Eigen::MatrixXcd& H, double noise_variance) {
  if (H.rows() < H.cols()) return stream_sinr(H.transpose(), noise_variance);  // one stream per UAV
  const Eigen::Index nt = H.cols();
  const Eigen::MatrixXcd G = H.adjoint() * H;
  StreamSinr out;
  out.nv.resize(nt);
  out.mf.resize(nt);
  out.zf.setZero(nt);
  for (Eigen::Index k = 0; k < nt; ++k) {
    const double gain = G(k, k).real();
    const double interference = G.row(k).squaredNorm() - gain * gain;
    out.nv(k) = gain * gain / (interference + gain * noise_variance);
    out.mf(k) = gain / noise_variance;
  }
  if (H.rows() >= nt) {
    const Eigen::LLT<Eigen::MatrixXcd> llt(G);
    if (llt.info() == Eigen::Success) {
      const Eigen::MatrixXcd G_inv = llt.solve(Eigen::MatrixXcd::Identity(nt, nt));
      for (Eigen::Index k = 0; k < nt; ++k) {
        const double d = G_inv(k, k).real();
        out.zf(k) = d > 0.0 && std::isfinite(d) ? 1.0 / (noise_variance * d) : 0.0;
      }
    }
  }
  return out;
}

double sum_rate_bps_hz(const Eigen::VectorXd& sinr_linear) {
  return (1.0 + sinr_linear.array()).log().sum() / std::log(2.0);
}

double to_db(double linear) {
  return linear > 0.0 ? 10.0 * std::log10(linear) : -std::numeric_limits<double>::infinity();
}

LinkMetrics evaluate_link(const Eigen::MatrixXcd& H, double noise_variance) {
  LinkMetrics m;
  m.icn = inverse_condition_number(H);
  m.objective = objective(H);
  m.sinr = stream_sinr(H, noise_variance);
  m.sum_rate_nv_bps_hz = sum_rate_bps_hz(m.sinr.nv);
  m.sum_rate_zf_bps_hz = sum_rate_bps_hz(m.sinr.zf);
  return m;
}

}  // namespace losmimo::placement
