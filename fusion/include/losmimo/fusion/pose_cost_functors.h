#pragma once
// Ceres residuals of the range-only pose smoother (range_smoother.h): the pose filters' models
// (localization/odometry_model.h, range_model.h) as whitened residuals, in cost_functors.h's style.
// Parameter block: a pose x = (x_m, y_m, z_m, yaw_rad) in the map frame; yaw is left unbounded
// in the solver, every residual wraps the angles it compares.

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <cmath>

#include "losmimo/fusion/cost_functors.h"

namespace losmimo::fusion {

// Gaussian prior on a pose (the filter's belief at a window's first frame):
//   e = (x - mean_x, y - mean_y, z - mean_z, wrap(yaw - mean_yaw)),   r = S e,  S^T S = cov^-1
class PosePriorCost {
 public:
  PosePriorCost(const Eigen::Vector4d& mean, const Eigen::Matrix4d& sqrt_information)
      : mean_(mean), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    Eigen::Matrix<T, 4, 1> e;
    for (int i = 0; i < 3; ++i) e(i) = pose[i] - mean_(i);
    e(3) = wrap_angle_rad(pose[3] - mean_(3));
    Eigen::Map<Eigen::Matrix<T, 4, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  // Throws std::invalid_argument if cov is not symmetric positive definite.
  static ceres::CostFunction* Create(const Eigen::Vector4d& mean, const Eigen::Matrix4d& cov);

 private:
  const Eigen::Vector4d mean_;
  const Eigen::Matrix4d sqrt_information_;
};

// One odometry increment u (robot frame at pose a, covariance Sigma_u) between poses a and b.
// The noise model of odometry_model.h, x_b = x_a (+) (u + n), solved for n:
//   e = ( Rz(-yaw_a) (p_b - p_a)_xy - u_xy,  z_b - z_a - u_z,  wrap(yaw_b - yaw_a - u_yaw) ),
//   r = S e,  S^T S = Sigma_u^-1   (exact: the composition is linear in u)
class OdometryCost {
 public:
  OdometryCost(const Eigen::Vector4d& increment, const Eigen::Matrix4d& sqrt_information)
      : increment_(increment), sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* const pose_a, const T* const pose_b, T* residual) const {
    using std::cos;
    using std::sin;
    const T dx = pose_b[0] - pose_a[0];
    const T dy = pose_b[1] - pose_a[1];
    const T c = cos(pose_a[3]);
    const T s = sin(pose_a[3]);
    Eigen::Matrix<T, 4, 1> e;
    e(0) = c * dx + s * dy - increment_(0);
    e(1) = -s * dx + c * dy - increment_(1);
    e(2) = pose_b[2] - pose_a[2] - increment_(2);
    e(3) = wrap_angle_rad(pose_b[3] - pose_a[3] - increment_(3));
    Eigen::Map<Eigen::Matrix<T, 4, 1>> r(residual);
    r = sqrt_information_.cast<T>() * e;
    return true;
  }

  // Throws std::invalid_argument if cov is not symmetric positive definite (floor it first, as
  // localization::screen_odometry does).
  static ceres::CostFunction* Create(const Eigen::Vector4d& increment, const Eigen::Matrix4d& cov);

 private:
  const Eigen::Vector4d increment_;
  const Eigen::Matrix4d sqrt_information_;
};

// One beacon range (range_model.h) seen from pose x with the sensor at s on the robot:
//   c = p + Rz(yaw) s,   r = (|c - b| - range_m) / sigma_m
class RangeCost {
 public:
  RangeCost(double range_m, const Eigen::Vector3d& sensor_on_robot_m, const Eigen::Vector3d& beacon_m, double sigma_m)
      : range_m_(range_m), sensor_on_robot_m_(sensor_on_robot_m), beacon_m_(beacon_m), inv_sigma_(1.0 / sigma_m) {}

  template <typename T>
  bool operator()(const T* const pose, T* residual) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const T c = cos(pose[3]);
    const T s = sin(pose[3]);
    const T dx = pose[0] + c * sensor_on_robot_m_(0) - s * sensor_on_robot_m_(1) - beacon_m_(0);
    const T dy = pose[1] + s * sensor_on_robot_m_(0) + c * sensor_on_robot_m_(1) - beacon_m_(1);
    const T dz = pose[2] + sensor_on_robot_m_(2) - beacon_m_(2);
    residual[0] = (sqrt(dx * dx + dy * dy + dz * dz) - range_m_) * inv_sigma_;
    return true;
  }

  static ceres::CostFunction* Create(double range_m, const Eigen::Vector3d& sensor_on_robot_m,
                                     const Eigen::Vector3d& beacon_m, double sigma_m);

 private:
  const double range_m_;
  const Eigen::Vector3d sensor_on_robot_m_;
  const Eigen::Vector3d beacon_m_;
  const double inv_sigma_;
};

}  // namespace losmimo::fusion
