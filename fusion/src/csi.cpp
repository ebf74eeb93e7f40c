#include "losmimo/fusion/csi.h"

#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>

namespace losmimo::fusion {

CsiMeasurement simulate_csi(const placement::ChannelModel& model, const Eigen::Vector3d& q_true_m,
                            double noise_variance, std::mt19937_64& rng) {
  if (!(noise_variance >= 0.0) || !std::isfinite(noise_variance)) {
    throw std::invalid_argument("simulate_csi: noise_variance = " + std::to_string(noise_variance) +
                                " must be a finite number >= 0");
  }
  std::uniform_real_distribution<double> uniform_phase(-M_PI, M_PI);
  // CN(0, v): real and imaginary parts each N(0, v / 2).
  std::normal_distribution<double> component(0.0, std::sqrt(0.5 * noise_variance));
  const std::complex<double> rotation = std::polar(1.0, uniform_phase(rng));
  CsiMeasurement csi;
  csi.y = rotation * model.row(q_true_m);
  for (Eigen::Index k = 0; k < csi.y.size(); ++k) {
    const double re = component(rng);
    const double im = component(rng);
    csi.y(k) += std::complex<double>(re, im);
  }
  return csi;
}

double csi_phase_sigma_rad(double noise_variance) { return std::sqrt(0.5 * noise_variance); }

Eigen::VectorXd csi_path_difference_m(const placement::ChannelModel& model, const Eigen::Vector3d& q_m) {
  const Eigen::Matrix3Xd& p = model.antennas_m();
  const double range_m = q_m.norm();
  Eigen::VectorXd delta(p.cols());
  for (Eigen::Index k = 0; k < p.cols(); ++k) {
    const double d_m = (q_m - p.col(k)).norm();
    delta(k) = (p.col(k).squaredNorm() - 2.0 * p.col(k).dot(q_m)) / (d_m + range_m);
  }
  return delta;
}

double csi_reference_phase_rad(const placement::ChannelModel& model, const CsiMeasurement& csi,
                               const Eigen::Vector3d& q_m) {
  const Eigen::VectorXd delta = csi_path_difference_m(model, q_m);
  std::complex<double> sum = 0.0;
  for (Eigen::Index k = 0; k < delta.size(); ++k) {
    sum += csi.y(k) * std::polar(1.0, model.wavenumber_rad_per_m() * delta(k));
  }
  return std::arg(sum);
}

}  // namespace losmimo::fusion
