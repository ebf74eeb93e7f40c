#pragma once
// The BS beacon observation model, its Jacobian, its inverse and the angle-aware innovation.
// h and J_z_q are range_az_el() and its Jacobian (range_az_el.h) with the BS array as the sensor
// frame: the same function the bearing-range landmark replay uses.
//
// Frame: BS array frame (placement/scenario.h): origin at the array centre, +x boresight, z up.
// State q = (x, y, z) [m], rho = sqrt(x^2 + y^2) [m], r = |q| [m].
// Observation z = h(q) = (r, az, el):
//   r  = |q|                          [m]
//   az = atan2(y, x)                  [rad], in (-pi, pi]
//   el = atan2(z, rho)                [rad], in [-pi/2, pi/2]
// Jacobian J_z_q = dh/dq (3 x 3, rows r, az, el; columns x, y, z):
//   dr/dq  = q^T / r
//   daz/dq = (-y, x, 0) / rho^2
//   del/dq = (-x z / rho, -y z / rho, rho) / r^2
// Inverse: q = g(z) = r (cos el cos az, cos el sin az, sin el), J_q_z = dg/dz.
// Noise: z_meas = h(q) + v, v ~ N(0, R), R = diag(sigma_range_m^2, sigma_angle_rad^2,
// sigma_angle_rad^2). At range r the lateral (cross-range) 1-sigma is r * sigma_angle_rad.
// Degenerate geometry: h is singular on the z axis (rho = 0) and at the origin; callers reject
// beacons there (see kMinBeaconRho_m).

#include <Eigen/Core>

#include "losmimo/localization/position/measurements.h"
#include "losmimo/localization/range_az_el.h"

namespace losmimo::localization {

// Below this horizontal distance from the array the azimuth is ill-conditioned [m].
inline constexpr double kMinBeaconRho_m = 1.0;

Eigen::Vector3d to_vector(const BeaconMeasurement& z);
BeaconMeasurement to_measurement(const Eigen::Vector3d& z);

// h(q) as above.
Eigen::Vector3d beacon_predict(const Eigen::Vector3d& q_m);
// J_z_q at q (requires rho > 0).
Eigen::Matrix3d beacon_jacobian(const Eigen::Vector3d& q_m);
// z_meas - z_pred with both angle components wrapped to (-pi, pi].
Eigen::Vector3d beacon_innovation(const Eigen::Vector3d& z_meas, const Eigen::Vector3d& z_pred);

// R = diag(sigma_range_m^2, sigma_angle_rad^2, sigma_angle_rad^2).
Eigen::Matrix3d beacon_noise_cov(double sigma_range_m, double sigma_angle_rad);

// g(z) and J_q_z: the position a single beacon implies.
Eigen::Vector3d beacon_to_position(const Eigen::Vector3d& z);
Eigen::Matrix3d beacon_to_position_jacobian(const Eigen::Vector3d& z);

// The beacon-only fix: mean g(z), covariance J_q_z R J_q_z^T (first order).
Belief beacon_fix(const BeaconMeasurement& z, double sigma_range_m, double sigma_angle_rad);

}  // namespace losmimo::localization
