// Both filters under bad inputs on the seeded nominal trial: gross outliers, NaN/Inf, a
// 20-epoch beacon outage, and a belief that has lost track.

#include <gtest/gtest.h>

#include <iostream>

#include "localization/position/trial_runner.h"

namespace losmimo::localization {
namespace {

using test_support::rmse_m;
using test_support::run_trial;
using test_support::run_trials;
using test_support::TrialSpec;

constexpr int kNumTrials = 20;
constexpr int kSettleEpochs = 10;

class Degradation : public ::testing::TestWithParam<FilterKind> {};

TEST_P(Degradation, FivePercentGrossOutliers_RmseWithin1p5xOfClean) {
  constexpr double kMaxRatio = 1.5;
  TrialSpec clean;
  TrialSpec dirty;
  dirty.sim.outlier_fraction = 0.05;
  const auto clean_trials = run_trials(GetParam(), clean, kNumTrials);
  const auto dirty_trials = run_trials(GetParam(), dirty, kNumTrials);
  const double clean_m = rmse_m(clean_trials, kSettleEpochs);
  const double dirty_m = rmse_m(dirty_trials, kSettleEpochs);
  std::cout << to_string(GetParam()) << ": RMSE clean " << clean_m << " m, 5% outliers " << dirty_m << " m\n";
  EXPECT_LE(dirty_m, kMaxRatio * clean_m);
  int outliers = 0;
  std::int64_t gated = 0;
  for (const auto& t : dirty_trials) {
    outliers += t.num_outliers;
    gated += t.counters.rejected_gate;
  }
  // Every gross error is gated (plus ~0.1% of clean beacons by the chi-square gate).
  EXPECT_GT(outliers, 0);
  EXPECT_GE(gated, outliers);
  constexpr int kFalseRejectionAllowance = 10;  // expected ~2: 0.1% of 2000 clean beacons
  EXPECT_LE(gated, outliers + kFalseRejectionAllowance);
}

TEST_P(Degradation, GateOff_OutliersDoDamage) {
  // The same outliers without the gate: proves the previous test measures the gate. (The PF
  // suffers less than the EKF: a particle cloud cannot follow an outlier beyond its support.)
  constexpr double kMinDamageRatio = 1.3;
  TrialSpec gated;
  gated.sim.outlier_fraction = 0.05;
  TrialSpec open = gated;
  open.filter.gate_enabled = false;
  const double gated_m = rmse_m(run_trials(GetParam(), gated, kNumTrials), kSettleEpochs);
  const double open_m = rmse_m(run_trials(GetParam(), open, kNumTrials), kSettleEpochs);
  std::cout << to_string(GetParam()) << ": RMSE with outliers, gate on " << gated_m << " m, gate off " << open_m
            << " m\n";
  EXPECT_GT(open_m, kMinDamageRatio * gated_m);
}

TEST_P(Degradation, NanBeaconsAndInfDisplacements_RejectedCountedAndHarmless) {
  TrialSpec spec;
  spec.nan_beacon_epochs = {5, 17, 40, 41, 77};
  spec.inf_displacement_epochs = {8, 60};
  const auto result = run_trial(GetParam(), spec, 3);
  EXPECT_EQ(result.counters.rejected_non_finite_beacon, 5);
  EXPECT_EQ(result.counters.rejected_non_finite_displacement, 2);
  for (const auto& e : result.error_m) {
    ASSERT_TRUE(e.allFinite());
    EXPECT_LT(e.norm(), 1.0);
  }
  for (const auto& P : result.cov_m2) ASSERT_TRUE(P.allFinite());
}

TEST_P(Degradation, TwentyEpochOutage_CovarianceGrowsDegradedThenRecovers) {
  constexpr int kOutageStart = 40;
  constexpr int kOutageEpochs = 20;
  TrialSpec spec;
  spec.sim.outages = {{kOutageStart, kOutageEpochs}};
  const auto r = run_trial(GetParam(), spec, 4);
  const int last_dark = kOutageStart + kOutageEpochs - 1;
  // THEN: the covariance grows through the outage...
  const double trace_before = r.cov_m2[kOutageStart - 1].trace();
  for (int k = kOutageStart; k <= last_dark; ++k) {
    EXPECT_GT(r.cov_m2[k].trace(), r.cov_m2[k - 1].trace()) << "epoch " << k;
  }
  EXPECT_GT(r.cov_m2[last_dark].trace(), 4.0 * trace_before);
  // ...the belief is healthy before, degraded after degraded_after_epochs dark epochs...
  const int first_degraded = kOutageStart + spec.filter.degraded_after_epochs - 1;
  EXPECT_FALSE(r.degraded[kOutageStart - 1]);
  EXPECT_FALSE(r.degraded[first_degraded - 1]);
  for (int k = first_degraded; k <= last_dark; ++k) EXPECT_TRUE(r.degraded[k]) << "epoch " << k;
  // ...and recovers at the first beacon after it, with the covariance back to its old size.
  EXPECT_FALSE(r.degraded[last_dark + 1]);
  EXPECT_LT(r.cov_m2[last_dark + 10].trace(), 1.5 * trace_before);
  EXPECT_LT(r.error_m[last_dark + 10].norm(), 0.5);
  EXPECT_EQ(r.counters.resets, 0);
}

TEST_P(Degradation, LostTrack_ResetsFromBeaconFixAndReconverges) {
  // GIVEN: an initial belief 30 m off with a 0.2 m sigma: the gate rejects every beacon until
  // reset_after_rejections of them in a row have been rejected.
  TrialSpec spec;
  spec.initial_offset_m = Eigen::Vector3d(0.0, 30.0, 0.0);
  const auto r = run_trial(GetParam(), spec, 5);
  EXPECT_EQ(r.counters.resets, 1);
  EXPECT_EQ(r.counters.rejected_gate, spec.filter.reset_after_rejections);
  EXPECT_LT(r.error_m.back().norm(), 0.5);
}

INSTANTIATE_TEST_SUITE_P(BothFilters, Degradation, ::testing::Values(FilterKind::kEkf, FilterKind::kParticle),
                         [](const auto& info) { return to_string(info.param); });

}  // namespace
}  // namespace losmimo::localization
