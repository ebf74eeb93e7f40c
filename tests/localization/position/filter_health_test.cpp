// Numerical health of the filters: health_problem() names the first non-finite or
// inconsistent part of a belief, and a filter whose state became non-finite says so. The
// plausibility screen (FilterConfig::max_beacon_range_m) keeps absurd but finite beacons from
// getting there through the reset rule, in both filters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "losmimo/localization/position/filter.h"
#include "localization/position/trial_runner.h"

namespace losmimo::localization {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Belief healthy_belief() {
  Belief b;
  b.mean_m = Eigen::Vector3d(1000.0, 2.0, 30.0);
  b.cov_m2 << 0.04, 0.01, 0.0, 0.01, 0.09, 0.005, 0.0, 0.005, 0.0225;
  return b;
}

std::string problem_of(const Belief& b) {
  const std::optional<std::string> p = health_problem(b);
  return p ? *p : std::string("healthy");
}

TEST(BeliefHealth, HealthyBelief_HasNoProblem) {
  EXPECT_EQ(problem_of(healthy_belief()), "healthy");
  Belief zero_variance = healthy_belief();  // PSD-ish is enough: a zero variance is no fault
  zero_variance.cov_m2.setZero();
  EXPECT_EQ(problem_of(zero_variance), "healthy");
}

TEST(BeliefHealth, NonFiniteMean_IsNamedWithItsAxis) {
  Belief b = healthy_belief();
  b.mean_m(1) = kNan;
  EXPECT_EQ(problem_of(b), "mean_m(1) = nan");
  b.mean_m(1) = 2.0;
  b.mean_m(2) = -kInf;
  EXPECT_EQ(problem_of(b), "mean_m(2) = -inf");
}

TEST(BeliefHealth, NonFiniteCovariance_IsNamedWithItsEntry) {
  Belief b = healthy_belief();
  b.cov_m2(0, 2) = kInf;
  b.cov_m2(2, 0) = kInf;
  EXPECT_EQ(problem_of(b), "cov_m2(0, 2) = inf");
  b = healthy_belief();
  b.cov_m2(1, 1) = kNan;
  EXPECT_EQ(problem_of(b), "cov_m2(1, 1) = nan");
}

TEST(BeliefHealth, NegativeVarianceAndAsymmetry_AreReported) {
  Belief b = healthy_belief();
  b.cov_m2(2, 2) = -0.5;
  EXPECT_EQ(problem_of(b), "cov_m2(2, 2) = -0.5 < 0");
  b = healthy_belief();
  b.cov_m2(0, 1) = 0.02;  // (1, 0) stays 0.01
  EXPECT_NE(problem_of(b).find("cov_m2 is asymmetric"), std::string::npos) << problem_of(b);
  // Rounding-level asymmetry is not a fault.
  b = healthy_belief();
  b.cov_m2(0, 1) += 1e-15;
  EXPECT_EQ(problem_of(b), "healthy");
}

class FilterHealth : public ::testing::TestWithParam<FilterKind> {};

TEST_P(FilterHealth, NominalEpochs_StayHealthy) {
  // GIVEN: a filter with sane beacons and displacements.
  FilterConfig config;
  config.num_particles = 200;
  auto filter = make_filter(GetParam(), config, healthy_belief(), 7);
  // WHEN
  for (int k = 0; k < 20; ++k) {
    filter->step(Eigen::Vector3d(0.0, 0.01, 0.0), BeaconMeasurement{1000.45, 0.002 + 1e-5 * k, 0.03});
  }
  // THEN
  EXPECT_FALSE(health_problem(*filter).has_value()) << *health_problem(*filter);
  EXPECT_EQ(filter->counters().non_finite_state, 0);
}

TEST_P(FilterHealth, BeaconFixAtAnAbsurdRange_OverflowsTheCovarianceAndIsReported) {
  // GIVEN: a filter without the plausibility screen (max_beacon_range_m opened up to DBL_MAX)
  // that keeps receiving a finite beacon at 1e300 m. The gate rejects it (its Mahalanobis
  // distance is infinite) until the reset rule re-initialises from a beacon fix, whose lateral
  // variance (r sigma_angle)^2 = 1e592 m^2 overflows.
  FilterConfig config;
  config.num_particles = 200;
  config.reset_after_rejections = 3;
  config.max_beacon_range_m = std::numeric_limits<double>::max();
  auto filter = make_filter(GetParam(), config, healthy_belief(), 7);
  const BeaconMeasurement absurd{1e300, 0.002, 0.03};
  // WHEN: the gated epochs: still healthy.
  for (int k = 0; k < config.reset_after_rejections; ++k) {
    filter->step(Eigen::Vector3d::Zero(), absurd);
    ASSERT_FALSE(health_problem(*filter).has_value()) << "epoch " << k << ": " << *health_problem(*filter);
  }
  // ... then the reset.
  filter->step(Eigen::Vector3d::Zero(), absurd);
  // THEN: the filter repaired its covariance (so its belief may look finite) but reports it.
  EXPECT_EQ(filter->counters().resets, 1);
  EXPECT_GE(filter->counters().non_finite_state, 1);
  const std::optional<std::string> problem = health_problem(*filter);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("non-finite"), std::string::npos) << *problem;
}

TEST_P(FilterHealth, AbsurdRange_IsRejectedBeforeTheResetRule_WithTheDefaultLimit) {
  // GIVEN: the test above, with the default max_beacon_range_m.
  FilterConfig config;
  config.num_particles = 200;
  config.reset_after_rejections = 3;
  auto filter = make_filter(GetParam(), config, healthy_belief(), 7);
  auto no_beacons = make_filter(GetParam(), config, healthy_belief(), 7);
  // WHEN: many more absurd beacons than the reset rule needs.
  constexpr int kNumAbsurd = 10;
  for (int k = 0; k < kNumAbsurd; ++k) {
    filter->step(Eigen::Vector3d::Zero(), BeaconMeasurement{1e300, 0.002, 0.03});
    no_beacons->step(Eigen::Vector3d::Zero(), std::nullopt);
  }
  // THEN: none was gated, none reset the filter, and it is healthy: as if they never came.
  EXPECT_EQ(filter->counters().rejected_out_of_range_beacon, kNumAbsurd);
  EXPECT_EQ(filter->counters().rejected_gate, 0);
  EXPECT_EQ(filter->counters().resets, 0);
  EXPECT_EQ(filter->counters().non_finite_state, 0);
  EXPECT_FALSE(health_problem(*filter).has_value()) << *health_problem(*filter);
  EXPECT_EQ(filter->belief().mean_m, no_beacons->belief().mean_m);
  EXPECT_EQ(filter->belief().cov_m2, no_beacons->belief().cov_m2);
}

// The nominal seeded trial (trial_runner.h, 100 epochs, a beacon every epoch) with 50 beacons
// replaced: blocks of 12 or 13 in a row, longer than reset_after_rejections (10), alternately
// at 1e300 m and just above the default max_beacon_range_m (in the start's direction).
// `withhold` withholds those beacons instead.
constexpr std::uint64_t kTrialSeed = 4;

test_support::TrialSpec trial_with_replaced_beacons(bool withhold, double max_beacon_range_m) {
  constexpr int kBlockFirstEpoch[] = {8, 28, 49, 69};
  constexpr int kBlockLength[] = {12, 13, 12, 13};
  test_support::TrialSpec spec;
  spec.filter.num_particles = 500;
  spec.filter.max_beacon_range_m = max_beacon_range_m;
  const double above_limit_m = std::nextafter(FilterConfig{}.max_beacon_range_m, kInf);
  for (int b = 0; b < 4; ++b) {
    const BeaconMeasurement z{b % 2 == 0 ? 1e300 : above_limit_m, std::atan2(spec.start_m.y(), spec.start_m.x()), 0.02};
    for (int k = kBlockFirstEpoch[b]; k < kBlockFirstEpoch[b] + kBlockLength[b]; ++k) {
      spec.replaced_beacons[k] = withhold ? std::nullopt : std::optional<BeaconMeasurement>(z);
    }
  }
  return spec;
}

TEST_P(FilterHealth, FiftyImplausibleBeacons_RejectedCounted_BeliefAsIfTheyWereAbsent) {
  constexpr int kNumReplaced = 50;
  const double limit_m = FilterConfig{}.max_beacon_range_m;
  // GIVEN / WHEN: the same trial with the implausible beacons, and with them withheld.
  const test_support::TrialResult with =
      test_support::run_trial(GetParam(), trial_with_replaced_beacons(false, limit_m), kTrialSeed);
  const test_support::TrialResult without =
      test_support::run_trial(GetParam(), trial_with_replaced_beacons(true, limit_m), kTrialSeed);
  // THEN: every one was rejected as out of range, and nothing else changed.
  EXPECT_EQ(with.counters.rejected_out_of_range_beacon, kNumReplaced);
  EXPECT_EQ(without.counters.rejected_out_of_range_beacon, 0);
  EXPECT_EQ(with.counters.beacons_received, without.counters.beacons_received + kNumReplaced);
  EXPECT_EQ(with.counters.beacons_fused, without.counters.beacons_fused);
  EXPECT_EQ(with.counters.rejected_gate, without.counters.rejected_gate);
  EXPECT_EQ(with.counters.resets, 0);
  EXPECT_EQ(without.counters.resets, 0);
  EXPECT_EQ(with.counters.non_finite_state, 0);
  ASSERT_EQ(with.mean_m.size(), without.mean_m.size());
  double max_error_m = 0.0;
  for (std::size_t k = 0; k < with.mean_m.size(); ++k) {
    ASSERT_EQ(with.mean_m[k], without.mean_m[k]) << "epoch " << k;  // bit for bit
    ASSERT_EQ(with.cov_m2[k], without.cov_m2[k]) << "epoch " << k;
    ASSERT_EQ(with.degraded[k], without.degraded[k]) << "epoch " << k;
    Belief b;
    b.mean_m = with.mean_m[k];
    b.cov_m2 = with.cov_m2[k];
    ASSERT_FALSE(health_problem(b).has_value()) << "epoch " << k << ": " << *health_problem(b);
    max_error_m = std::max(max_error_m, with.error_m[k].norm());
  }
  // Close to the truth throughout: dead reckoning bridges each block of up to 13 epochs.
  // (Measured: 0.25 m (EKF) and 0.32 m (PF) at worst, 0.09 m at the end.)
  constexpr double kMaxError_m = 1.0;
  constexpr double kMaxFinalError_m = 0.5;
  EXPECT_LT(max_error_m, kMaxError_m);
  EXPECT_LT(with.error_m.back().norm(), kMaxFinalError_m);
}

TEST_P(FilterHealth, FiftyImplausibleBeacons_WithoutTheScreen_BreakTheFilter) {
  // The control of the test above: with the limit opened up, the same beacons are gated until
  // the reset rule takes a fix at 1e300 m, which overflows.
  const test_support::TrialResult open = test_support::run_trial(
      GetParam(), trial_with_replaced_beacons(false, std::numeric_limits<double>::max()), kTrialSeed);
  EXPECT_EQ(open.counters.rejected_out_of_range_beacon, 0);
  EXPECT_GE(open.counters.resets, 1);
  EXPECT_GE(open.counters.non_finite_state, 1);
}

TEST_P(FilterHealth, RangeJustBelowTheLimit_IsScreenedByTheGateOnly) {
  // GIVEN: beacons just below max_beacon_range_m in the belief's direction, ~99 km beyond it,
  // and a reference filter without a limit.
  FilterConfig config;
  config.num_particles = 200;
  config.reset_after_rejections = 3;
  FilterConfig open = config;
  open.max_beacon_range_m = std::numeric_limits<double>::max();
  auto filter = make_filter(GetParam(), config, healthy_belief(), 7);
  auto reference = make_filter(GetParam(), open, healthy_belief(), 7);
  const BeaconMeasurement far{std::nextafter(config.max_beacon_range_m, 0.0), 0.002, 0.03};
  // WHEN: gated three times, then the reset rule takes a fix from the fourth.
  for (int k = 0; k < config.reset_after_rejections + 1; ++k) {
    filter->step(Eigen::Vector3d::Zero(), far);
    reference->step(Eigen::Vector3d::Zero(), far);
  }
  // THEN: as before the screen existed (the same as without a limit), and healthy: at 1e5 m
  // the fix is finite.
  EXPECT_EQ(filter->counters().rejected_out_of_range_beacon, 0);
  EXPECT_EQ(filter->counters().rejected_gate, config.reset_after_rejections);
  EXPECT_EQ(filter->counters().resets, 1);
  EXPECT_EQ(filter->belief().mean_m, reference->belief().mean_m);
  EXPECT_EQ(filter->belief().cov_m2, reference->belief().cov_m2);
  constexpr double kFixTolerance_m = 1e3;  // the fix's lateral 1-sigma is 1e5 m * 1e-4 = 10 m
  EXPECT_NEAR(filter->belief().mean_m.norm(), far.range_m, kFixTolerance_m);
  EXPECT_FALSE(health_problem(*filter).has_value()) << *health_problem(*filter);
}

INSTANTIATE_TEST_SUITE_P(BothFilters, FilterHealth, ::testing::Values(FilterKind::kEkf, FilterKind::kParticle),
                         [](const ::testing::TestParamInfo<FilterKind>& info) { return to_string(info.param); });

}  // namespace
}  // namespace losmimo::localization
