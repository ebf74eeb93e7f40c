#pragma once
// Ceres residuals of the sliding-window refinement (refinement.h). Every residual is whitened
// (scaled by the square-root information), so its squared norm is a negative log-likelihood.
// Parameter blocks: a position q = (x, y, z) [m] in the BS array frame, and for CSI one
// reference phase psi [rad] (csi.h). Create() returns a cost function owned by the
// ceres::Problem it is added to (Ceres' ownership convention).

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <cmath>

namespace losmimo::fusion {

// Wraps an angle to (-pi, pi] through atan2(sin a, cos a): smooth (derivative 1) everywhere but
// on the cut, and valid for ceres::Jet as well as double.
template <typename T>
T wrap_angle_rad(const T& angle_rad) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(angle_rad), cos(angle_rad));
}

// S with S^T S = cov^-1 (S = L^-1 for cov = L L^T), the whitening of a Gaussian residual.
// Throws std::invalid_argument naming `who` if cov is not finite symmetric positive definite.
Eigen::MatrixXd sqrt_information(const Eigen::MatrixXd& cov, const char* who);

// Gaussian prior on a position (the filter's belief at the oldest window epoch):
//   r = S (q - mean),   S^T S = cov^-1   (S = L^-1, cov = L L^T)
class PositionPriorCost {
 public:
  PositionPriorCost(const Eigen::Vector3d& mean_m, const Eigen::Matrix3d& sqrt_information)
      : mean_m_(mean_m), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const q_m, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> q(q_m);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residual);
    r = sqrt_information_.cast<T>() * (q - mean_m_.cast<T>());
    return true;
  }

  // Throws std::invalid_argument if cov_m2 is not symmetric positive definite.
  static ceres::CostFunction* Create(const Eigen::Vector3d& mean_m, const Eigen::Matrix3d& cov_m2);

 private:
  const Eigen::Vector3d mean_m_;
  const Eigen::Matrix3d sqrt_information_;
};

// The BS beacon (localization/measurements.h) at position q, with rho = sqrt(x^2 + y^2):
//   r = ( (|q| - range_m) / sigma_range_m,
//         wrap(atan2(y, x) - azimuth_rad) / sigma_angle_rad,
//         wrap(atan2(z, rho) - elevation_rad) / sigma_angle_rad )
class BeaconCost {
 public:
  BeaconCost(double range_m, double azimuth_rad, double elevation_rad, double sigma_range_m, double sigma_angle_rad)
      : range_m_(range_m),
        azimuth_rad_(azimuth_rad),
        elevation_rad_(elevation_rad),
        inv_sigma_range_(1.0 / sigma_range_m),
        inv_sigma_angle_(1.0 / sigma_angle_rad) {}

  template <typename T>
  bool operator()(const T* const q_m, T* residual) const {
    using std::atan2;
    using std::sqrt;
    const T rho_m = sqrt(q_m[0] * q_m[0] + q_m[1] * q_m[1]);
    const T range_m = sqrt(rho_m * rho_m + q_m[2] * q_m[2]);
    residual[0] = (range_m - range_m_) * inv_sigma_range_;
    residual[1] = wrap_angle_rad(atan2(q_m[1], q_m[0]) - azimuth_rad_) * inv_sigma_angle_;
    residual[2] = wrap_angle_rad(atan2(q_m[2], rho_m) - elevation_rad_) * inv_sigma_angle_;
    return true;
  }

  static ceres::CostFunction* Create(double range_m, double azimuth_rad, double elevation_rad, double sigma_range_m,
                                     double sigma_angle_rad);

 private:
  const double range_m_;
  const double azimuth_rad_;
  const double elevation_rad_;
  const double inv_sigma_range_;
  const double inv_sigma_angle_;
};

// Dead-reckoning displacement d measured from position a to position b:
//   r = (q_b - q_a - d) / sigma_m,   sigma_m = floor + per_m * |d|   (chosen by the caller)
class DisplacementCost {
 public:
  DisplacementCost(const Eigen::Vector3d& displacement_m, double sigma_m)
      : displacement_m_(displacement_m), inv_sigma_(1.0 / sigma_m) {}

  template <typename T>
  bool operator()(const T* const q_a_m, const T* const q_b_m, T* residual) const {
    for (int i = 0; i < 3; ++i) {
      residual[i] = (q_b_m[i] - q_a_m[i] - displacement_m_(i)) * inv_sigma_;
    }
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& displacement_m, double sigma_m);

 private:
  const Eigen::Vector3d displacement_m_;
  const double inv_sigma_;
};

// One CSI row (csi.h) seen from position q with reference phase psi, one residual per antenna:
//   r_k = wrap(arg y_k + kappa delta_k(q) - psi) / sigma_phase_rad,
//   delta_k(q) = (|p_k|^2 - 2 p_k . q) / (|q - p_k| + |q|)
class CsiPhaseCost {
 public:
  // measured_phase_rad(k) = arg y_k; antennas_m = p (3 x Nt); kappa = 2 pi / lambda.
  CsiPhaseCost(const Eigen::VectorXd& measured_phase_rad, const Eigen::Matrix3Xd& antennas_m,
               double wavenumber_rad_per_m, double sigma_phase_rad)
      : measured_phase_rad_(measured_phase_rad),
        antennas_m_(antennas_m),
        wavenumber_rad_per_m_(wavenumber_rad_per_m),
        inv_sigma_(1.0 / sigma_phase_rad) {}

  int num_residuals() const { return static_cast<int>(measured_phase_rad_.size()); }

  template <typename T>
  bool operator()(const T* const q_m, const T* const psi_rad, T* residual) const {
    using std::sqrt;
    const T range_m = sqrt(q_m[0] * q_m[0] + q_m[1] * q_m[1] + q_m[2] * q_m[2]);
    for (Eigen::Index k = 0; k < antennas_m_.cols(); ++k) {
      const T dx = q_m[0] - antennas_m_(0, k);
      const T dy = q_m[1] - antennas_m_(1, k);
      const T dz = q_m[2] - antennas_m_(2, k);
      const T d_m = sqrt(dx * dx + dy * dy + dz * dz);
      const T p_dot_q = antennas_m_(0, k) * q_m[0] + antennas_m_(1, k) * q_m[1] + antennas_m_(2, k) * q_m[2];
      const T delta_m = (antennas_m_.col(k).squaredNorm() - 2.0 * p_dot_q) / (d_m + range_m);
      residual[k] = wrap_angle_rad(measured_phase_rad_(k) + wavenumber_rad_per_m_ * delta_m - psi_rad[0]) * inv_sigma_;
    }
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::VectorXd& measured_phase_rad, const Eigen::Matrix3Xd& antennas_m,
                                     double wavenumber_rad_per_m, double sigma_phase_rad);

 private:
  const Eigen::VectorXd measured_phase_rad_;
  const Eigen::Matrix3Xd antennas_m_;
  const double wavenumber_rad_per_m_;
  const double inv_sigma_;
};

}  // namespace losmimo::fusion
