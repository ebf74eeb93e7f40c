// The simulator reproduces its documented noise, schedule and outlier models.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/simulator.h"

namespace losmimo::localization {
namespace {

constexpr int kSamples = 20000;
// A sample standard deviation from 20000 draws is within ~2.5% at 5 sigma.
constexpr double kStdRelTolerance = 0.025;

double sample_std(const std::vector<double>& v) {
  double mean = 0.0;
  for (const double x : v) mean += x / static_cast<double>(v.size());
  double var = 0.0;
  for (const double x : v) var += (x - mean) * (x - mean) / static_cast<double>(v.size() - 1);
  return std::sqrt(var);
}

TEST(SensorSimulator, BeaconNoise_MatchesConfiguredSigmas) {
  SimulatorConfig config;
  config.sigma_range_m = 0.3;
  config.sigma_angle_rad = 2e-4;
  SensorSimulator sim(config, 11);
  const Eigen::Vector3d q(900.0, -40.0, 60.0);
  const Eigen::Vector3d z_true = beacon_predict(q);
  std::vector<double> er, ea, ee;
  for (int k = 0; k < kSamples; ++k) {
    const auto z = sim.measure_beacon(q, k);
    ASSERT_TRUE(z.has_value());
    const Eigen::Vector3d y = beacon_innovation(to_vector(*z), z_true);
    er.push_back(y(0));
    ea.push_back(y(1));
    ee.push_back(y(2));
  }
  EXPECT_NEAR(sample_std(er), config.sigma_range_m, kStdRelTolerance * config.sigma_range_m);
  EXPECT_NEAR(sample_std(ea), config.sigma_angle_rad, kStdRelTolerance * config.sigma_angle_rad);
  EXPECT_NEAR(sample_std(ee), config.sigma_angle_rad, kStdRelTolerance * config.sigma_angle_rad);
}

TEST(SensorSimulator, DeadReckoningNoise_IsFloorPlusFractionOfDistance) {
  SimulatorConfig config;  // floor 0.01 m, fraction 0.02
  SensorSimulator sim(config, 12);
  const Eigen::Vector3d d(3.0, -4.0, 0.0);  // |d| = 5 m -> sigma 0.11 m per axis
  const double expected = config.dr_sigma_floor_m + config.dr_sigma_fraction * 5.0;
  std::vector<double> ex, ez;
  for (int k = 0; k < kSamples; ++k) {
    const Eigen::Vector3d e = sim.measure_displacement(d) - d;
    ex.push_back(e.x());
    ez.push_back(e.z());
  }
  EXPECT_NEAR(sample_std(ex), expected, kStdRelTolerance * expected);
  EXPECT_NEAR(sample_std(ez), expected, kStdRelTolerance * expected);
}

TEST(SensorSimulator, Actuation_AddsSigmaActPerAxis) {
  SimulatorConfig config;
  config.sigma_act_m = 0.2;
  SensorSimulator sim(config, 13);
  const Eigen::Vector3d c(1.0, 0.0, 0.0);
  std::vector<double> ey;
  for (int k = 0; k < kSamples; ++k) ey.push_back((sim.actuate(c) - c).y());
  EXPECT_NEAR(sample_std(ey), config.sigma_act_m, kStdRelTolerance * config.sigma_act_m);
}

TEST(SensorSimulator, PeriodAndOutages_ShapeTheSchedule) {
  SimulatorConfig config;
  config.beacon_period_epochs = 3;
  config.outages = {{6, 4}, {20, 1}};  // no beacon at 6..9 and at 20
  SensorSimulator sim(config, 14);
  const Eigen::Vector3d q(1000.0, 0.0, 0.0);
  std::vector<int> epochs_with_beacon;
  for (int k = 0; k < 25; ++k) {
    if (sim.measure_beacon(q, k)) epochs_with_beacon.push_back(k);
  }
  EXPECT_EQ(epochs_with_beacon, (std::vector<int>{0, 3, 12, 15, 18, 21, 24}));
  EXPECT_THROW(sim.beacon_scheduled(-1), std::invalid_argument);
}

TEST(SensorSimulator, Outliers_AppearAtTheConfiguredRateAndAreGross) {
  SimulatorConfig config;
  config.outlier_fraction = 0.05;
  SensorSimulator sim(config, 15);
  const Eigen::Vector3d q(1000.0, 0.0, 0.0);
  int gross = 0;
  for (int k = 0; k < kSamples; ++k) {
    const auto z = sim.measure_beacon(q, k);
    const Eigen::Vector3d y = beacon_innovation(to_vector(*z), beacon_predict(q));
    // 10 nominal sigmas on any component: a nominal beacon essentially never gets there.
    if (std::abs(y(0)) > 10.0 * config.sigma_range_m || std::abs(y(1)) > 10.0 * config.sigma_angle_rad ||
        std::abs(y(2)) > 10.0 * config.sigma_angle_rad) {
      ++gross;
    }
  }
  // Binomial(20000, 0.05): mean 1000, sigma ~31.
  EXPECT_NEAR(sim.num_outliers(), 1000, 5 * 31);
  EXPECT_LE(gross, sim.num_outliers());
  EXPECT_GE(gross, sim.num_outliers() * 99 / 100);  // gross on at least one component
}

TEST(SensorSimulator, SameSeed_SameSequence_OtherSeed_Differs) {
  const SimulatorConfig config;
  SensorSimulator a(config, 99);
  SensorSimulator b(config, 99);
  SensorSimulator c(config, 100);
  const Eigen::Vector3d q(1000.0, 1.0, 2.0);
  const auto za = a.measure_beacon(q, 0);
  const auto zb = b.measure_beacon(q, 0);
  const auto zc = c.measure_beacon(q, 0);
  EXPECT_EQ(za->range_m, zb->range_m);
  EXPECT_EQ(za->azimuth_rad, zb->azimuth_rad);
  EXPECT_NE(za->range_m, zc->range_m);
}

}  // namespace
}  // namespace losmimo::localization
