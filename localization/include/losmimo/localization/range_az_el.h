#pragma once
// Range, azimuth and elevation of a point expressed in a sensor frame, and its Jacobian: the one
// measurement function of every range-bearing sensor in losmimo. The closed loop's BS beacon
// (position/beacon_model.h: the UAV in the BS array frame) and the bearing-range landmark replay
// (pose/landmark_model.h: a mapped landmark in the frame of a sensor on the robot) both call it.
//
// Frame: the sensor frame, +x forward (boresight), +y left, z up (MRPT's CPose3D axes).
// Point p = (x, y, z) [m], rho = sqrt(x^2 + y^2) [m], r = |p| [m].
// z = h(p) = (r, az, el):
//   r  = |p|                          [m]
//   az = atan2(y, x)                  [rad], in (-pi, pi]
//   el = atan2(z, rho)                [rad], in [-pi/2, pi/2], positive above the x-y plane
// MRPT's CObservationBearingRange stores yaw = az and pitch = -el (its header: pitch is the
// "negative elevation"; CPose3D::sphericalCoordinates computes the same).
// Jacobian J_z_p = dh/dp (3 x 3, rows r, az, el; columns x, y, z):
//   dr/dp  = p^T / r
//   daz/dp = (-y, x, 0) / rho^2
//   del/dp = (-x z / rho, -y z / rho, rho) / r^2
// Degenerate geometry: h is singular on the z axis (rho = 0) and at the origin; callers keep
// points away from there (the Jacobian is not finite at rho = 0).

#include <Eigen/Core>

namespace losmimo::localization {

// Wraps an angle to (-pi, pi].
double wrap_angle_rad(double angle_rad);

// h(p) above.
Eigen::Vector3d range_az_el(const Eigen::Vector3d& p_sensor_m);
// J_z_p at p (requires rho > 0).
Eigen::Matrix3d range_az_el_jacobian(const Eigen::Vector3d& p_sensor_m);
// z_meas - z_pred with both angle components wrapped to (-pi, pi].
Eigen::Vector3d range_az_el_innovation(const Eigen::Vector3d& z_meas, const Eigen::Vector3d& z_pred);

}  // namespace losmimo::localization
