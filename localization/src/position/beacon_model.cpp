#include "losmimo/localization/position/beacon_model.h"

#include <cmath>

namespace losmimo::localization {

Eigen::Vector3d to_vector(const BeaconMeasurement& z) { return {z.range_m, z.azimuth_rad, z.elevation_rad}; }

BeaconMeasurement to_measurement(const Eigen::Vector3d& z) {
  BeaconMeasurement m;
  m.range_m = z(0);
  m.azimuth_rad = z(1);
  m.elevation_rad = z(2);
  return m;
}

// The BS beacon is range_az_el of the UAV in the BS array frame (the array is the sensor frame).
Eigen::Vector3d beacon_predict(const Eigen::Vector3d& q_m) { return range_az_el(q_m); }

Eigen::Matrix3d beacon_jacobian(const Eigen::Vector3d& q_m) { return range_az_el_jacobian(q_m); }

Eigen::Vector3d beacon_innovation(const Eigen::Vector3d& z_meas, const Eigen::Vector3d& z_pred) {
  return range_az_el_innovation(z_meas, z_pred);
}

Eigen::Matrix3d beacon_noise_cov(double sigma_range_m, double sigma_angle_rad) {
  return Eigen::Vector3d(sigma_range_m * sigma_range_m, sigma_angle_rad * sigma_angle_rad,
                         sigma_angle_rad * sigma_angle_rad)
      .asDiagonal();
}

Eigen::Vector3d beacon_to_position(const Eigen::Vector3d& z) {
  const double r = z(0);
  const double ca = std::cos(z(1));
  const double sa = std::sin(z(1));
  const double ce = std::cos(z(2));
  const double se = std::sin(z(2));
  return {r * ce * ca, r * ce * sa, r * se};
}

Eigen::Matrix3d beacon_to_position_jacobian(const Eigen::Vector3d& z) {
  const double r = z(0);
  const double ca = std::cos(z(1));
  const double sa = std::sin(z(1));
  const double ce = std::cos(z(2));
  const double se = std::sin(z(2));
  Eigen::Matrix3d J_q_z;
  J_q_z << ce * ca, -r * ce * sa, -r * se * ca,  //
      ce * sa, r * ce * ca, -r * se * sa,        //
      se, 0.0, r * ce;
  return J_q_z;
}

Belief beacon_fix(const BeaconMeasurement& z, double sigma_range_m, double sigma_angle_rad) {
  const Eigen::Vector3d z_vec = to_vector(z);
  const Eigen::Matrix3d J_q_z = beacon_to_position_jacobian(z_vec);
  Belief belief;
  belief.mean_m = beacon_to_position(z_vec);
  belief.cov_m2 = J_q_z * beacon_noise_cov(sigma_range_m, sigma_angle_rad) * J_q_z.transpose();
  belief.cov_m2 = 0.5 * (belief.cov_m2 + belief.cov_m2.transpose()).eval();
  return belief;
}

}  // namespace losmimo::localization
