#include "losmimo/localization/pose/odometry_model.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "losmimo/localization/position/beacon_model.h"

namespace losmimo::localization {

double wrap_near_rad(double angle_rad) {
  constexpr double kPi = 3.14159265358979323846;
  if (angle_rad > kPi) angle_rad -= 2.0 * kPi;
  if (angle_rad <= -kPi) angle_rad += 2.0 * kPi;
  return (angle_rad > kPi || angle_rad <= -kPi) ? wrap_angle_rad(angle_rad) : angle_rad;
}

Eigen::Vector4d compose(const Eigen::Vector4d& pose, const Eigen::Vector4d& delta) {
  const double c = std::cos(pose(kPoseYaw));
  const double s = std::sin(pose(kPoseYaw));
  return {pose(kPoseX) + c * delta(kPoseX) - s * delta(kPoseY), pose(kPoseY) + s * delta(kPoseX) + c * delta(kPoseY),
          pose(kPoseZ) + delta(kPoseZ), wrap_near_rad(pose(kPoseYaw) + delta(kPoseYaw))};
}

Eigen::Matrix4d compose_jacobian_pose(const Eigen::Vector4d& pose, const Eigen::Vector4d& delta) {
  const double c = std::cos(pose(kPoseYaw));
  const double s = std::sin(pose(kPoseYaw));
  Eigen::Matrix4d J = Eigen::Matrix4d::Identity();
  J(kPoseX, kPoseYaw) = -s * delta(kPoseX) - c * delta(kPoseY);
  J(kPoseY, kPoseYaw) = c * delta(kPoseX) - s * delta(kPoseY);
  return J;
}

Eigen::Matrix4d compose_jacobian_increment(const Eigen::Vector4d& pose) {
  const double c = std::cos(pose(kPoseYaw));
  const double s = std::sin(pose(kPoseYaw));
  Eigen::Matrix4d J = Eigen::Matrix4d::Identity();
  J(kPoseX, kPoseX) = c;
  J(kPoseX, kPoseY) = -s;
  J(kPoseY, kPoseX) = s;
  J(kPoseY, kPoseY) = c;
  return J;
}

Eigen::Vector4d increment_between(const Eigen::Vector4d& from, const Eigen::Vector4d& to) {
  const double c = std::cos(from(kPoseYaw));
  const double s = std::sin(from(kPoseYaw));
  const double ex = to(kPoseX) - from(kPoseX);
  const double ey = to(kPoseY) - from(kPoseY);
  return {c * ex + s * ey, -s * ex + c * ey, to(kPoseZ) - from(kPoseZ), wrap_angle_rad(to(kPoseYaw) - from(kPoseYaw))};
}

void validate(const GaussianMotionModel2D& model) {
  const auto check = [](const char* field, double value) {
    if (!std::isfinite(value) || value < 0.0) {
      std::ostringstream msg;
      msg << field << " = " << value << ": must be finite and >= 0";
      throw std::invalid_argument(msg.str());
    }
  };
  check("gaussian_motion_model.a1", model.a1);
  check("gaussian_motion_model.a2", model.a2);
  check("gaussian_motion_model.a3", model.a3);
  check("gaussian_motion_model.a4", model.a4);
  check("gaussian_motion_model.min_std_xy_m", model.min_std_xy_m);
  check("gaussian_motion_model.min_std_phi_rad", model.min_std_phi_rad);
}

Eigen::Matrix3d gaussian_motion_cov_2d(double dx_m, double dy_m, double dphi_rad, const GaussianMotionModel2D& model) {
  const double distance_m = std::hypot(dx_m, dy_m);
  const double turn_rad = std::abs(dphi_rad);
  const double s_xy = model.min_std_xy_m + model.a1 * distance_m + model.a2 * turn_rad;
  const double s_phi = model.min_std_phi_rad + model.a3 * distance_m + model.a4 * turn_rad;
  const double c = std::cos(0.5 * dphi_rad);
  const double s = std::sin(0.5 * dphi_rad);
  Eigen::Matrix3d J;
  J << c, -s, -s * dx_m - c * dy_m,  //
      s, c, c * dx_m - s * dy_m,     //
      0.0, 0.0, 1.0;
  const Eigen::Vector3d variances(s_xy * s_xy, s_xy * s_xy, s_phi * s_phi);
  return J * variances.asDiagonal() * J.transpose();
}

OdometryIncrement odometry_2d(double dx_m, double dy_m, double dphi_rad, const GaussianMotionModel2D& model,
                              double sigma_z_m) {
  const Eigen::Matrix3d cov_xyphi = gaussian_motion_cov_2d(dx_m, dy_m, dphi_rad, model);
  OdometryIncrement u;
  u.delta = Eigen::Vector4d(dx_m, dy_m, 0.0, dphi_rad);
  constexpr int kXyPhi[3] = {kPoseX, kPoseY, kPoseYaw};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) u.cov(kXyPhi[i], kXyPhi[j]) = cov_xyphi(i, j);
  }
  u.cov(kPoseZ, kPoseZ) = sigma_z_m * sigma_z_m;
  return u;
}

OdometryIncrement odometry_3d(const Eigen::Vector4d& delta, const Eigen::Matrix<double, 6, 6>& cov_xyzypr) {
  OdometryIncrement u;
  u.delta = delta;
  u.cov = cov_xyzypr.topLeftCorner<4, 4>();  // x, y, z, yaw: the same order as PoseIndex
  return u;
}

}  // namespace losmimo::localization
