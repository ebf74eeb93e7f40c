// The pose filters (pose/filter.h) on single epochs: the MRPT-based EKF against an independent
// sequential EKF in plain Eigen, the particle filter against the EKF with many particles, and the
// rules every reading goes through (counted by reason, never fused when rejected), the reset and
// non-finite odometry, for both filters.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <Eigen/LU>
#include <vector>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/ekf.h"
#include "losmimo/localization/pose/particle_filter.h"

namespace losmimo::localization {
namespace {

const Eigen::Vector3d kSensor(0.3, 0.1, 0.8);

BeaconMap four_beacons() {
  BeaconMap map;
  map.add(10, {0.0, 0.0, 2.5});
  map.add(11, {12.0, 0.0, 0.5});
  map.add(12, {12.0, 9.0, 3.0});
  map.add(13, {0.0, 9.0, 1.0});
  return map;
}

PoseBelief prior_at(const Eigen::Vector4d& mean) {
  PoseBelief b;
  b.mean = mean;
  b.cov = Eigen::Vector4d(0.04, 0.04, 0.01, 0.01).asDiagonal();
  b.cov(kPoseX, kPoseY) = b.cov(kPoseY, kPoseX) = 0.01;
  return b;
}

BeaconRangeScan exact_scan(const BeaconMap& map, const Eigen::Vector4d& pose) {
  BeaconRangeScan scan;
  scan.std_error_m = 0.05;
  for (const auto& [id, b] : map.beacons()) scan.ranges.push_back({id, range_predict(pose, kSensor, b), kSensor});
  return scan;
}

PoseFilterConfig config_with_sigma(double sigma_m) {
  PoseFilterConfig c;
  c.filter.noise.sigma_range_m = sigma_m;
  return c;
}

// Independent reference: prediction, then the iterated EKF (Gauss-Newton) over all readings at
// once (pose/ekf.h), with the range model and its Jacobian written out here, explicit inverses.
PoseBelief reference_epoch(const PoseFilterConfig& config, const PoseBelief& prior, const OdometryIncrement& u,
                           const BeaconMap& map, const BeaconRangeScan& scan) {
  const double c = std::cos(prior.mean(kPoseYaw));
  const double s = std::sin(prior.mean(kPoseYaw));
  Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
  F(0, 3) = -s * u.delta(0) - c * u.delta(1);
  F(1, 3) = c * u.delta(0) - s * u.delta(1);
  Eigen::Matrix4d G = Eigen::Matrix4d::Identity();
  G(0, 0) = c;
  G(0, 1) = -s;
  G(1, 0) = s;
  G(1, 1) = c;
  Eigen::Matrix4d Su = u.cov;
  const double fm = config.filter.min_sigma_displacement_m;
  Su.diagonal() += Eigen::Vector4d(fm * fm, fm * fm, fm * fm, config.min_sigma_yaw_rad * config.min_sigma_yaw_rad);
  Eigen::Vector4d x0 = prior.mean;
  x0(0) += c * u.delta(0) - s * u.delta(1);
  x0(1) += s * u.delta(0) + c * u.delta(1);
  x0(2) += u.delta(2);
  x0(3) += u.delta(3);
  const Eigen::Matrix4d P0 = F * prior.cov * F.transpose() + G * Su * G.transpose();
  PoseBelief b;
  b.mean = x0;
  b.cov = P0;
  const int n = static_cast<int>(scan.ranges.size());
  if (n == 0) return b;
  const double sigma = config.filter.noise.sigma_range_m;
  const Eigen::MatrixXd R = sigma * sigma * Eigen::MatrixXd::Identity(n, n);
  Eigen::Vector4d lin = x0;
  Eigen::MatrixXd H(n, 4);
  Eigen::MatrixXd K;
  for (int it = 0; it < 50; ++it) {
    Eigen::VectorXd y(n);
    const double cy = std::cos(lin(3));
    const double sy = std::sin(lin(3));
    const Eigen::Vector3d sensor(lin(0) + cy * kSensor.x() - sy * kSensor.y(),
                                 lin(1) + sy * kSensor.x() + cy * kSensor.y(), lin(2) + kSensor.z());
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector3d d = sensor - *map.find(scan.ranges[j].beacon_id);
      const Eigen::Vector3d e = d.normalized();
      H.row(j) << e.x(), e.y(), e.z(),
          e.x() * (-sy * kSensor.x() - cy * kSensor.y()) + e.y() * (cy * kSensor.x() - sy * kSensor.y());
      y(j) = scan.ranges[j].range_m - d.norm();
    }
    y -= H * (x0 - lin);
    K = P0 * H.transpose() * (H * P0 * H.transpose() + R).inverse();
    const Eigen::Vector4d next = x0 + K * y;
    const double step = (next - lin).norm();
    lin = next;
    if (step < 1e-12) break;
  }
  b.mean = lin;
  const Eigen::Matrix4d A = Eigen::Matrix4d::Identity() - K * H;
  b.cov = A * P0 * A.transpose() + K * R * K.transpose();
  return b;
}

TEST(PoseEkf, OneEpoch_MatchesIndependentIteratedEkf) {
  const BeaconMap map = four_beacons();
  const PoseFilterConfig config = config_with_sigma(0.05);
  const PoseBelief prior = prior_at({4.0, 3.0, 0.0, 0.6});
  const OdometryIncrement u = odometry_2d(0.4, 0.05, 0.1, GaussianMotionModel2D{});
  const Eigen::Vector4d truth = compose(prior.mean, u.delta) + Eigen::Vector4d(0.1, -0.15, 0.02, 0.03);
  const BeaconRangeScan scan = exact_scan(map, truth);
  EkfPoseFilter ekf(config, map, initial_pose(prior));
  ekf.step(u, {scan});
  const PoseBelief expected = reference_epoch(config, prior, u, map, scan);
  EXPECT_LT((ekf.belief().mean - expected.mean).norm(), 1e-9);
  EXPECT_LT((ekf.belief().cov - expected.cov).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_EQ(ekf.counters().ranges_received, 4);
  EXPECT_EQ(ekf.counters().ranges_fused, 4);
  EXPECT_EQ(ekf.belief().epochs_since_beacon, 0);
}

TEST(PoseEkf, PredictionOnly_IsTheCompositionWithPropagatedNoise) {
  const BeaconMap map = four_beacons();
  const PoseFilterConfig config;
  const PoseBelief prior = prior_at({4.0, 3.0, 0.0, 2.5});
  const OdometryIncrement u = odometry_2d(0.3, 0.0, 0.8, GaussianMotionModel2D{});  // crosses +-pi
  EkfPoseFilter ekf(config, map, initial_pose(prior));
  ekf.step(u, {});
  const PoseBelief expected = reference_epoch(config, prior, u, map, BeaconRangeScan{});
  EXPECT_LT((ekf.belief().mean.head<3>() - expected.mean.head<3>()).norm(), 1e-12);
  EXPECT_NEAR(ekf.belief().mean(kPoseYaw), wrap_angle_rad(expected.mean(kPoseYaw)), 1e-12);
  EXPECT_LT((ekf.belief().cov - expected.cov).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_EQ(ekf.belief().epochs_since_beacon, config.filter.degraded_after_epochs + 1);
}

TEST(PoseParticleFilter, OneEpochWithManyParticles_MatchesEkfPosterior) {
  // GIVEN: near-linear ranges (0.1 m prior spread, beacons >= 3 m away) and 50000 particles.
  constexpr int kParticles = 50000;
  const BeaconMap map = four_beacons();
  PoseFilterConfig config = config_with_sigma(0.05);
  config.filter.num_particles = kParticles;
  const PoseBelief prior = prior_at({4.0, 3.0, 0.0, 0.6});
  const OdometryIncrement u = odometry_2d(0.4, 0.05, 0.1, GaussianMotionModel2D{});
  const BeaconRangeScan scan = exact_scan(map, compose(prior.mean, u.delta) + Eigen::Vector4d(0.1, -0.15, 0.0, 0.03));
  EkfPoseFilter ekf(config, map, initial_pose(prior));
  ParticlePoseFilter pf(config, map, initial_pose(prior), 5);
  ekf.step(u, {scan});
  pf.step(u, {scan});
  const PoseBelief e = ekf.belief();
  const PoseBelief p = pf.belief();
  for (int i = 0; i < kPoseSize; ++i) {
    const double sigma = std::sqrt(e.cov(i, i));
    EXPECT_NEAR(p.mean(i), e.mean(i), 0.05 * sigma) << "axis " << i;
    EXPECT_NEAR(p.cov(i, i), e.cov(i, i), 0.08 * e.cov(i, i)) << "axis " << i;
  }
}

class PoseRules : public ::testing::TestWithParam<FilterKind> {};

TEST_P(PoseRules, EveryRejectedReading_CountedByReasonAndNeverFused) {
  // GIVEN: one scan with one reading of each kind.
  const BeaconMap map = four_beacons();
  const PoseBelief prior = prior_at({4.0, 3.0, 0.0, 0.6});
  const PoseFilterConfig config = config_with_sigma(0.05);
  BeaconRangeScan scan = exact_scan(map, prior.mean);  // 4 good readings
  scan.max_sensor_distance_m = 20.0;
  const Eigen::Vector3d s = kSensor;
  scan.ranges.push_back({77, 5.0, s});                                       // unknown beacon
  scan.ranges.push_back({kInvalidBeaconId, 5.0, s});                         // invalid ID
  scan.ranges.push_back({10, std::numeric_limits<double>::quiet_NaN(), s});  // non-finite
  scan.ranges.push_back({10, 0.0, s});                                       // dropout
  scan.ranges.push_back({10, 25.0, s});                                      // beyond maxSensorDistance
  scan.ranges.push_back({11, scan.ranges[1].range_m + 3.0, s});              // gross error: gated
  auto filter = make_pose_filter(GetParam(), config, map, initial_pose(prior), 3);
  filter->step(OdometryIncrement{}, {scan});
  const FilterCounters& c = filter->counters();
  EXPECT_EQ(c.ranges_received, 10);
  EXPECT_EQ(c.ranges_fused, 4);
  EXPECT_EQ(c.rejected_unknown_beacon, 2);
  EXPECT_EQ(c.rejected_non_finite_range, 2);
  EXPECT_EQ(c.rejected_outside_sensor_limits, 1);
  EXPECT_EQ(c.rejected_range_gate, 1);
  EXPECT_EQ(c.ranges_fused + c.rejected_ranges(), c.ranges_received);
  // THEN: the belief is what the four good readings alone give.
  auto clean = make_pose_filter(GetParam(), config, map, initial_pose(prior), 3);
  clean->step(OdometryIncrement{}, {exact_scan(map, prior.mean)});
  EXPECT_LT((filter->belief().mean - clean->belief().mean).norm(), 1e-12);
}

TEST_P(PoseRules, ImplausibleRange_CountedApartFromSensorLimits) {
  const BeaconMap map = four_beacons();
  PoseFilterConfig config;
  config.filter.max_beacon_range_m = 8.0;
  BeaconRangeScan scan;
  scan.ranges.push_back({12, 9.0, kSensor});  // within maxSensorDistance (100), above 8 m
  auto filter = make_pose_filter(GetParam(), config, map, initial_pose(prior_at({4.0, 3.0, 0.0, 0.0})), 3);
  filter->step(OdometryIncrement{}, {scan});
  EXPECT_EQ(filter->counters().rejected_implausible_range, 1);
  EXPECT_EQ(filter->counters().ranges_fused, 0);
}

TEST_P(PoseRules, LostTrack_ResetFromARangeFixAfterTheGatedEpochs) {
  // GIVEN: a confident belief 4 m off the truth; exact ranges gated every epoch.
  const BeaconMap map = four_beacons();
  PoseFilterConfig config = config_with_sigma(0.05);
  config.filter.reset_after_rejections = 3;
  const Eigen::Vector4d truth(6.0, 5.0, 0.0, 0.3);
  const PoseBelief wrong = prior_at(truth + Eigen::Vector4d(4.0, 0.0, 0.0, 0.0));
  auto filter = make_pose_filter(GetParam(), config, map, initial_pose(wrong), 4);
  for (int k = 0; k < 3; ++k) filter->step(OdometryIncrement{}, {exact_scan(map, truth)});
  EXPECT_EQ(filter->counters().resets, 0);
  EXPECT_EQ(filter->counters().rejected_range_gate, 12);
  EXPECT_EQ(filter->belief().epochs_since_beacon, config.filter.degraded_after_epochs + 3);  // from the prior
  // THEN: the fourth gated epoch resets the position to the fix (the heading kept).
  filter->step(OdometryIncrement{}, {exact_scan(map, truth)});
  EXPECT_EQ(filter->counters().resets, 1);
  EXPECT_EQ(filter->counters().ranges_fused, 4);
  EXPECT_LT((filter->belief().mean.head<2>() - truth.head<2>()).norm(), 0.1);
  EXPECT_EQ(filter->belief().epochs_since_beacon, 0);
}

TEST_P(PoseRules, NonFiniteOdometry_PredictsInPlaceWithTheMissingSigmas) {
  const BeaconMap map = four_beacons();
  PoseFilterConfig config;
  config.filter.num_particles = 20000;  // sample variances within ~1%
  const PoseBelief prior = prior_at({4.0, 3.0, 0.0, 0.6});
  auto filter = make_pose_filter(GetParam(), config, map, initial_pose(prior), 6);
  OdometryIncrement bad = odometry_2d(0.4, 0.0, 0.1, GaussianMotionModel2D{});
  bad.delta(kPoseX) = std::numeric_limits<double>::infinity();
  filter->step(bad, {});
  EXPECT_EQ(filter->counters().rejected_non_finite_displacement, 1);
  const PoseBelief b = filter->belief();
  // The missing reading's sigmas plus the odometry floors (robustness.cpp).
  const double s2 =
      std::pow(config.filter.missing_displacement_sigma_m, 2) + std::pow(config.filter.min_sigma_displacement_m, 2);
  const double yaw2 = std::pow(config.missing_yaw_sigma_rad, 2) + std::pow(config.min_sigma_yaw_rad, 2);
  // The EKF's prediction in place is exact (identity Jacobians, those variances added); the
  // particle filter's moments carry the sampling error of 20000 particles.
  const bool exact = GetParam() == FilterKind::kEkf;
  const double mean_tol_m = exact ? 1e-12 : 0.2, cov_rel = exact ? 1e-12 : 0.1;
  EXPECT_LT((b.mean.head<2>() - prior.mean.head<2>()).norm(), mean_tol_m);  // in place
  EXPECT_NEAR(b.cov(kPoseX, kPoseX), prior.cov(kPoseX, kPoseX) + s2, cov_rel * s2);
  EXPECT_NEAR(b.cov(kPoseY, kPoseY), prior.cov(kPoseY, kPoseY) + s2, cov_rel * s2);
  EXPECT_NEAR(b.cov(kPoseYaw, kPoseYaw), prior.cov(kPoseYaw, kPoseYaw) + yaw2, cov_rel * yaw2);
  if (exact) {
    EXPECT_NEAR(b.mean(kPoseYaw), prior.mean(kPoseYaw), 1e-12);
  }
  EXPECT_FALSE(health_problem(*filter));
}

INSTANTIATE_TEST_SUITE_P(BothFilters, PoseRules, ::testing::Values(FilterKind::kEkf, FilterKind::kParticle),
                         [](const auto& info) { return to_string(info.param); });

TEST(PoseParticleFilter, SameSeedSameBeliefs_OtherSeedOtherBeliefs) {
  const BeaconMap map = four_beacons();
  const PoseFilterConfig config = config_with_sigma(0.05);
  const PoseBelief prior = prior_at({4.0, 3.0, 0.0, 0.6});
  ParticlePoseFilter a(config, map, initial_pose(prior), 9);
  ParticlePoseFilter b(config, map, initial_pose(prior), 9);
  ParticlePoseFilter c(config, map, initial_pose(prior), 10);
  const OdometryIncrement u = odometry_2d(0.2, 0.0, 0.05, GaussianMotionModel2D{});
  Eigen::Vector4d truth = prior.mean;
  for (int k = 0; k < 20; ++k) {
    truth = compose(truth, u.delta);
    a.step(u, {exact_scan(map, truth)});
    b.step(u, {exact_scan(map, truth)});
    c.step(u, {exact_scan(map, truth)});
  }
  EXPECT_EQ(a.belief().mean, b.belief().mean);
  EXPECT_EQ(a.belief().cov, b.belief().cov);
  EXPECT_NE(a.belief().mean, c.belief().mean);
}

TEST(PoseFilterConfig, BadNewField_NamesIt) {
  PoseFilterConfig config;
  config.range_gate_chi2 = -1.0;
  try {
    validate(config);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("range_gate_chi2 = -1"), std::string::npos) << e.what();
  }
  config = PoseFilterConfig{};
  config.min_ranges_for_fix = 0;
  EXPECT_THROW(validate(config), std::invalid_argument);
}

}  // namespace
}  // namespace losmimo::localization
