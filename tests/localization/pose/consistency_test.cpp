// Statistical tests of both pose filters on the seeded range-and-odometry trial
// (pose/trial_runner.h): 4-dof NEES consistency at the nominal and at the smallest range noise
// the filters represent, accuracy against dead reckoning, and a wrong noise model failing the
// same check. Seeded, never retried.

#include <gtest/gtest.h>

#include <iostream>

#include "localization/pose/trial_runner.h"

namespace losmimo::localization {
namespace {

using test_support::fraction_in_pose_nees_band;
using test_support::mean_nees;
using test_support::range_rmse_m;
using test_support::RangeTrialSpec;
using test_support::run_range_trials;

// As the position filters' consistency test: the band fraction of a consistent filter is ~0.95,
// but epochs are correlated, so it varies by a few hundredths between seed sets; 50 runs x 200
// epochs, the first kSettleEpochs left out (the start's heading prior is 30x wider than what 1 mm
// ranges resolve through the sensor lever, a non-Gaussian transient). The particle filter runs
// 2000 particles: at 1000 its Monte Carlo error raises the mean NEES by ~5% and the fraction
// becomes marginal. Measured (this seed set): EKF 0.968 / 0.911, PF 0.911 / 0.932 (nominal /
// smallest noise); mean NEES 4.08 / 4.15 and 4.22 / 4.09 against 4.
constexpr int kNumTrials = 50;
constexpr int kEpochs = 200;
constexpr int kParticles = 2000;
constexpr double kMinFractionInBand = 0.90;
constexpr int kSettleEpochs = 10;

RangeTrialSpec consistency_spec() {
  RangeTrialSpec spec;
  spec.num_epochs = kEpochs;
  spec.filter.filter.num_particles = kParticles;
  return spec;
}

RangeTrialSpec smallest_noise_spec() {
  // The smallest range noise a filter represents: its floor, in truth and in the model.
  RangeTrialSpec spec = consistency_spec();
  spec.sim.sigma_range_m = spec.filter.filter.min_sigma_range_m;
  return spec;
}

class RangeConsistency : public ::testing::TestWithParam<FilterKind> {};

TEST_P(RangeConsistency, NominalNoise_NeesInBandAndBetterThanDeadReckoning) {
  const auto trials = run_range_trials(GetParam(), consistency_spec(), kNumTrials);
  const double fraction = fraction_in_pose_nees_band(trials, kSettleEpochs);
  const double rmse = range_rmse_m(trials, false, kSettleEpochs);
  const double dr = range_rmse_m(trials, true, kSettleEpochs);
  const double nis = test_support::mean_reading_nis(trials);
  std::cout << to_string(GetParam()) << " nominal (sigma 0.05 m): NEES mean " << mean_nees(trials)
            << ", fraction in band " << fraction << ", reading NIS " << nis << ", RMSE " << rmse
            << " m, dead reckoning " << dr << " m\n";
  EXPECT_GE(fraction, kMinFractionInBand);
  EXPECT_NEAR(nis, 1.0, 0.1);  // 10000 readings: ~0.015 of sampling spread
  EXPECT_LT(rmse, dr);
  for (const auto& t : trials) {
    EXPECT_TRUE(t.fixed_at_start);
    EXPECT_EQ(t.counters.rejected_ranges(), t.counters.rejected_range_gate);
  }
}

TEST_P(RangeConsistency, SmallestRangeNoise_NeesInBandAndBetterThanDeadReckoning) {
  const auto trials = run_range_trials(GetParam(), smallest_noise_spec(), kNumTrials);
  const double fraction = fraction_in_pose_nees_band(trials, kSettleEpochs);
  const double rmse = range_rmse_m(trials, false, kSettleEpochs);
  const double dr = range_rmse_m(trials, true, kSettleEpochs);
  std::cout << to_string(GetParam()) << " smallest (sigma 1 mm): NEES mean " << mean_nees(trials)
            << ", fraction in band " << fraction << ", RMSE " << rmse << " m, dead reckoning " << dr << " m\n";
  EXPECT_GE(fraction, kMinFractionInBand);
  EXPECT_LT(rmse, dr);
}

TEST_P(RangeConsistency, OverconfidentRangeModel_FailsTheSameCheck) {
  RangeTrialSpec spec;  // 150 epochs, 1000 particles: the failure is gross
  spec.filter.use_observation_std = false;
  spec.filter.filter.noise.sigma_range_m = spec.sim.sigma_range_m / 3.0;
  spec.filter.filter.gate_enabled = false;  // test the consistency check, not the gate
  const auto trials = run_range_trials(GetParam(), spec, kNumTrials);
  const double fraction = fraction_in_pose_nees_band(trials, kSettleEpochs);
  std::cout << to_string(GetParam()) << " overconfident: fraction in band " << fraction << "\n";
  EXPECT_LT(fraction, kMinFractionInBand);
}

INSTANTIATE_TEST_SUITE_P(BothFilters, RangeConsistency, ::testing::Values(FilterKind::kEkf, FilterKind::kParticle),
                         [](const auto& info) { return to_string(info.param); });

}  // namespace
}  // namespace losmimo::localization
