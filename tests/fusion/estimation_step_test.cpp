// The per-UAV estimation step (estimation_step.h): what it screens, what the filter and the
// refinement receive, and the health rule, against the filter driven by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "losmimo/fusion/estimation_step.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/placement/channel.h"

namespace losmimo::fusion {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

placement::Scenario scenario() { return placement::Scenario{}; }

localization::BeaconMeasurement beacon_at(const Eigen::Vector3d& q_m) {
  const Eigen::Vector3d z = localization::beacon_predict(q_m);
  return {z(0), z(1), z(2)};
}

UavEstimator estimator(bool refine = false) {
  EstimatorConfig config;
  config.refine = refine;
  const localization::Belief prior = localization::start_cube_prior(scenario(), config.filter);
  return UavEstimator(scenario(), config, prior, 7);
}

TEST(UavEstimator, Epoch0WithAPlausibleBeacon_StartsFromItsFix) {
  UavEstimator uav = estimator();
  const Eigen::Vector3d q(1000.0, 3.0, -2.0);
  const localization::BeaconMeasurement z = beacon_at(q);
  const EpochEstimate e = uav.start({std::nullopt, z, {}});
  const localization::Belief fix = localization::beacon_fix(z, 0.1, 1e-4);  // FilterConfig's noise
  EXPECT_EQ(e.initial_source, localization::InitialBeliefSource::kBeaconFix);
  EXPECT_EQ(e.filter_belief.mean_m, fix.mean_m);
  EXPECT_EQ(e.filter_belief.cov_m2, fix.cov_m2);
  ASSERT_TRUE(e.beacon);
  ASSERT_TRUE(e.beacon_fix_m);
  EXPECT_EQ(*e.beacon_fix_m, fix.mean_m);
  EXPECT_FALSE(e.health_problem);
}

TEST(UavEstimator, ImplausibleBeacon_IsDroppedBeforeTheFilter_AndNotABeaconOnlySample) {
  UavEstimator uav = estimator();
  const Eigen::Vector3d q(1000.0, 3.0, -2.0);
  uav.start({std::nullopt, beacon_at(q), {}});
  localization::BeaconMeasurement far = beacon_at(q);
  far.range_m = 2e5;  // beyond max_beacon_range_m = 1e5 m
  const EpochEstimate e = uav.step({Eigen::Vector3d::Zero(), far, {}});
  EXPECT_TRUE(e.rejected_beacon);
  EXPECT_FALSE(e.beacon);
  EXPECT_FALSE(e.beacon_fix_m);
  EXPECT_EQ(uav.filter().counters().beacons_received, 0);  // the filter saw an epoch without beacon
}

TEST(UavEstimator, NonFiniteDisplacement_IsMissing_TheFilterPredictsWithItsMissingSigma) {
  UavEstimator uav = estimator();
  const Eigen::Vector3d q(1000.0, 3.0, -2.0);
  const localization::Belief start = uav.start({std::nullopt, beacon_at(q), {}}).filter_belief;
  const EpochEstimate e = uav.step({Eigen::Vector3d(kNaN, 0.0, 0.0), std::nullopt, {}});
  EXPECT_TRUE(e.rejected_displacement);
  EXPECT_FALSE(e.displacement_m);
  // Prediction with d = 0 and missing_displacement_sigma_m = 1 m per axis: P + I.
  EXPECT_EQ(e.filter_belief.mean_m, start.mean_m);
  EXPECT_NEAR((e.filter_belief.cov_m2 - start.cov_m2 - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 0.0, 1e-12);
}

TEST(UavEstimator, Beliefs_AreTheFiltersDrivenByHand_BitForBit) {
  // GIVEN: the same measurements to the step and to a filter made and stepped by hand.
  EstimatorConfig config;
  config.filter_kind = localization::FilterKind::kParticle;
  config.filter.num_particles = 200;
  const localization::Belief prior = localization::start_cube_prior(scenario(), config.filter);
  UavEstimator uav(scenario(), config, prior, 99);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 0.05);
  Eigen::Vector3d q(1000.0, 3.0, -2.0);
  const localization::BeaconMeasurement z0 = beacon_at(q);
  const localization::Belief fix =
      localization::beacon_fix(z0, config.filter.noise.sigma_range_m, config.filter.noise.sigma_angle_rad);
  auto by_hand = localization::make_filter(config.filter_kind, config.filter, fix, 99);
  uav.start({std::nullopt, z0, {}});
  for (int k = 1; k <= 20; ++k) {
    const Eigen::Vector3d d(0.1, -0.05 * k, 0.02);
    q += d;
    const Eigen::Vector3d d_meas = d + Eigen::Vector3d(n(rng), n(rng), n(rng));
    const std::optional<localization::BeaconMeasurement> z =
        k % 3 == 0 ? std::nullopt : std::optional<localization::BeaconMeasurement>(beacon_at(q));
    const EpochEstimate e = uav.step({d_meas, z, {}});
    by_hand->step(d_meas, z);
    const localization::Belief b = by_hand->belief();
    // THEN: identical beliefs, and the placement belief is the filter's without refinement.
    ASSERT_EQ(e.filter_belief.mean_m, b.mean_m) << "epoch " << k;
    ASSERT_EQ(e.filter_belief.cov_m2, b.cov_m2) << "epoch " << k;
    ASSERT_EQ(e.belief.mean_m, b.mean_m);
  }
}

TEST(UavEstimator, RefinementWithCsi_DropsNonFiniteRows_AndRefinesTheBelief) {
  UavEstimator uav = estimator(true);
  const placement::ChannelModel model(scenario());
  std::mt19937_64 rng(3);
  const Eigen::Vector3d q(1000.0, 0.3, -0.2);
  CsiMeasurement good = simulate_csi(model, q, scenario().noise_variance(), rng);
  CsiMeasurement bad = good;
  bad.y(2) = std::complex<double>(kNaN, 0.0);
  const EpochEstimate e = uav.start({std::nullopt, beacon_at(q), {bad, good}});
  EXPECT_EQ(e.rejected_csi, 1);
  ASSERT_EQ(e.csi.size(), 1u);
  EXPECT_EQ(e.csi.front().y, good.y);
  EXPECT_NE(e.belief.mean_m, e.filter_belief.mean_m);  // the refinement's, not the filter's
}

TEST(UavEstimator, AnOverflowingInitialFix_IsAHealthProblem_NamedAsSuch) {
  // GIVEN: a plausibility bound so large that a 1e300 m range passes the screen; its fix's
  // lateral variance (r sigma_angle)^2 overflows.
  EstimatorConfig config;
  config.filter.max_beacon_range_m = 1e308;
  const localization::Belief prior = localization::start_cube_prior(scenario(), config.filter);
  UavEstimator uav(scenario(), config, prior, 1);
  const EpochEstimate e = uav.start({std::nullopt, localization::BeaconMeasurement{1e300, 0.1, 0.1}, {}});
  EXPECT_EQ(e.initial_source, localization::InitialBeliefSource::kPriorHealthProblem);
  ASSERT_TRUE(e.health_problem);
  EXPECT_EQ(e.health_problem->rfind("initial beacon fix ", 0), 0u) << *e.health_problem;
  EXPECT_EQ(e.filter_belief.mean_m, prior.mean_m);  // the filter starts from the prior meanwhile
}

TEST(UavEstimator, StepBeforeStart_Throws) {
  UavEstimator uav = estimator();
  EXPECT_THROW(uav.step({}), std::logic_error);
}

}  // namespace
}  // namespace losmimo::fusion
