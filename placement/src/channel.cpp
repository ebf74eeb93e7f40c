#include "losmimo/placement/channel.h"

#include <cmath>
#include <complex>

namespace losmimo::placement {

ChannelModel::ChannelModel(const Scenario& scenario)
    : antennas_m_(bs_antenna_positions_m(scenario)),
      wavenumber_rad_per_m_(2.0 * M_PI / scenario.wavelength_m()),
      range_m_(scenario.range_m()),
      gain_model_(scenario.gain_model) {
  ax_m_ = antennas_m_.row(0).transpose().array();
  ay_m_ = antennas_m_.row(1).transpose().array();
  az_m_ = antennas_m_.row(2).transpose().array();
}

Eigen::VectorXcd ChannelModel::row(const Eigen::Vector3d& q_m) const {
  Eigen::VectorXcd x;
  row(q_m, x);
  return x;
}

void ChannelModel::row(const Eigen::Vector3d& q_m, Eigen::VectorXcd& x) const {
  const int nt = num_antennas();
  x.resize(nt);
  // Per-thread scratch: a probe allocates nothing. Whole-array expressions vectorise.
  thread_local Eigen::ArrayXd d_m, phase_rad, c, s;
  d_m = ((ax_m_ - q_m.x()).square() + (ay_m_ - q_m.y()).square() + (az_m_ - q_m.z()).square()).sqrt();
  // d / lambda is ~2e5 cycles at 1 km and 60 GHz: unit_phasors reduces the phase exactly.
  phase_rad = -wavenumber_rad_per_m_ * d_m;
  c.resize(nt);
  s.resize(nt);
  unit_phasors(phase_rad.data(), c.data(), s.data(), nt);
  double* out = reinterpret_cast<double*>(x.data());
  if (gain_model_ == GainModel::kExact) {
    for (int k = 0; k < nt; ++k) {
      const double amplitude = range_m_ / d_m(k);
      out[2 * k] = amplitude * c(k);
      out[2 * k + 1] = amplitude * s(k);
    }
  } else {
    for (int k = 0; k < nt; ++k) {
      out[2 * k] = c(k);
      out[2 * k + 1] = s(k);
    }
  }
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
