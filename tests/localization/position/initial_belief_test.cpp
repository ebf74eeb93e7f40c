// The epoch-0 position belief (initial_belief.h): each branch of the rule, and the start-cube
// prior against the uniform distribution it stands for.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/initial_belief.h"

namespace losmimo::localization {
namespace {

BeaconMeasurement beacon_at(const Eigen::Vector3d& q_m) { return to_measurement(beacon_predict(q_m)); }

TEST(InitialBelief, NoBeacon_IsTheDegradedPrior) {
  const FilterConfig config;
  const Belief prior = start_cube_prior(placement::Scenario{}, config);
  const InitialBelief b = initial_belief(std::nullopt, config, prior);
  EXPECT_EQ(b.source, InitialBeliefSource::kPriorNoBeacon);
  EXPECT_FALSE(b.beacon_used());
  EXPECT_FALSE(b.beacon_fix);
  EXPECT_EQ(b.belief.mean_m, prior.mean_m);
  EXPECT_EQ(b.belief.cov_m2, prior.cov_m2);
  EXPECT_TRUE(b.belief.degraded);
  EXPECT_EQ(b.belief.epochs_since_beacon, config.degraded_after_epochs);
}

TEST(InitialBelief, PlausibleBeacon_IsTheFixWithTheConfiguredSigmas) {
  FilterConfig config;
  config.noise.sigma_range_m = 0.3;
  config.noise.sigma_angle_rad = 2e-4;
  const BeaconMeasurement z = beacon_at({1000.0, 20.0, -5.0});
  const InitialBelief b = initial_belief(z, config, start_cube_prior(placement::Scenario{}, config));
  const Belief expected = beacon_fix(z, 0.3, 2e-4);
  EXPECT_EQ(b.source, InitialBeliefSource::kBeaconFix);
  EXPECT_TRUE(b.beacon_used());
  EXPECT_EQ(b.belief.mean_m, expected.mean_m);  // bit for bit: the closed loop's golden runs depend on it
  EXPECT_EQ(b.belief.cov_m2, expected.cov_m2);
  EXPECT_FALSE(b.belief.degraded);
  EXPECT_EQ(b.belief.epochs_since_beacon, 0);
  ASSERT_TRUE(b.beacon_fix);
  EXPECT_EQ(b.beacon_fix->mean_m, expected.mean_m);
}

TEST(InitialBelief, ImplausibleOrNanBeacon_IsThePriorAndSaysWhy) {
  const FilterConfig config;
  const Belief prior = start_cube_prior(placement::Scenario{}, config);
  BeaconMeasurement far = beacon_at({1000.0, 0.0, 0.0});
  far.range_m = 2.0 * config.max_beacon_range_m;
  BeaconMeasurement nan = beacon_at({1000.0, 0.0, 0.0});
  nan.range_m = std::numeric_limits<double>::quiet_NaN();
  BeaconMeasurement upside_down = beacon_at({1000.0, 0.0, 0.0});
  upside_down.elevation_rad = 2.0;  // |el| > pi/2 after wrapping
  for (const BeaconMeasurement& z : {far, nan, upside_down}) {
    const InitialBelief b = initial_belief(z, config, prior);
    EXPECT_EQ(b.source, InitialBeliefSource::kPriorImplausibleBeacon);
    EXPECT_FALSE(b.beacon_fix);
    EXPECT_EQ(b.belief.mean_m, prior.mean_m);
    EXPECT_TRUE(b.belief.degraded);
  }
}

TEST(InitialBelief, UnhealthyFix_IsThePriorWithTheProblemAndTheFixKept) {
  // GIVEN: a plausible beacon but an angle sigma so large that the fix's covariance overflows.
  FilterConfig config;
  config.noise.sigma_angle_rad = 1e300;
  const Belief prior = start_cube_prior(placement::Scenario{}, config);
  const InitialBelief b = initial_belief(beacon_at({1000.0, 0.0, 0.0}), config, prior);
  EXPECT_EQ(b.source, InitialBeliefSource::kPriorHealthProblem);
  EXPECT_NE(b.health_problem.find("cov_m2"), std::string::npos) << b.health_problem;
  EXPECT_TRUE(b.beacon_fix);  // callers still score the fix they computed
  EXPECT_EQ(b.belief.cov_m2, prior.cov_m2);
  EXPECT_EQ(to_string(b.source), "prior (beacon fix unhealthy)");
}

TEST(InitialBelief, StartCubePrior_HasTheMomentsOfTheUniformCube) {
  // Independent check: the sample moments of uniform draws in the cube.
  constexpr int kDraws = 200000;
  placement::Scenario scenario;
  scenario.cube_side_m = 40.0;
  scenario.cube_center_m = Eigen::Vector3d(900.0, -10.0, 30.0);
  const Belief prior = start_cube_prior(scenario, FilterConfig{});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.5 * scenario.cube_side_m, 0.5 * scenario.cube_side_m);
  double sum = 0.0;
  double sum_sq = 0.0;
  for (int k = 0; k < kDraws; ++k) {
    const double x = u(rng);
    sum += x;
    sum_sq += x * x;
  }
  const double var = sum_sq / kDraws - (sum / kDraws) * (sum / kDraws);
  EXPECT_EQ(prior.mean_m, scenario.cube_center_m);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(prior.cov_m2(i, i), var, 0.01 * var);
  EXPECT_EQ(prior.cov_m2(0, 1), 0.0);
}

}  // namespace
}  // namespace losmimo::localization
