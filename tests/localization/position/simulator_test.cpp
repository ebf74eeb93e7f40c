// The simulator reproduces its documented noise, schedule and outlier models.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
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

TEST(SensorSimulator, CommonModeErrors_AreTheBsMisplacedAndMisaligned_TheSameForEveryUav) {
  // Noise-free, so each beacon is the geometry itself, computed here from the BS's true place.
  SimulatorConfig config;
  config.sigma_range_m = 0.0;
  config.sigma_angle_rad = 0.0;
  config.bs_azimuth_bias_rad = 1e-3;
  config.bs_elevation_bias_rad = -5e-4;
  config.beacon_range_bias_m = 0.25;
  config.bs_position_error_m = Eigen::Vector3d(0.3, -0.5, 0.2);
  for (const Eigen::Vector3d& q : {Eigen::Vector3d(1000.0, 2.0, -3.0), Eigen::Vector3d(995.0, -7.5, 4.0)}) {
    SensorSimulator sim(config, 5);
    const auto z = sim.measure_beacon(q, 0);
    ASSERT_TRUE(z.has_value());
    const Eigen::Vector3d d = q - config.bs_position_error_m;
    EXPECT_NEAR(z->range_m, d.norm() + 0.25, 1e-9);
    EXPECT_NEAR(z->azimuth_rad, std::atan2(d.y(), d.x()) + 1e-3, 1e-12);
    EXPECT_NEAR(z->elevation_rad, std::atan2(d.z(), std::hypot(d.x(), d.y())) - 5e-4, 1e-12);
    // Negative control: the nominal BS (origin, aligned) reads otherwise.
    SimulatorConfig aligned;
    aligned.sigma_range_m = aligned.sigma_angle_rad = 0.0;
    SensorSimulator nominal(aligned, 5);
    EXPECT_GT(std::abs(nominal.measure_beacon(q, 0)->azimuth_rad - z->azimuth_rad), 9e-4);
  }
}

TEST(SensorSimulator, CommonModeErrorsUnset_MeasureBitForBitAsWithoutThem) {
  SimulatorConfig zero;
  zero.bs_azimuth_bias_rad = zero.bs_elevation_bias_rad = zero.beacon_range_bias_m = -0.0;
  zero.bs_position_error_m = -Eigen::Vector3d::Zero();
  SensorSimulator a(SimulatorConfig{}, 7), b(zero, 7);
  const Eigen::Vector3d q(1000.0, 0.0, -0.0);
  for (int k = 0; k < 50; ++k) {
    const auto za = a.measure_beacon(q, k), zb = b.measure_beacon(q, k);
    ASSERT_EQ(za.has_value(), zb.has_value());
    if (!za) continue;
    EXPECT_EQ(std::signbit(za->azimuth_rad), std::signbit(zb->azimuth_rad));
    EXPECT_EQ(za->range_m, zb->range_m);
    EXPECT_EQ(za->azimuth_rad, zb->azimuth_rad);
    EXPECT_EQ(za->elevation_rad, zb->elevation_rad);
  }
}

TEST(SensorSimulator, CommonModeErrorsOutOfRange_AreRefusedNamingTheField) {
  SimulatorConfig c;
  c.bs_azimuth_bias_rad = 0.5;
  EXPECT_THROW(validate(c), std::exception);
  c = SimulatorConfig{};
  c.bs_position_error_m.y() = std::nan("");
  try {
    validate(c);
    ADD_FAILURE() << "NaN BS position error accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("bs_position_error_m[1]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace losmimo::localization
