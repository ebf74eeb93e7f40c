#pragma once
// Robot-frame odometry and the pose it moves: the motion model of the pose filters
// (pose/filter.h), written the way MRPT's actions carry it.
//
// Pose x = (x_m, y_m, z_m, yaw_rad) (PoseIndex): the robot origin in the map frame (the beacon
// map's frame) and the heading about +z, wrapped to (-pi, pi]. The robot frame is MRPT's: +x
// forward, +y left, +z up. Pitch and roll are zero: a ground robot, or a vehicle whose odometry
// is levelled. That is the CPose3D (x, y, z, yaw, 0, 0), and composition below is exactly
// CPose3D's (and, for z = dz = 0, CPose2D's); the tests check both against mrpt::poses.
// No IMU is used: the heading comes from the odometry's dyaw and from ranges through a sensor
// mounted off the robot's origin; where odometry is world-frame (the UAVs of the closed loop),
// the position filters of position/filter.h apply and no heading is needed.
//
// Odometry increment u = (dx_m, dy_m, dz_m, dyaw_rad): the pose change over one step, in the
// robot frame at the start of the step. Sources:
//   CActionRobotMovement2D       poseChange mean (x, y, phi) -> (dx, dy, 0, dphi), its 3x3 cov
//                                 (or odometry_2d() from rawOdometryIncrementReading and the
//                                 Gaussian motion model, which is how MRPT rebuilds poseChange)
//   CActionRobotMovement3D       poseChange.mean's (x, y, z, yaw), cov's x-y-z-yaw block
//                                 (odometry_3d())
//   CObservationOdometry         cumulative 2-D readings: increment_between(previous, current)
//
// Composition x' = x (+) u:
//   x' = x + cos(yaw) dx - sin(yaw) dy,   y' = y + sin(yaw) dx + cos(yaw) dy,
//   z' = z + dz,                           yaw' = wrap(yaw + dyaw)
// Jacobians (x' is linear in u, so the noise propagates exactly):
//   J_x'_x = [1 0 0  -sin(yaw) dx - cos(yaw) dy]      J_x'_u = [cos(yaw) -sin(yaw) 0 0]
//            [0 1 0   cos(yaw) dx - sin(yaw) dy]               [sin(yaw)  cos(yaw) 0 0]
//            [0 0 1   0                        ]               [0         0        1 0]
//            [0 0 0   1                        ]               [0         0        0 1]
// Noise: the true increment is u + n, n ~ N(0, Sigma_u), so given x,
//   x' ~ N(x (+) u, J_x'_u Sigma_u J_x'_u^T)     (MRPT's samplers: particle (+) sampled increment)
//
// MRPT's Gaussian motion model (CActionRobotMovement2D, mmGaussian), checked against MRPT 2.5.8:
//   D = |(dx, dy)| [m], A = |dphi| [rad] (the code multiplies radians, whatever its header says)
//   s_xy = minStdXY + a1 D + a2 A,   s_phi = minStdPHI + a3 D + a4 A
//   Sigma_(x, y, phi) = J diag(s_xy^2, s_xy^2, s_phi^2) J^T,
//   J = [c -s -s dx - c dy; s c c dx - s dy; 0 0 1],  c = cos(dphi / 2), s = sin(dphi / 2).

#include <Eigen/Core>

namespace losmimo::localization {

// Indices of the pose state (robot_localization's StateMembers idea).
enum PoseIndex : int { kPoseX = 0, kPoseY = 1, kPoseZ = 2, kPoseYaw = 3 };
inline constexpr int kPoseSize = 4;

struct OdometryIncrement {
  Eigen::Vector4d delta = Eigen::Vector4d::Zero();  // (dx_m, dy_m, dz_m, dyaw_rad), robot frame
  Eigen::Matrix4d cov = Eigen::Matrix4d::Zero();    // of delta: m^2, m rad, rad^2
};

// wrap_angle_rad() (position/beacon_model.h) with a fast path for angles within one turn of (-pi, pi]
// (sums and differences of wrapped angles): one comparison instead of std::remainder, which the
// particle filters would otherwise pay for every particle. Same range; may differ from
// wrap_angle_rad in the last bit.
double wrap_near_rad(double angle_rad);

// x (+) u, yaw wrapped to (-pi, pi].
Eigen::Vector4d compose(const Eigen::Vector4d& pose, const Eigen::Vector4d& delta);
// J_x'_x and J_x'_u above.
Eigen::Matrix4d compose_jacobian_pose(const Eigen::Vector4d& pose, const Eigen::Vector4d& delta);
Eigen::Matrix4d compose_jacobian_increment(const Eigen::Vector4d& pose);
// The increment u with from (+) u = to: (-from) (+) to, dyaw wrapped.
Eigen::Vector4d increment_between(const Eigen::Vector4d& from, const Eigen::Vector4d& to);

// CActionRobotMovement2D::TMotionModelOptions::TOptions_GaussianModel, with MRPT's defaults.
struct GaussianMotionModel2D {
  double a1 = 0.01;                               // m of s_xy per m travelled
  double a2 = 0.05729577951308232;                // m of s_xy per rad turned (RAD2DEG(0.001))
  double a3 = 0.017453292519943295;               // rad of s_phi per m travelled (DEG2RAD(1))
  double a4 = 0.05;                               // rad of s_phi per rad turned
  double min_std_xy_m = 0.01;                     // minStdXY
  double min_std_phi_rad = 0.003490658503988659;  // minStdPHI (DEG2RAD(0.2))
};

// Throws std::invalid_argument naming the first field that is negative or not finite.
void validate(const GaussianMotionModel2D& model);

// MRPT's Gaussian covariance of a 2-D increment (rows/cols x, y, phi), as above.
Eigen::Matrix3d gaussian_motion_cov_2d(double dx_m, double dy_m, double dphi_rad, const GaussianMotionModel2D& model);

// A 2-D odometry reading as a 4-D increment: dz = 0, Sigma_u the 3x3 above in the x-y-yaw
// block and sigma_z_m^2 on z (0 for a robot on a floor; the filters floor it).
OdometryIncrement odometry_2d(double dx_m, double dy_m, double dphi_rad, const GaussianMotionModel2D& model,
                              double sigma_z_m = 0.0);

// A 3-D increment (CActionRobotMovement3D: the mean's x, y, z, yaw) with the covariance of a
// CPose3DPDFGaussian (6x6, order x, y, z, yaw, pitch, roll): its x-y-z-yaw block is kept.
OdometryIncrement odometry_3d(const Eigen::Vector4d& delta, const Eigen::Matrix<double, 6, 6>& cov_xyzypr);

}  // namespace losmimo::localization
