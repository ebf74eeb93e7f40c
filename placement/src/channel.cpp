#include "losmimo/placement/channel.h"

#include <cmath>
#include <complex>

namespace losmimo::placement {

ChannelModel::ChannelModel(const Scenario& scenario)
    : antennas_m_(bs_antenna_positions_m(scenario)),
      wavenumber_rad_per_m_(2.0 * M_PI / scenario.wavelength_m()),
      range_m_(scenario.range_m()),
      gain_model_(scenario.gain_model) {}

Eigen::VectorXcd ChannelModel::row(const Eigen::Vector3d& q_m) const {
  const int nt = num_antennas();
  Eigen::VectorXcd x(nt);
  for (int k = 0; k < nt; ++k) {
    const double d_m = (q_m - antennas_m_.col(k)).norm();
    // Reduce the phase before sincos: d / lambda is ~2e5 cycles at 1 km and 60 GHz.
    const double phase_rad = -wavenumber_rad_per_m_ * d_m;
    const double amplitude = gain_model_ == GainModel::kExact ? range_m_ / d_m : 1.0;
    x(k) = std::polar(amplitude, std::remainder(phase_rad, 2.0 * M_PI));
  }
  return x;
}

Eigen::MatrixXcd ChannelModel::matrix(const Eigen::Matrix3Xd& q_m) const {
  Eigen::MatrixXcd H(q_m.cols(), num_antennas());
  for (Eigen::Index n = 0; n < q_m.cols(); ++n) H.row(n) = row(q_m.col(n)).transpose();
  return H;
}

void ChannelModel::row_derivative_terms(const Eigen::Vector3d& q_m, Eigen::VectorXcd& s,
                                        Eigen::Matrix3Xd& U) const {
  const int nt = num_antennas();
  s.resize(nt);
  U.resize(3, nt);
  for (int k = 0; k < nt; ++k) {
    const Eigen::Vector3d v = q_m - antennas_m_.col(k);
    const double d_m = v.norm();
    U.col(k) = v / d_m;
    const double radial = gain_model_ == GainModel::kExact ? -1.0 / d_m : 0.0;
    s(k) = std::complex<double>(radial, -wavenumber_rad_per_m_);
  }
}

}  // namespace losmimo::placement
