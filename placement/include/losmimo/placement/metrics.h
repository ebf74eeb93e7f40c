#pragma once
// Link metrics of a channel H (Nr x Nt, rows are UAVs), paper section 2.
//
// Streams. With Nr >= Nt (the paper's case) the streams are the BS antennas: the BS sends one
// stream per antenna without CSI and the UAVs combine jointly; stream k's signature is column
// h_k of H and the Gram matrix is G = H^H H (Nt x Nt). With Nr < Nt (a massive-MIMO BS) Nr
// combining dimensions cannot separate Nt streams, so the streams are the UAVs: one per UAV,
// with linear processing at the BS (ZF or matched-filter precoding from TDD-reciprocal CSI, or
// equally ZF / MRC combining of the uplink), one unit of power per stream (as a BS antenna's
// stream above); stream n's signature is row h_n of H and the Gram matrix is K = H H^H (Nr x Nr).
// Both are the formulas below on H (Nr >= Nt) or on H^T (Nr < Nt): (H^T)^H H^T = conj(K).
//
// - ICN = sigma_min / sigma_max over the min(Nr, Nt) singular values of H.
// - Objective f = sum_{l != k} |M_lk|^2 over the off-diagonal entries of the smaller Gram matrix
//   M (G or K; full recompute; SwarmChannel keeps it up to date per moved UAV). It is 0 exactly
//   when the signatures are orthogonal.
// - Per stream k, with signatures h_k (columns of H, or of H^T), noise variance psi^2 in the
//   units of H:
//     NV (matched filter):   |h_k|^4 / (sum_{m != k} |h_k^H h_m|^2 + |h_k|^2 psi^2)
//     ZF:                    1 / (psi^2 [(M)^-1]_kk)     (0 when H is rank deficient)
//     MF (single user):      |h_k|^2 / psi^2
//   For Nr < Nt these are the downlink with ZF precoding (unit-norm beams: the precoder's column
//   norms are exactly [(H H^H)^-1]_nn), the uplink's ZF combiner, and the uplink's MRC (the
//   downlink's MRT equals it when every row has the same norm, as in the far field).
// - Sum rate sum_k log2(1 + SINR_k) in bit/s/Hz.
// SINR values here are linear; to_db converts.

#include <Eigen/Core>

namespace losmimo::placement {

double inverse_condition_number(const Eigen::MatrixXcd& H);
double objective(const Eigen::MatrixXcd& H);

struct StreamSinr {
  Eigen::VectorXd nv;  // linear, one per stream (BS antenna if Nr >= Nt, else UAV)
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
