// The beacon model against independent computations: central differences for both
// Jacobians, the inverse model, angle wrapping, and a Monte Carlo check of the fix covariance.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "losmimo/localization/beacon_model.h"
#include "losmimo/localization/sensor_simulator.h"
#include "support/numdiff.h"

namespace losmimo::localization {
namespace {

using test_support::jacobian_mismatch;
using test_support::numeric_jacobian;

constexpr double kPi = 3.14159265358979323846;
constexpr double kJacobianTolerance = 1e-6;  // relative, central differences at h ~ 1e-6 |x|

Eigen::VectorXd h_of(const Eigen::VectorXd& q) { return beacon_predict(q.head<3>()); }

// Angle-aware difference of two observations (azimuth may cross the +-pi cut).
Eigen::VectorXd observation_diff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return beacon_innovation(a.head<3>(), b.head<3>());
}

std::vector<Eigen::Vector3d> test_points() {
  std::vector<Eigen::Vector3d> points = {
      {1000.0, 0.0, 0.0},      // boresight, 1 km
      {1025.0, -25.0, 25.0},   // corner of the default start cube
      {3.0, 2.0, 0.5},         // close to the array
      {1.5, 0.5, 800.0},       // near-degenerate: almost above the array (rho ~ 1.6 m)
      {-1000.0, 1e-3, -10.0},  // behind the array, azimuth next to the +-pi cut
      {0.0, 500.0, 0.0},       // azimuth exactly pi/2
  };
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1500.0, 1500.0);
  for (int i = 0; i < 20; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  return points;
}

TEST(BeaconJacobian, TypicalRandomAndNearDegeneratePoints_MatchCentralDifferences) {
  for (const Eigen::Vector3d& q : test_points()) {
    const Eigen::MatrixXd numeric = numeric_jacobian(h_of, q, 1e-6, observation_diff);
    EXPECT_LT(jacobian_mismatch(beacon_jacobian(q), numeric), kJacobianTolerance)
        << "q = " << q.transpose();
  }
}

TEST(BeaconJacobian, DeliberatelyWrongJacobian_IsCaught) {
  // Two classic slips: a sign error in d(az)/dx, and rho / r instead of rho / r^2 in d(el)/dz.
  const Eigen::Vector3d q(1025.0, -25.0, 25.0);
  const Eigen::MatrixXd numeric = numeric_jacobian(h_of, q, 1e-6, observation_diff);
  Eigen::Matrix3d sign_slip = beacon_jacobian(q);
  sign_slip(1, 0) = -sign_slip(1, 0);
  EXPECT_GT(jacobian_mismatch(sign_slip, numeric), 1e3 * kJacobianTolerance);
  Eigen::Matrix3d power_slip = beacon_jacobian(q);
  power_slip(2, 2) *= q.norm();
  EXPECT_GT(jacobian_mismatch(power_slip, numeric), 1e3 * kJacobianTolerance);
}

TEST(BeaconInverse, Jacobian_MatchesCentralDifferencesAndInvertsJzq) {
  for (const Eigen::Vector3d& q : test_points()) {
    const Eigen::Vector3d z = beacon_predict(q);
    const auto g = [](const Eigen::VectorXd& zz) -> Eigen::VectorXd {
      return beacon_to_position(zz.head<3>());
    };
    const Eigen::MatrixXd numeric = numeric_jacobian(g, z, 1e-7);
    const Eigen::Matrix3d J_q_z = beacon_to_position_jacobian(z);
    EXPECT_LT(jacobian_mismatch(J_q_z, numeric), kJacobianTolerance) << q.transpose();
    EXPECT_LT((J_q_z * beacon_jacobian(q) - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(),
              1e-9)
        << q.transpose();
  }
}

TEST(BeaconInverse, PredictThenInvert_ReturnsThePoint) {
  for (const Eigen::Vector3d& q : test_points()) {
    EXPECT_LT((beacon_to_position(beacon_predict(q)) - q).norm(), 1e-9 * (1.0 + q.norm()));
  }
}

TEST(WrapAngle, Values_LandInHalfOpenPiInterval) {
  EXPECT_DOUBLE_EQ(wrap_angle_rad(-kPi), kPi);
  EXPECT_NEAR(wrap_angle_rad(3.0 * kPi), kPi, 1e-12);
  EXPECT_NEAR(wrap_angle_rad(0.5 + 10.0 * kPi), 0.5, 1e-12);
  EXPECT_NEAR(wrap_angle_rad(-0.5 - 4.0 * kPi), -0.5, 1e-12);
}

TEST(BeaconInnovation, AzimuthAcrossPiCut_IsSmall) {
  const Eigen::Vector3d z_meas(1000.0, kPi - 1e-4, 0.0);
  const Eigen::Vector3d z_pred(1000.0, -kPi + 1e-4, 0.0);
  EXPECT_NEAR(beacon_innovation(z_meas, z_pred)(1), -2e-4, 1e-12);
}

TEST(BeaconFix, Covariance_MatchesMonteCarloAt1km) {
  // GIVEN: the default simulator at (1000, 20, 30) m; THEN the first-order fix covariance
  // matches the sample covariance of many beacon-only fixes, and is ~0.1 m per axis.
  constexpr int kSamples = 20000;
  constexpr double kRelTolerance = 0.05;  // ~5 sigma of a variance estimate from 20000 samples
  const SimulatorConfig config;
  SensorSimulator sim(config, 3);
  const Eigen::Vector3d q(1000.0, 20.0, 30.0);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  Belief fix;
  for (int i = 0; i < kSamples; ++i) {
    const auto z = sim.measure_beacon(q, i);
    ASSERT_TRUE(z.has_value());
    fix = beacon_fix(*z, config.sigma_range_m, config.sigma_angle_rad);
    const Eigen::Vector3d e = fix.mean_m - q;
    mean += e / kSamples;
    second += e * e.transpose() / kSamples;
  }
  const Eigen::Matrix3d sample_cov = second - mean * mean.transpose();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sample_cov(i, i), fix.cov_m2(i, i), kRelTolerance * fix.cov_m2(i, i));
    EXPECT_NEAR(std::sqrt(fix.cov_m2(i, i)), 0.1, 0.01);  // the documented default
  }
}

}  // namespace
}  // namespace losmimo::localization
