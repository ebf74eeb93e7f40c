// The range-and-odometry simulator (pose/simulator.h) against its stated models: noise moments
// by Monte Carlo, what a scan contains, its schedule, and the BS's antennas as beacons.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "losmimo/localization/pose/simulator.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::localization {
namespace {

constexpr int kDraws = 20000;

BeaconMap two_beacons() {
  BeaconMap map;
  map.add(5, {0.0, 0.0, 1.0});
  map.add(9, {30.0, 0.0, 1.0});
  return map;
}

TEST(RangeSimulator, Ranges_UnbiasedWithTheConfiguredSigma_FromTheOffsetSensor) {
  RangeSimulatorConfig config;
  config.sigma_range_m = 0.07;
  config.sensor_on_robot_m = Eigen::Vector3d(0.5, 0.0, 0.2);
  RangeSensorSimulator sim(config, two_beacons(), 3);
  const Eigen::Vector4d pose(10.0, 4.0, 0.0, 1.5707963267948966);  // sensor at (10, 4.5, 0.2)
  const double truth_m = (Eigen::Vector3d(10.0, 4.5, 0.2) - Eigen::Vector3d(0.0, 0.0, 1.0)).norm();
  double sum = 0.0, sum_sq = 0.0;
  for (int k = 0; k < kDraws; ++k) {
    const auto scan = sim.measure_ranges(pose, k);
    ASSERT_TRUE(scan);
    ASSERT_EQ(scan->ranges.size(), 2U);
    EXPECT_EQ(scan->ranges[0].beacon_id, 5);
    EXPECT_EQ(scan->ranges[0].sensor_on_robot_m, config.sensor_on_robot_m);
    EXPECT_EQ(scan->std_error_m, 0.07);
    const double e = scan->ranges[0].range_m - truth_m;
    sum += e;
    sum_sq += e * e;
  }
  EXPECT_NEAR(sum / kDraws, 0.0, 4.0 * 0.07 / std::sqrt(kDraws));
  EXPECT_NEAR(std::sqrt(sum_sq / kDraws), 0.07, 0.02 * 0.07);
}

TEST(RangeSimulator, BeaconsOutsideTheSensorLimits_AreNotReported) {
  RangeSimulatorConfig config;
  config.max_sensor_distance_m = 25.0;
  RangeSensorSimulator sim(config, two_beacons(), 4);
  const auto scan = sim.measure_ranges({2.0, 0.0, 1.0, 0.0}, 0);  // 2 m and 28 m away
  ASSERT_TRUE(scan);
  ASSERT_EQ(scan->ranges.size(), 1U);
  EXPECT_EQ(scan->ranges[0].beacon_id, 5);
  EXPECT_EQ(scan->max_sensor_distance_m, 25.0);
}

TEST(RangeSimulator, ScheduleHonoursPeriodAndOutages) {
  RangeSimulatorConfig config;
  config.period_epochs = 2;
  config.outages = {{4, 3}};
  RangeSensorSimulator sim(config, two_beacons(), 5);
  EXPECT_TRUE(sim.scan_scheduled(0));
  EXPECT_FALSE(sim.scan_scheduled(1));
  EXPECT_FALSE(sim.scan_scheduled(4));
  EXPECT_FALSE(sim.scan_scheduled(6));
  EXPECT_TRUE(sim.scan_scheduled(8));
  EXPECT_FALSE(sim.measure_ranges(Eigen::Vector4d::Zero(), 5));
  EXPECT_THROW(sim.scan_scheduled(-1), std::invalid_argument);
}

TEST(RangeSimulator, OdometryNoise_HasTheMrptGaussianCovariance) {
  RangeSimulatorConfig config;
  config.odometry.a1 = 0.05;
  config.sigma_z_m = 0.01;
  RangeSensorSimulator sim(config, two_beacons(), 6);
  const Eigen::Vector4d u(0.3, 0.05, 0.02, 0.2);
  const Eigen::Matrix4d model = odometry_2d(0.3, 0.05, 0.2, config.odometry, 0.01).cov;
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  Eigen::Matrix4d sum_sq = Eigen::Matrix4d::Zero();
  for (int k = 0; k < kDraws; ++k) {
    const OdometryIncrement r = sim.measure_odometry(u);
    const Eigen::Vector4d e = r.delta - u;
    sum += e;
    sum_sq += e * e.transpose();
  }
  const Eigen::Matrix4d cov = sum_sq / kDraws - (sum / kDraws) * (sum / kDraws).transpose();
  for (int i = 0; i < kPoseSize; ++i) EXPECT_NEAR(cov(i, i), model(i, i), 0.04 * model(i, i)) << i;
  EXPECT_NEAR(cov(kPoseY, kPoseYaw), model(kPoseY, kPoseYaw), 0.08 * std::abs(model(kPoseY, kPoseYaw)));
}

TEST(RangeSimulator, BsAntennas_RangesFromAKilometreAreTheAntennaDistances) {
  const placement::Scenario scenario;
  RangeSimulatorConfig config;
  config.sigma_range_m = 0.0;
  config.max_sensor_distance_m = 5000.0;
  RangeSensorSimulator sim(config, bs_antenna_beacon_map(scenario), 7);
  const Eigen::Vector4d uav(1000.0, 20.0, -10.0, 0.0);
  const auto scan = sim.measure_ranges(uav, 0);
  ASSERT_TRUE(scan);
  ASSERT_EQ(scan->ranges.size(), static_cast<std::size_t>(scenario.num_bs_antennas()));
  const Eigen::Matrix3Xd antennas_m = placement::bs_antenna_positions_m(scenario);
  for (const BeaconRange& r : scan->ranges) {
    EXPECT_DOUBLE_EQ(r.range_m, (uav.head<3>() - antennas_m.col(r.beacon_id)).norm());
  }
}

TEST(RangeSimulator, BadConfig_NamesTheField) {
  RangeSimulatorConfig config;
  config.dropout_fraction = 1.5;
  try {
    RangeSensorSimulator sim(config, two_beacons(), 1);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dropout_fraction = 1.5"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace losmimo::localization
