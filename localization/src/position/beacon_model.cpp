#include "losmimo/localization/position/beacon_model.h"

#include <cmath>

namespace losmimo::localization {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double wrap_angle_rad(double angle_rad) {
  // remainder() maps to [-pi, pi]; fold -pi to +pi so the range is (-pi, pi].
  double wrapped = std::remainder(angle_rad, 2.0 * kPi);
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  return wrapped;
}

Eigen::Vector3d to_vector(const BeaconMeasurement& z) { return {z.range_m, z.azimuth_rad, z.elevation_rad}; }

BeaconMeasurement to_measurement(const Eigen::Vector3d& z) {
  BeaconMeasurement m;
  m.range_m = z(0);
  m.azimuth_rad = z(1);
  m.elevation_rad = z(2);
  return m;
}

Eigen::Vector3d beacon_predict(const Eigen::Vector3d& q_m) {
  const double rho_m = std::hypot(q_m.x(), q_m.y());
  return {q_m.norm(), std::atan2(q_m.y(), q_m.x()), std::atan2(q_m.z(), rho_m)};
}

Eigen::Matrix3d beacon_jacobian(const Eigen::Vector3d& q_m) {
  const double x = q_m.x();
  const double y = q_m.y();
  const double z = q_m.z();
  const double rho2 = x * x + y * y;
  const double rho = std::sqrt(rho2);
  const double r2 = rho2 + z * z;
  const double r = std::sqrt(r2);
  Eigen::Matrix3d J_z_q;
  J_z_q << x / r, y / r, z / r,                            // range
      -y / rho2, x / rho2, 0.0,                            // azimuth
      -x * z / (rho * r2), -y * z / (rho * r2), rho / r2;  // elevation
  return J_z_q;
}

Eigen::Vector3d beacon_innovation(const Eigen::Vector3d& z_meas, const Eigen::Vector3d& z_pred) {
  return {z_meas(0) - z_pred(0), wrap_angle_rad(z_meas(1) - z_pred(1)), wrap_angle_rad(z_meas(2) - z_pred(2))};
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
