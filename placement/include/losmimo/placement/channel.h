#pragma once
// LoS channel between the BS array and the UAVs (paper eq. 1), in normalised units.
//
//   H(n, m) = gamma_nm / g_R * exp(-j 2 pi d_nm / lambda),   d_nm = |q_n - p_m|
//
// Rows are UAVs (Nr), columns BS antennas (Nt). Dividing by the far-field gain
// g_R = lambda / (4 pi R) makes every entry unit-modulus in the far-field model, so the
// objective, its gradient and the GD step are independent of carrier and range scaling;
// the noise variance in the same units is 1 / SNR (Scenario::noise_variance).

#include <Eigen/Core>
#include <vector>

#include "losmimo/placement/kernels.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::placement {

class ChannelModel {
 public:
  explicit ChannelModel(const Scenario& scenario);
  // Copies point their geometry at their own arrays.
  ChannelModel(const ChannelModel& other);
  ChannelModel& operator=(const ChannelModel& other);

  // The channel row (as a column vector, length Nt) of a UAV at q_m (metres).
  Eigen::VectorXcd row(const Eigen::Vector3d& q_m) const;
  // The same row into x (resized to Nt; no allocation when it already has that size).
  void row(const Eigen::Vector3d& q_m, Eigen::VectorXcd& x) const;
  // The same row in the kernels' layout: re[k] + j im[k], k < geometry().ld (pads 0).
  void row_planes(const Eigen::Vector3d& q_m, double* re, double* im) const;
  // The full Nr x Nt channel of UAVs at the columns of q_m (3 x Nr).
  Eigen::MatrixXcd matrix(const Eigen::Matrix3Xd& q_m) const;

  // d row(k) / d q = row(k) * s_k * u_k^T with u_k the unit vector from antenna k to q and
  // s_k = -j 2 pi / lambda (far field) or -j 2 pi / lambda - 1 / d_k (exact gain).
  // Returns s (length Nt) and U (3 x Nt, the u_k) for a UAV at q_m.
  void row_derivative_terms(const Eigen::Vector3d& q_m, Eigen::VectorXcd& s, Eigen::Matrix3Xd& U) const;

  const Eigen::Matrix3Xd& antennas_m() const { return antennas_m_; }
  int num_antennas() const { return static_cast<int>(antennas_m_.cols()); }
  double wavenumber_rad_per_m() const { return wavenumber_rad_per_m_; }
  double range_m() const { return range_m_; }
  GainModel gain_model() const { return gain_model_; }
  // The array in the kernels' padded layout (kernels.h), and the kernels of this process.
  const kernels::RowGeometry& geometry() const { return geometry_; }
  const kernels::Kernels& kernels() const { return *kernels_; }

 private:
  Eigen::Matrix3Xd antennas_m_;
  double wavenumber_rad_per_m_;
  double range_m_;
  GainModel gain_model_;
  std::vector<double> padded_x_m_, padded_y_m_, padded_z_m_, padded_valid_;
  kernels::RowGeometry geometry_;
  const kernels::Kernels* kernels_;
};

}  // namespace losmimo::placement
