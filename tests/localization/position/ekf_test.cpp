// The MRPT-based EKF against an independent textbook EKF written here in plain Eigen.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <limits>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/ekf.h"
#include "losmimo/localization/position/robustness.h"

namespace losmimo::localization {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTolerance = 1e-9;

Belief initial_belief(const Eigen::Vector3d& mean_m) {
  Belief b;
  b.mean_m = mean_m;
  b.cov_m2 << 0.04, 0.01, 0.0, 0.01, 0.09, 0.005, 0.0, 0.005, 0.0225;
  return b;
}

// Reference: x- = x + d, P- = P + s^2 I; K = P- H^T S^-1; x+ = x- + K y;
// P+ = (I - K H) P- (I - K H)^T + K R K^T. Explicit inverse on purpose (independent code path).
Belief reference_update(const FilterConfig& config, const Belief& prior, const Eigen::Vector3d& d,
                        const BeaconMeasurement& z) {
  const double s = config.noise.dr_sigma_floor_m + config.noise.dr_sigma_fraction * d.norm();
  const Eigen::Vector3d x = prior.mean_m + d;
  const Eigen::Matrix3d P = prior.cov_m2 + s * s * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d H = beacon_jacobian(x);
  const Eigen::Matrix3d R = Eigen::Vector3d(config.noise.sigma_range_m * config.noise.sigma_range_m,
                                            config.noise.sigma_angle_rad * config.noise.sigma_angle_rad,
                                            config.noise.sigma_angle_rad * config.noise.sigma_angle_rad)
                                .asDiagonal();
  const Eigen::Matrix3d S = H * P * H.transpose() + R;
  const Eigen::Matrix3d K = P * H.transpose() * S.inverse();
  Eigen::Vector3d y = to_vector(z) - beacon_predict(x);
  y(1) = std::atan2(std::sin(y(1)), std::cos(y(1)));
  const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() - K * H;
  Belief post;
  post.mean_m = x + K * y;
  post.cov_m2 = A * P * A.transpose() + K * R * K.transpose();
  return post;
}

TEST(Ekf, OneEpoch_MatchesIndependentJosephFormEkf) {
  const FilterConfig config;
  const Belief prior = initial_belief({1000.0, 12.0, -30.0});
  const Eigen::Vector3d d(0.8, -0.4, 0.2);
  BeaconMeasurement z = to_measurement(beacon_predict(prior.mean_m + d + Eigen::Vector3d(0.1, -0.2, 0.05)));
  EkfPositionFilter ekf(config, prior);
  ekf.step(d, z);
  const Belief expected = reference_update(config, prior, d, z);
  const Belief got = ekf.belief();
  EXPECT_LT((got.mean_m - expected.mean_m).norm(), kTolerance * 1000.0);
  EXPECT_LT((got.cov_m2 - expected.cov_m2).cwiseAbs().maxCoeff(), kTolerance);
  EXPECT_EQ(ekf.counters().beacons_fused, 1);
  EXPECT_EQ(got.epochs_since_beacon, 0);
}

TEST(Ekf, PredictionOnlyEpoch_MovesMeanAndAddsProcessNoise) {
  const FilterConfig config;
  const Belief prior = initial_belief({1000.0, 0.0, 0.0});
  const Eigen::Vector3d d(2.0, 0.0, 0.0);
  EkfPositionFilter ekf(config, prior);
  ekf.step(d, std::nullopt);
  const double s = displacement_sigma_m(config, d.norm());
  EXPECT_LT((ekf.belief().mean_m - (prior.mean_m + d)).norm(), 1e-12);
  EXPECT_LT((ekf.belief().cov_m2 - (prior.cov_m2 + s * s * Eigen::Matrix3d::Identity())).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(ekf.belief().epochs_since_beacon, 1);
  EXPECT_EQ(ekf.counters().beacons_received, 0);
}

TEST(Ekf, AzimuthAcrossPiCut_IsWrappedNotGated) {
  // GIVEN: a UAV behind the array (azimuth ~ pi) and a beacon whose azimuth is on the other side
  // of the cut. THEN: the innovation is small, the beacon is fused and the mean barely moves.
  const FilterConfig config;
  Belief prior = initial_belief({-1000.0, 0.02, 5.0});  // azimuth just below pi
  EkfPositionFilter ekf(config, prior);
  BeaconMeasurement z = to_measurement(beacon_predict({-1000.0, -0.02, 5.0}));  // just above -pi
  ASSERT_LT(z.azimuth_rad, -kPi + 1e-4);
  ekf.step(Eigen::Vector3d::Zero(), z);
  EXPECT_EQ(ekf.counters().beacons_fused, 1);
  EXPECT_EQ(ekf.counters().rejected_gate, 0);
  const Belief expected = reference_update(config, prior, Eigen::Vector3d::Zero(), z);
  EXPECT_LT((ekf.belief().mean_m - expected.mean_m).norm(), 1e-6);
  EXPECT_LT((ekf.belief().mean_m - prior.mean_m).norm(), 0.1);
}

TEST(Ekf, NonFiniteDisplacement_PredictsInPlaceWithMissingSigma) {
  const FilterConfig config;
  const Belief prior = initial_belief({1000.0, 0.0, 0.0});
  EkfPositionFilter ekf(config, prior);
  ekf.step(Eigen::Vector3d(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0), std::nullopt);
  const double s = config.missing_displacement_sigma_m;
  EXPECT_EQ(ekf.belief().mean_m, prior.mean_m);
  EXPECT_LT((ekf.belief().cov_m2 - (prior.cov_m2 + s * s * Eigen::Matrix3d::Identity())).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(ekf.counters().rejected_non_finite_displacement, 1);
}

TEST(Ekf, CovarianceAfterManyUpdates_StaysSymmetricPositiveDefinite) {
  const FilterConfig config;
  EkfPositionFilter ekf(config, initial_belief({1000.0, 0.0, 0.0}));
  for (int k = 0; k < 500; ++k) {
    ekf.step(Eigen::Vector3d::Zero(), to_measurement(beacon_predict({1000.0, 0.0, 0.0})));
  }
  const Eigen::Matrix3d P = ekf.belief().cov_m2;
  EXPECT_EQ(P, P.transpose());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(P).eigenvalues().minCoeff(), 0.0);
}

}  // namespace
}  // namespace losmimo::localization
