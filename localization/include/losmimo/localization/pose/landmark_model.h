#pragma once
// Bearing-range readings of mapped landmarks from a sensor on a 6-D robot pose: the model of
// MRPT's CObservationBearingRange (kf-slam's logs), written with mrpt::poses::CPose3D so that
// composition is MRPT's own.
//
// Pose x = (x_m, y_m, z_m, yaw_rad, pitch_rad, roll_rad) (Pose6Index): CPose3D's parameters and
// order, the robot origin in the map frame (the landmark map's). Robot frame: +x forward, +y left,
// +z up. A planar pose (a 2-D log) is one with z = pitch = roll = 0.
// Sensor pose s on the robot: sensorLocationOnRobot, a Pose6 in the robot frame.
// Reading of landmark L (map frame [m]):
//   p = (x (+) s) (-) L                   the landmark in the sensor frame
//   z = range_az_el(p)                    (range_az_el.h: range, azimuth, elevation)
// computed as p = s (-) (x (-) L) with CPose3D::inverseComposePoint, whose Jacobians give
//   J_z_x = J_z_p * J_p_pr * J_pr_x,  pr = x (-) L (the landmark in the robot frame),
//   J_pr_x = d(x (-) L)/dx (3x6, MRPT's df_dpose), J_p_pr = R_s^T (df_dpoint).
// MRPT stores yaw = azimuth and pitch = -elevation: to_range_az_el() converts.
// Odometry: x' = x (+) u (CPose3D composition, u in the robot frame at the start of the step),
// with J_x'_x and J_x'_u as central differences (step 1e-6) of that composition in these
// coordinates. Not CPose3DPDF::jacobiansPoseComposition: in MRPT 2.5.8 its three angle rows
// come out with the opposite sign on part of the rotation group (e.g. x yaw 1.97, roll -2.89,
// u yaw -2.87; tests/localization/pose/landmark_model_test.cpp checks ours against central
// differences at random poses).

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <mrpt/poses/CPose3D.h>

namespace losmimo::localization {

using Pose6 = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix36d = Eigen::Matrix<double, 3, 6>;

enum Pose6Index : int { kP6X = 0, kP6Y = 1, kP6Z = 2, kP6Yaw = 3, kP6Pitch = 4, kP6Roll = 5 };

// x (+) u as CPose3D (angles normalised as CPose3D does: yaw, roll in (-pi, pi], pitch in
// [-pi/2, pi/2]); J_x'_x and J_x'_u when asked.
Pose6 compose_pose6(const Pose6& x, const Pose6& u, Matrix6d* J_x = nullptr, Matrix6d* J_u = nullptr);

// a - b with the three angle differences wrapped to (-pi, pi]: the deviation of a from b in the
// pose's own coordinates (filters' innovations, particle moments).
Pose6 pose6_deviation(const Pose6& a, const Pose6& b);

// Landmark in the sensor frame (header); J_p_x (3x6) when asked.
Eigen::Vector3d landmark_in_sensor(const Pose6& robot, const Pose6& sensor_on_robot, const Eigen::Vector3d& landmark_m,
                                   Matrix36d* J_p_x = nullptr);
// z = range_az_el(p); J_z_x when asked (zero rows are never returned: callers keep rho > 0, see
// kMinLandmarkRho_m).
Eigen::Vector3d landmark_predict(const Pose6& robot, const Pose6& sensor_on_robot, const Eigen::Vector3d& landmark_m,
                                 Matrix36d* J_z_x = nullptr);

// The same with the poses already as CPose3D (the particle filter builds each once, not once per
// reading and particle).
mrpt::poses::CPose3D to_cpose3d(const Pose6& pose);
Eigen::Vector3d landmark_predict(const mrpt::poses::CPose3D& robot, const mrpt::poses::CPose3D& sensor_on_robot,
                                 const Eigen::Vector3d& landmark_m, Matrix36d* J_z_x = nullptr);

// Below this horizontal distance in the sensor frame the azimuth is ill-conditioned [m]; such
// readings are not fused.
inline constexpr double kMinLandmarkRho_m = 1e-3;

// MRPT's (range, yaw, pitch) as (range, azimuth, elevation): pitch = -elevation.
Eigen::Vector3d to_range_az_el(double range_m, double yaw_rad, double pitch_rad);

// One reading of a CObservationBearingRange.
struct BearingReading {
  std::int32_t landmark_id = -1;                // -1: the sensor does not identify it (INVALID_LANDMARK_ID)
  Eigen::Vector3d z = Eigen::Vector3d::Zero();  // (range_m, azimuth_rad, elevation_rad)
};

// One CObservationBearingRange.
struct BearingScan {
  std::vector<BearingReading> readings;
  Pose6 sensor_on_robot = Pose6::Zero();            // sensorLocationOnRobot
  Eigen::Vector3d sigma = Eigen::Vector3d::Zero();  // sensor_std_range, _yaw, _pitch (0: not given)
  double max_range_m = 0.0;                         // maxSensorDistance (0: no limit)
};

}  // namespace losmimo::localization
