#include "losmimo/localization/pose/landmark_model.h"

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>

#include "losmimo/localization/range_az_el.h"

namespace losmimo::localization {

namespace {

mrpt::poses::CPose3D to_mrpt(const Pose6& p) { return {p(0), p(1), p(2), p(3), p(4), p(5)}; }

Pose6 from_mrpt(const mrpt::poses::CPose3D& p) {
  Pose6 out;
  out << p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll();
  return out;
}

}  // namespace

Pose6 compose_pose6(const Pose6& x, const Pose6& u, Matrix6d* J_x, Matrix6d* J_u) {
  const Pose6 out = from_mrpt(to_mrpt(x) + to_mrpt(u));
  // Central differences of CPose3D's own composition (header: why not jacobiansPoseComposition).
  const auto differentiate = [&](bool wrt_x, Matrix6d& J) {
    constexpr double kStep = 1e-6;
    for (int i = 0; i < 6; ++i) {
      Pose6 plus_x = x, minus_x = x, plus_u = u, minus_u = u;
      (wrt_x ? plus_x : plus_u)(i) += kStep;
      (wrt_x ? minus_x : minus_u)(i) -= kStep;
      const Pose6 plus = from_mrpt(to_mrpt(plus_x) + to_mrpt(plus_u));
      const Pose6 minus = from_mrpt(to_mrpt(minus_x) + to_mrpt(minus_u));
      J.col(i) = pose6_deviation(plus, minus) / (2.0 * kStep);
    }
  };
  if (J_x) differentiate(true, *J_x);
  if (J_u) differentiate(false, *J_u);
  return out;
}

Pose6 pose6_deviation(const Pose6& a, const Pose6& b) {
  Pose6 d = a - b;
  for (int i = kP6Yaw; i <= kP6Roll; ++i) d(i) = wrap_angle_rad(d(i));
  return d;
}

namespace {

Eigen::Vector3d in_sensor(const mrpt::poses::CPose3D& x, const mrpt::poses::CPose3D& s,
                          const Eigen::Vector3d& landmark_m, Matrix36d* J_p_x) {
  double rx = 0.0, ry = 0.0, rz = 0.0, px = 0.0, py = 0.0, pz = 0.0;
  if (!J_p_x) {
    x.inverseComposePoint(landmark_m.x(), landmark_m.y(), landmark_m.z(), rx, ry, rz);
    s.inverseComposePoint(rx, ry, rz, px, py, pz);
    return {px, py, pz};
  }
  mrpt::math::CMatrixDouble33 unused, J_p_pr;
  mrpt::math::CMatrixDouble36 J_pr_x;
  x.inverseComposePoint(landmark_m.x(), landmark_m.y(), landmark_m.z(), rx, ry, rz, unused, J_pr_x);
  s.inverseComposePoint(rx, ry, rz, px, py, pz, J_p_pr);
  *J_p_x = J_p_pr.asEigen() * J_pr_x.asEigen();
  return {px, py, pz};
}

}  // namespace

mrpt::poses::CPose3D to_cpose3d(const Pose6& pose) { return to_mrpt(pose); }

Eigen::Vector3d landmark_in_sensor(const Pose6& robot, const Pose6& sensor_on_robot, const Eigen::Vector3d& landmark_m,
                                   Matrix36d* J_p_x) {
  return in_sensor(to_mrpt(robot), to_mrpt(sensor_on_robot), landmark_m, J_p_x);
}

Eigen::Vector3d landmark_predict(const mrpt::poses::CPose3D& robot, const mrpt::poses::CPose3D& sensor_on_robot,
                                 const Eigen::Vector3d& landmark_m, Matrix36d* J_z_x) {
  Matrix36d J_p_x;
  const Eigen::Vector3d p = in_sensor(robot, sensor_on_robot, landmark_m, J_z_x ? &J_p_x : nullptr);
  if (J_z_x) *J_z_x = range_az_el_jacobian(p) * J_p_x;
  return range_az_el(p);
}

Eigen::Vector3d landmark_predict(const Pose6& robot, const Pose6& sensor_on_robot, const Eigen::Vector3d& landmark_m,
                                 Matrix36d* J_z_x) {
  return landmark_predict(to_mrpt(robot), to_mrpt(sensor_on_robot), landmark_m, J_z_x);
}

Eigen::Vector3d to_range_az_el(double range_m, double yaw_rad, double pitch_rad) {
  return {range_m, yaw_rad, -pitch_rad};
}

}  // namespace losmimo::localization
