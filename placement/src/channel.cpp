#include "losmimo/placement/channel.h"

#include <cmath>
#include <complex>

namespace losmimo::placement {

ChannelModel::ChannelModel(const Scenario& scenario)
    : antennas_m_(bs_antenna_positions_m(scenario)),
      wavenumber_rad_per_m_(2.0 * M_PI / scenario.wavelength_m()),
      range_m_(scenario.range_m()),
      gain_model_(scenario.gain_model),
      kernels_(&kernels::active_kernels()) {
  const int nt = num_antennas();
  const int ld = kernels::padded(nt);
  padded_x_m_.assign(ld, 0.0);
  padded_y_m_.assign(ld, 0.0);
  padded_z_m_.assign(ld, 0.0);
  padded_valid_.assign(ld, 0.0);
  for (int k = 0; k < nt; ++k) {
    padded_x_m_[k] = antennas_m_(0, k);
    padded_y_m_[k] = antennas_m_(1, k);
    padded_z_m_[k] = antennas_m_(2, k);
    padded_valid_[k] = 1.0;
  }
  geometry_.nt = nt;
  geometry_.ld = ld;
  geometry_.wavenumber_rad_per_m = wavenumber_rad_per_m_;
  geometry_.range_m = range_m_;
  geometry_.exact_gain = gain_model_ == GainModel::kExact;
  geometry_.ax_m = padded_x_m_.data();
  geometry_.ay_m = padded_y_m_.data();
  geometry_.az_m = padded_z_m_.data();
  geometry_.valid = padded_valid_.data();
}

ChannelModel::ChannelModel(const ChannelModel& other) { *this = other; }

ChannelModel& ChannelModel::operator=(const ChannelModel& other) {
  if (this == &other) return *this;
  antennas_m_ = other.antennas_m_;
  padded_x_m_ = other.padded_x_m_;
  padded_y_m_ = other.padded_y_m_;
  padded_z_m_ = other.padded_z_m_;
  padded_valid_ = other.padded_valid_;
  wavenumber_rad_per_m_ = other.wavenumber_rad_per_m_;
  range_m_ = other.range_m_;
  gain_model_ = other.gain_model_;
  kernels_ = other.kernels_;
  geometry_ = other.geometry_;
  geometry_.ax_m = padded_x_m_.data();
  geometry_.ay_m = padded_y_m_.data();
  geometry_.az_m = padded_z_m_.data();
  geometry_.valid = padded_valid_.data();
  return *this;
}

Eigen::VectorXcd ChannelModel::row(const Eigen::Vector3d& q_m) const {
  Eigen::VectorXcd x;
  row(q_m, x);
  return x;
}

void ChannelModel::row(const Eigen::Vector3d& q_m, Eigen::VectorXcd& x) const {
  const int nt = num_antennas();
  x.resize(nt);
  // Per-thread scratch: a row allocates nothing. The kernel writes split planes.
  thread_local std::vector<double> re, im;
  re.resize(geometry_.ld);
  im.resize(geometry_.ld);
  row_planes(q_m, re.data(), im.data());
  for (int k = 0; k < nt; ++k) x(k) = std::complex<double>(re[k], im[k]);
}

void ChannelModel::row_planes(const Eigen::Vector3d& q_m, double* re, double* im) const {
  const double q[3] = {q_m.x(), q_m.y(), q_m.z()};
  kernels_->row(geometry_, q, re, im);
}

Eigen::MatrixXcd ChannelModel::matrix(const Eigen::Matrix3Xd& q_m) const {
  Eigen::MatrixXcd H(q_m.cols(), num_antennas());
  for (Eigen::Index n = 0; n < q_m.cols(); ++n) H.row(n) = row(q_m.col(n)).transpose();
  return H;
}

void ChannelModel::row_derivative_terms(const Eigen::Vector3d& q_m, Eigen::VectorXcd& s, Eigen::Matrix3Xd& U) const {
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
