// The shared range/azimuth/elevation function (range_az_el.h) and the 6-D landmark model built on
// it (pose/landmark_model.h): hand values, MRPT's own spherical coordinates, central differences.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <mrpt/poses/CPose3D.h>

#include "losmimo/localization/pose/landmark_model.h"
#include "losmimo/localization/pose/odometry_model.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/range_az_el.h"
#include "support/numdiff.h"

namespace losmimo::localization {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHandTolerance = 1e-15;
constexpr double kJacobianTolerance = 1e-6;
constexpr int kRandomPoses = 50;

// Pitch within +-max_pitch_rad: compositions stay away from pitch = +-pi/2, where yaw and roll
// are not defined (gimbal lock) and the yaw-pitch-roll Jacobians blow up.
Pose6 random_pose(std::mt19937_64& rng, double position_m, double max_pitch_rad = 1.2) {
  std::uniform_real_distribution<double> pos(-position_m, position_m), ang(-3.0, 3.0),
      tilt(-max_pitch_rad, max_pitch_rad);
  Pose6 p;
  p << pos(rng), pos(rng), pos(rng), ang(rng), tilt(rng), ang(rng);
  return p;
}

Eigen::Vector3d random_point(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> pos(-10.0, 10.0);
  return {pos(rng), pos(rng), pos(rng)};
}

TEST(RangeAzEl, HandValues_DiagonalPointAndPointsAboveAndBelow) {
  // (1, 1, 0): r = sqrt 2, az = pi / 4, el = 0.
  const Eigen::Vector3d diag = range_az_el(Eigen::Vector3d(1.0, 1.0, 0.0));
  EXPECT_NEAR(diag(0), std::sqrt(2.0), kHandTolerance);
  EXPECT_NEAR(diag(1), kPi / 4.0, kHandTolerance);
  EXPECT_EQ(diag(2), 0.0);
  // (3, 0, 4): r = 5, az = 0, el = atan(4 / 3) > 0 (above the x-y plane is positive).
  const Eigen::Vector3d above = range_az_el(Eigen::Vector3d(3.0, 0.0, 4.0));
  EXPECT_NEAR(above(0), 5.0, kHandTolerance);
  EXPECT_EQ(above(1), 0.0);
  EXPECT_NEAR(above(2), std::atan2(4.0, 3.0), kHandTolerance);
  EXPECT_GT(above(2), 0.0);
  // (0, -2, -2): az = -pi / 2 (to the right), el = -pi / 4.
  const Eigen::Vector3d below = range_az_el(Eigen::Vector3d(0.0, -2.0, -2.0));
  EXPECT_NEAR(below(1), -kPi / 2.0, kHandTolerance);
  EXPECT_NEAR(below(2), -kPi / 4.0, kHandTolerance);
}

TEST(RangeAzEl, TheBsBeaconModelIsThisFunction_BitForBit) {
  // The closed loop's beacon model calls range_az_el: identical bits, not merely close values.
  std::mt19937_64 rng(7);
  for (int i = 0; i < kRandomPoses; ++i) {
    const Eigen::Vector3d q = random_point(rng);
    EXPECT_EQ(beacon_predict(q), range_az_el(q));
    EXPECT_EQ(beacon_jacobian(q), range_az_el_jacobian(q));
  }
}

TEST(RangeAzEl, Jacobian_MatchesCentralDifferences) {
  std::mt19937_64 rng(11);
  for (int i = 0; i < kRandomPoses; ++i) {
    const Eigen::Vector3d p = random_point(rng);
    const Eigen::MatrixXd numeric = test_support::numeric_jacobian(
        [](const Eigen::VectorXd& x) -> Eigen::VectorXd { return range_az_el(Eigen::Vector3d(x)); }, p);
    EXPECT_LT((range_az_el_jacobian(p) - numeric).cwiseAbs().maxCoeff(), kJacobianTolerance) << p.transpose();
  }
}

TEST(LandmarkModel, AgreesWithMrptSphericalCoordinates_YawIsAzimuthPitchIsMinusElevation) {
  // MRPT's model of CObservationBearingRange: (robot (+) sensor).sphericalCoordinates(L) gives
  // (range, yaw, pitch); ours gives (range, az, el) with az = yaw and el = -pitch.
  std::mt19937_64 rng(3);
  for (int i = 0; i < kRandomPoses; ++i) {
    const Pose6 robot = random_pose(rng, 5.0);
    const Pose6 sensor = random_pose(rng, 0.5);
    const Eigen::Vector3d L = random_point(rng);
    const mrpt::poses::CPose3D s = to_cpose3d(robot) + to_cpose3d(sensor);
    double range = 0.0, yaw = 0.0, pitch = 0.0;
    s.sphericalCoordinates(mrpt::math::TPoint3D(L.x(), L.y(), L.z()), range, yaw, pitch);
    const Eigen::Vector3d z = landmark_predict(robot, sensor, L);
    EXPECT_NEAR(z(0), range, 1e-12);
    EXPECT_NEAR(wrap_angle_rad(z(1) - yaw), 0.0, 1e-12);
    EXPECT_NEAR(z(2), -pitch, 1e-12);
    const Eigen::Vector3d stored = to_range_az_el(range, yaw, pitch);
    EXPECT_NEAR(stored(2), z(2), 1e-12);
  }
}

TEST(LandmarkModel, AboveTheSensor_ElevationPositiveAndMrptPitchNegative) {
  // A landmark 1 m ahead and 1 m up from an identity robot: el = +pi / 4, MRPT pitch = -pi / 4.
  const Eigen::Vector3d z = landmark_predict(Pose6::Zero(), Pose6::Zero(), Eigen::Vector3d(1.0, 0.0, 1.0));
  EXPECT_NEAR(z(2), kPi / 4.0, kHandTolerance);
  double range = 0.0, yaw = 0.0, pitch = 0.0;
  mrpt::poses::CPose3D().sphericalCoordinates(mrpt::math::TPoint3D(1.0, 0.0, 1.0), range, yaw, pitch);
  EXPECT_NEAR(pitch, -kPi / 4.0, 1e-12);
}

TEST(LandmarkModel, JacobianWrtThePose_MatchesCentralDifferences_WithAnOffCentreSensor) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < kRandomPoses; ++i) {
    const Pose6 robot = random_pose(rng, 5.0);
    const Pose6 sensor = random_pose(rng, 0.5);
    const Eigen::Vector3d L = random_point(rng);
    Matrix36d J;
    landmark_predict(robot, sensor, L, &J);
    const Eigen::MatrixXd numeric = test_support::numeric_jacobian(
        [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return landmark_predict(Pose6(x), sensor, L); }, robot, 1e-6,
        [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) -> Eigen::VectorXd {
          return range_az_el_innovation(Eigen::Vector3d(a), Eigen::Vector3d(b));
        });
    EXPECT_LT((J - numeric).cwiseAbs().maxCoeff(), 1e-5) << robot.transpose();
  }
}

TEST(LandmarkModel, WrongSensorPose_ChangesThePrediction) {
  // Negative control for the noncentered replay: the sensor pose must matter.
  const Pose6 sensor = (Pose6() << 0.5, 0.2, 0.1, 80.0 * kPi / 180.0, -20.0 * kPi / 180.0, 0.17).finished();
  const Eigen::Vector3d L(4.0, 2.0, 1.0);
  const Eigen::Vector3d with = landmark_predict(Pose6::Zero(), sensor, L);
  const Eigen::Vector3d without = landmark_predict(Pose6::Zero(), Pose6::Zero(), L);
  EXPECT_GT(std::abs(wrap_angle_rad(with(1) - without(1))), 0.5);
}

TEST(PoseComposition, MatchesCPose3DAndItsJacobiansMatchCentralDifferences) {
  std::mt19937_64 rng(9);
  for (int i = 0; i < kRandomPoses; ++i) {
    const Pose6 x = random_pose(rng, 5.0, 0.6);
    const Pose6 u = random_pose(rng, 1.0, 0.6);
    Matrix6d J_x, J_u;
    const Pose6 c = compose_pose6(x, u, &J_x, &J_u);
    const mrpt::poses::CPose3D ref = to_cpose3d(x) + to_cpose3d(u);
    const Eigen::Vector3d t = c.head<3>();
    EXPECT_LT((t - Eigen::Vector3d(ref.x(), ref.y(), ref.z())).norm(), 1e-12);
    EXPECT_LT((to_cpose3d(c).getRotationMatrix().asEigen() - ref.getRotationMatrix().asEigen()).cwiseAbs().maxCoeff(),
              1e-12);
    const auto diff = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) -> Eigen::VectorXd {
      return pose6_deviation(Pose6(a), Pose6(b));
    };
    const Eigen::MatrixXd nx = test_support::numeric_jacobian(
        [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return compose_pose6(Pose6(v), u); }, x, 1e-6, diff);
    const Eigen::MatrixXd nu = test_support::numeric_jacobian(
        [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return compose_pose6(x, Pose6(v)); }, u, 1e-6, diff);
    EXPECT_LT((J_x - nx).cwiseAbs().maxCoeff(), 1e-5) << x.transpose();
    EXPECT_LT((J_u - nu).cwiseAbs().maxCoeff(), 1e-5) << u.transpose();
  }
}

TEST(PoseComposition, PlanarJacobians_EqualTheHandDerivedFourDofOnes) {
  // Independent of differencing: for planar poses (z, pitch, roll = 0 in x and u) the x, y, z, yaw
  // block of the Jacobians is odometry_model.h's analytic J_x'_x and J_x'_u.
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> pos(-5.0, 5.0), ang(-3.1, 3.1);
  const int idx[4] = {kP6X, kP6Y, kP6Z, kP6Yaw};
  for (int i = 0; i < kRandomPoses; ++i) {
    Pose6 x = Pose6::Zero(), u = Pose6::Zero();
    x << pos(rng), pos(rng), 0.0, ang(rng), 0.0, 0.0;
    u << pos(rng), pos(rng), 0.0, ang(rng), 0.0, 0.0;
    Matrix6d J_x, J_u;
    compose_pose6(x, u, &J_x, &J_u);
    const Eigen::Vector4d x4(x(0), x(1), x(2), x(3)), u4(u(0), u(1), u(2), u(3));
    const Eigen::Matrix4d A_x = compose_jacobian_pose(x4, u4), A_u = compose_jacobian_increment(x4);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        EXPECT_NEAR(J_x(idx[r], idx[c]), A_x(r, c), 1e-8);
        EXPECT_NEAR(J_u(idx[r], idx[c]), A_u(r, c), 1e-8);
      }
  }
}

}  // namespace
}  // namespace losmimo::localization
