#pragma once
// Link metrics of a channel H (Nr x Nt, rows are UAVs), paper section 2.
//
// - ICN = sigma_min / sigma_max of H (0 when Nr < Nt: the columns cannot be independent).
// - Objective f = sum_{l != k} |h_l^H h_k|^2 over the columns h of H (full recompute,
//   O(Nr Nt^2); SwarmChannel keeps it up to date in O(Nt^2) per moved UAV).
// - Per stream k (column k), with noise variance psi^2 in the units of H:
//     NV (w = h_k):          |h_k|^4 / (sum_{m != k} |h_k^H h_m|^2 + |h_k|^2 psi^2)
//     ZF (w _|_ other h_m):  1 / (psi^2 [(H^H H)^-1]_kk)     (0 when H is rank deficient)
//     MF (single user):      |h_k|^2 / psi^2
// - Sum rate sum_k log2(1 + SINR_k) in bit/s/Hz.
// SINR values here are linear; to_db converts.

#include <Eigen/Core>

namespace losmimo::placement {

double inverse_condition_number(const Eigen::MatrixXcd& H);
double objective(const Eigen::MatrixXcd& H);

struct StreamSinr {
  Eigen::VectorXd nv;  // linear, one per BS antenna (stream)
  Eigen::VectorXd zf;
  Eigen::VectorXd mf;
};
StreamSinr stream_sinr(const Eigen::MatrixXcd& H, double noise_variance);

double sum_rate_bps_hz(const Eigen::VectorXd& sinr_linear);
double to_db(double linear);

// Everything above for one channel.
struct LinkMetrics {
  double icn = 0.0;
  double objective = 0.0;
  StreamSinr sinr;
  double sum_rate_nv_bps_hz = 0.0;
  double sum_rate_zf_bps_hz = 0.0;
};
LinkMetrics evaluate_link(const Eigen::MatrixXcd& H, double noise_variance);

}  // namespace losmimo::placement
