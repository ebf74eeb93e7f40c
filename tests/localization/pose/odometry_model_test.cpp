// The odometry model (odometry_model.h) against independent computations: mrpt::poses' CPose3D /
// CPose2D composition, central differences for both Jacobians, and covariances that MRPT 2.5.8's
// CActionRobotMovement2D::computeFromOdometry (mmGaussian) printed.

#include <gtest/gtest.h>

#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/pose/odometry_model.h"
#include "support/numdiff.h"

namespace losmimo::localization {
namespace {

using test_support::jacobian_mismatch;
using test_support::numeric_jacobian;

constexpr double kPi = 3.14159265358979323846;
constexpr double kExact = 1e-12;
constexpr double kJacobianTolerance = 1e-6;
constexpr int kRandomPoints = 200;

mrpt::poses::CPose3D to_mrpt(const Eigen::Vector4d& x) {
  return mrpt::poses::CPose3D(x(kPoseX), x(kPoseY), x(kPoseZ), x(kPoseYaw), 0.0, 0.0);
}

Eigen::Vector4d random_pose(std::mt19937_64& rng, double scale_m) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return {scale_m * u(rng), scale_m * u(rng), scale_m * u(rng), kPi * u(rng)};
}

// a - b with the heading difference wrapped.
Eigen::VectorXd pose_diff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  Eigen::VectorXd d = a - b;
  d(kPoseYaw) = wrap_angle_rad(d(kPoseYaw));
  return d;
}

TEST(OdometryModel, Compose_MatchesMrptCPose3DComposition) {
  std::mt19937_64 rng(11);
  for (int k = 0; k < kRandomPoints; ++k) {
    const Eigen::Vector4d x = random_pose(rng, 50.0);
    const Eigen::Vector4d u = random_pose(rng, 2.0);
    const mrpt::poses::CPose3D expected = to_mrpt(x) + to_mrpt(u);
    const Eigen::Vector4d got = compose(x, u);
    EXPECT_NEAR(got(kPoseX), expected.x(), kExact * 100.0);
    EXPECT_NEAR(got(kPoseY), expected.y(), kExact * 100.0);
    EXPECT_NEAR(got(kPoseZ), expected.z(), kExact * 100.0);
    EXPECT_NEAR(wrap_angle_rad(got(kPoseYaw) - expected.yaw()), 0.0, kExact);
    EXPECT_GT(got(kPoseYaw), -kPi);
    EXPECT_LE(got(kPoseYaw), kPi);
  }
}

TEST(OdometryModel, Compose2D_MatchesMrptCPose2D) {
  const mrpt::poses::CPose2D a(1.5, -2.0, 2.9);
  const mrpt::poses::CPose2D d(0.3, 0.1, 0.4);  // crosses +-pi
  const mrpt::poses::CPose2D expected = a + d;
  const Eigen::Vector4d got = compose({1.5, -2.0, 0.0, 2.9}, {0.3, 0.1, 0.0, 0.4});
  EXPECT_NEAR(got(kPoseX), expected.x(), kExact);
  EXPECT_NEAR(got(kPoseY), expected.y(), kExact);
  EXPECT_NEAR(got(kPoseYaw), expected.phi(), kExact);
}

TEST(OdometryModel, IncrementBetween_MatchesMrptInverseCompositionAndRoundTrips) {
  std::mt19937_64 rng(12);
  for (int k = 0; k < kRandomPoints; ++k) {
    const Eigen::Vector4d from = random_pose(rng, 50.0);
    const Eigen::Vector4d to = random_pose(rng, 50.0);
    const mrpt::poses::CPose3D expected = to_mrpt(to) - to_mrpt(from);  // (-from) (+) to
    const Eigen::Vector4d u = increment_between(from, to);
    EXPECT_NEAR(u(kPoseX), expected.x(), 1e-10);
    EXPECT_NEAR(u(kPoseY), expected.y(), 1e-10);
    EXPECT_NEAR(u(kPoseZ), expected.z(), 1e-10);
    EXPECT_NEAR(wrap_angle_rad(u(kPoseYaw) - expected.yaw()), 0.0, 1e-12);
    EXPECT_LT(pose_diff(compose(from, u), to).norm(), 1e-10);
  }
}

TEST(OdometryModel, Jacobians_MatchCentralDifferences) {
  std::mt19937_64 rng(13);
  for (int k = 0; k < kRandomPoints; ++k) {
    const Eigen::Vector4d x = random_pose(rng, 50.0);
    const Eigen::Vector4d u = random_pose(rng, 2.0);
    const Eigen::MatrixXd J_x =
        numeric_jacobian([&](const Eigen::VectorXd& v) { return Eigen::VectorXd(compose(v, u)); }, x, 1e-6, pose_diff);
    const Eigen::MatrixXd J_u =
        numeric_jacobian([&](const Eigen::VectorXd& v) { return Eigen::VectorXd(compose(x, v)); }, u, 1e-6, pose_diff);
    EXPECT_LT(jacobian_mismatch(compose_jacobian_pose(x, u), J_x), kJacobianTolerance);
    EXPECT_LT(jacobian_mismatch(compose_jacobian_increment(x), J_u), kJacobianTolerance);
  }
}

TEST(OdometryModel, WrongTransitionJacobian_IsCaught) {
  // A classic slip: the heading column built from the world-frame increment instead of the
  // rotated one. The same check must reject it.
  const Eigen::Vector4d x(3.0, -1.0, 0.5, 0.8);
  const Eigen::Vector4d u(0.4, 0.2, 0.0, 0.1);
  Eigen::Matrix4d wrong = Eigen::Matrix4d::Identity();
  wrong(kPoseX, kPoseYaw) = -u(kPoseY);
  wrong(kPoseY, kPoseYaw) = u(kPoseX);
  const Eigen::MatrixXd J_x =
      numeric_jacobian([&](const Eigen::VectorXd& v) { return Eigen::VectorXd(compose(v, u)); }, x, 1e-6, pose_diff);
  EXPECT_GT(jacobian_mismatch(wrong, J_x), 100.0 * kJacobianTolerance);
}

// MRPT 2.5.8, CActionRobotMovement2D::computeFromOdometry(CPose2D(dx, dy, dphi), mmGaussian with
// {a1, a2, a3, a4, minStdXY, minStdPHI}), poseChange->getCovarianceAndMean(), printed with %.17g.
struct MrptCase {
  double dx, dy, dphi;
  GaussianMotionModel2D model;
  double cov[3][3];
};

const MrptCase kMrptCases[] = {
    {0.3,
     0.05,
     0.2,
     {0.01, 0.0573, 0.0175, 0.05, 0.02, 0.0035},
     {{0.0011925957623533019, -8.2876740642989885e-06, -2.8236468804747296e-05},
      {-8.2876740642990156e-06, 0.001220866069607556, 0.00010398556849232738},
      {-2.8236468804747296e-05, 0.00010398556849232738, 0.00035428338977829568}}},
    {-0.12,
     0.4,
     -1.1,
     {0.01, 0.0572957795, 0.0174532925, 0.05, 0.01, 0.00349065850},
     {{0.0066653562490132179, -0.00018652198384517873, -0.0017469193521603955},
      {-0.0001865219838451787, 0.0060093965472481576, 0.00046199423428972528},
      {-0.0017469193521603955, 0.00046199423428972528, 0.0043269251796997019}}},
    {0.2,
     0.0,
     0.0,
     {0.0, 0.0, 0.0, 0.0, 0.001, 3.4906585e-5},
     {{9.9999999999999995e-07, 0.0, 0.0},
      {0.0, 1.0000487387870545e-06, 2.4369393527244503e-10},
      {0.0, 2.4369393527244503e-10, 1.2184696763622252e-09}}},
};

TEST(OdometryModel, GaussianCov_MatchesMrptComputeFromOdometry) {
  for (const MrptCase& c : kMrptCases) {
    const Eigen::Matrix3d cov = gaussian_motion_cov_2d(c.dx, c.dy, c.dphi, c.model);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(cov(i, j), c.cov[i][j], 1e-14 + 1e-12 * std::abs(c.cov[i][j])) << i << "," << j;
      }
    }
  }
}

TEST(OdometryModel, Odometry2dAnd3d_FillThePoseOrder) {
  const GaussianMotionModel2D model;
  const OdometryIncrement u = odometry_2d(0.3, 0.05, 0.2, model, 0.02);
  const Eigen::Matrix3d cov = gaussian_motion_cov_2d(0.3, 0.05, 0.2, model);
  EXPECT_EQ(u.delta, Eigen::Vector4d(0.3, 0.05, 0.0, 0.2));
  EXPECT_EQ(u.cov(kPoseX, kPoseYaw), cov(0, 2));
  EXPECT_EQ(u.cov(kPoseYaw, kPoseYaw), cov(2, 2));
  EXPECT_EQ(u.cov(kPoseZ, kPoseZ), 0.02 * 0.02);
  EXPECT_EQ(u.cov(kPoseZ, kPoseX), 0.0);

  Eigen::Matrix<double, 6, 6> cov6 = Eigen::Matrix<double, 6, 6>::Identity();
  cov6(0, 3) = cov6(3, 0) = 0.5;  // x-yaw
  cov6(4, 4) = 7.0;               // pitch: dropped
  const OdometryIncrement u3 = odometry_3d({1.0, 2.0, 3.0, 0.1}, cov6);
  EXPECT_EQ(u3.cov(kPoseX, kPoseYaw), 0.5);
  EXPECT_EQ(u3.cov(kPoseYaw, kPoseYaw), 1.0);
}

TEST(OdometryModel, NegativeModelParameter_NamesTheField) {
  GaussianMotionModel2D model;
  model.a3 = -1.0;
  try {
    validate(model);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("a3 = -1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace losmimo::localization
