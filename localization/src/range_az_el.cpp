#include "losmimo/localization/range_az_el.h"

#include <cmath>

namespace losmimo::localization {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double wrap_angle_rad(double angle_rad) {
  // Inside (-pi, pi] remainder() returns its argument exactly (quotient 0), so the common case
  // skips the library call with the same bits.
  if (angle_rad > -kPi && angle_rad <= kPi) return angle_rad;
  // remainder() maps to [-pi, pi]; fold -pi to +pi so the range is (-pi, pi].
  double wrapped = std::remainder(angle_rad, 2.0 * kPi);
  if (wrapped <= -kPi) wrapped += 2.0 * kPi;
  return wrapped;
}

Eigen::Vector3d range_az_el(const Eigen::Vector3d& p_sensor_m) {
  const double rho_m = std::hypot(p_sensor_m.x(), p_sensor_m.y());
  return {p_sensor_m.norm(), std::atan2(p_sensor_m.y(), p_sensor_m.x()), std::atan2(p_sensor_m.z(), rho_m)};
}

Eigen::Matrix3d range_az_el_jacobian(const Eigen::Vector3d& p_sensor_m) {
  const double x = p_sensor_m.x();
  const double y = p_sensor_m.y();
  const double z = p_sensor_m.z();
  const double rho2 = x * x + y * y;
  const double rho = std::sqrt(rho2);
  const double r2 = rho2 + z * z;
  const double r = std::sqrt(r2);
  Eigen::Matrix3d J_z_p;
  J_z_p << x / r, y / r, z / r,                            // range
      -y / rho2, x / rho2, 0.0,                            // azimuth
      -x * z / (rho * r2), -y * z / (rho * r2), rho / r2;  // elevation
  return J_z_p;
}

Eigen::Vector3d range_az_el_innovation(const Eigen::Vector3d& z_meas, const Eigen::Vector3d& z_pred) {
  return {z_meas(0) - z_pred(0), wrap_angle_rad(z_meas(1) - z_pred(1)), wrap_angle_rad(z_meas(2) - z_pred(2))};
}

}  // namespace losmimo::localization
