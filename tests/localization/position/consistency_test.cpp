// Statistical tests of both filters on the seeded nominal trial (trial_runner.h): NEES
// consistency, accuracy against each other and against the two single-sensor baselines.
// Seeded, never retried: every number below is reproducible.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "localization/position/trial_runner.h"

namespace losmimo::localization {
namespace {

using test_support::fraction_of_epochs_in_nees_band;
using test_support::rmse_m;
using test_support::run_trials;
using test_support::TrialResult;
using test_support::TrialSpec;

constexpr int kNumTrials = 50;
constexpr double kMinFractionInBand = 0.90;
// The band fraction of a consistent filter is ~0.95 but epochs are correlated (filter memory of
// a few epochs), so over 100 epochs it varies by ~0.04 from one seed set to the next; 200
// epochs halve that. The particle filter runs 2000 particles here: at 1000 its Monte Carlo
// error raises the mean NEES by ~3-4% over the EKF's and the fraction becomes marginal
// (0.89-0.96 over four seed sets, against 0.91-0.97 at 2000).
constexpr int kConsistencyEpochs = 200;
constexpr int kConsistencyParticles = 2000;

double mean_nees(const std::vector<TrialResult>& trials) {
  double sum = 0.0;
  int n = 0;
  for (const auto& t : trials) {
    for (const double v : t.nees) {
      sum += v;
      ++n;
    }
  }
  return sum / n;
}

// The pooled check: the NEES averaged over every run and epoch against chi-square. Runs are
// independent, a run's epochs are not: at worst (every run's epochs fully correlated) R times the
// pooled mean is chi2(3 R), so its 99% band [chi2(3R) at 0.5%, at 99.5%] / R holds a consistent
// filter whatever the correlation (R = 50: [2.18, 3.97]). An overconfident filter (NEES 4.6,
// accepted by the per-epoch fraction at a marginal seed set) or a pessimistic one falls outside.
struct Pooled {
  double mean = 0.0, lo = 0.0, hi = 0.0;
  bool inside() const { return mean >= lo && mean <= hi; }
};
Pooled pooled_nees(const std::vector<TrialResult>& trials) {
  constexpr double kZ995 = 2.5758;
  const double r = static_cast<double>(trials.size());
  return {mean_nees(trials), test_support::chi2_quantile(3.0 * r, -kZ995) / r,
          test_support::chi2_quantile(3.0 * r, kZ995) / r};
}

TrialSpec consistency_spec() {
  TrialSpec spec;
  spec.num_epochs = kConsistencyEpochs;
  spec.filter.num_particles = kConsistencyParticles;
  return spec;
}
// A wrong noise model: the filter trusts both sensors this many times more than it should.
constexpr double kOverconfidenceFactor = 3.0;

class Consistency : public ::testing::TestWithParam<FilterKind> {};

TEST_P(Consistency, NominalNoise_AverageNeesInside95BandOn90PercentOfEpochs) {
  // GIVEN: 50 seeded trials, the filter's noise model equal to the simulator's.
  const auto trials = run_trials(GetParam(), consistency_spec(), kNumTrials);
  // THEN: the run-averaged NEES is inside the chi2(3 N)/N 95% band on >= 90% of epochs.
  const double fraction = fraction_of_epochs_in_nees_band(trials);
  const Pooled pooled = pooled_nees(trials);
  std::cout << to_string(GetParam()) << ": fraction of epochs in NEES band = " << fraction << ", pooled NEES "
            << pooled.mean << " in [" << pooled.lo << ", " << pooled.hi << "]\n";
  EXPECT_GE(fraction, kMinFractionInBand);
  // AND: the pooled NEES is inside its chi-square band.
  EXPECT_TRUE(pooled.inside()) << pooled.mean;
}

TEST_P(Consistency, OverconfidentNoiseModel_FailsTheSameCheck) {
  // GIVEN: the filter believes sigmas kOverconfidenceFactor times smaller than the truth.
  TrialSpec spec = consistency_spec();
  spec.filter.noise.sigma_range_m /= kOverconfidenceFactor;
  spec.filter.noise.sigma_angle_rad /= kOverconfidenceFactor;
  spec.filter.noise.dr_sigma_floor_m /= kOverconfidenceFactor;
  spec.filter.noise.dr_sigma_fraction /= kOverconfidenceFactor;
  spec.filter.gate_enabled = false;  // test the consistency check, not the gate
  const auto trials = run_trials(GetParam(), spec, kNumTrials);
  const double fraction = fraction_of_epochs_in_nees_band(trials);
  const Pooled pooled = pooled_nees(trials);
  std::cout << to_string(GetParam()) << ": overconfident, fraction in band = " << fraction << ", pooled NEES "
            << pooled.mean << "\n";
  EXPECT_LT(fraction, kMinFractionInBand);
  EXPECT_GT(pooled.mean, pooled.hi);  // and the pooled check says which way
}

TEST_P(Consistency, PessimisticNoiseModel_FailsTheSameCheck) {
  // GIVEN: the filter believes sigmas kOverconfidenceFactor times larger than the truth.
  TrialSpec spec = consistency_spec();
  spec.filter.noise.sigma_range_m *= kOverconfidenceFactor;
  spec.filter.noise.sigma_angle_rad *= kOverconfidenceFactor;
  spec.filter.noise.dr_sigma_floor_m *= kOverconfidenceFactor;
  spec.filter.noise.dr_sigma_fraction *= kOverconfidenceFactor;
  const auto trials = run_trials(GetParam(), spec, kNumTrials);
  const double fraction = fraction_of_epochs_in_nees_band(trials);
  const Pooled pooled = pooled_nees(trials);
  std::cout << to_string(GetParam()) << ": pessimistic, fraction in band = " << fraction << ", pooled NEES "
            << pooled.mean << "\n";
  EXPECT_LT(fraction, kMinFractionInBand);
  EXPECT_LT(pooled.mean, pooled.lo);
}

TEST_P(Consistency, SmallestBeaconNoise_AverageNeesInside95BandOn90PercentOfEpochs) {
  // GIVEN: the smallest beacon noise a filter represents, its angle floor (1e-6 rad: a 1 mm
  // lateral 1-sigma at 1 km, far below the centimetres of dead-reckoning noise per epoch), in
  // truth and in the model. The particle filter's optimal proposal is what keeps it consistent.
  TrialSpec spec = consistency_spec();
  spec.sim.sigma_angle_rad = spec.filter.min_sigma_angle_rad;
  spec.filter.noise.sigma_angle_rad = spec.filter.min_sigma_angle_rad;
  const auto trials = run_trials(GetParam(), spec, kNumTrials);
  const double fraction = fraction_of_epochs_in_nees_band(trials);
  const Pooled pooled = pooled_nees(trials);
  std::cout << to_string(GetParam()) << ": smallest beacon noise, pooled NEES " << pooled.mean << " in [" << pooled.lo
            << ", " << pooled.hi << "], fraction of epochs in NEES band = " << fraction << "\n";
  EXPECT_GE(fraction, kMinFractionInBand);
  if (GetParam() == FilterKind::kEkf) {
    EXPECT_TRUE(pooled.inside()) << pooled.mean;
  } else {
    // Known: here the particle filter is overconfident by half (pooled NEES 4.61 with these
    // seeds, outside [2.18, 3.97], while 93% of its epochs are inside the per-epoch band): a few
    // epochs' clouds are far narrower than a 1 mm posterior needs (docs/localization.md). Bounded
    // so that it gets no worse; a PF that fixes it fails this line and should take the EKF's.
    EXPECT_GT(pooled.mean, pooled.hi);
    EXPECT_LT(pooled.mean, 5.0);
  }
}

TEST(ZeroBeaconNoise, PfNeesAsTheEkfs) {
  // GIVEN: the co-evaluation's beacon noise 0: a noise-free angle, the filters floored at 1e-6.
  // Both are then pessimistic laterally (NEES below 3); the particle filter must be as
  // consistent as the EKF, not collapse (its NEES was ~1e6 with the motion model as proposal).
  TrialSpec spec = consistency_spec();
  spec.sim.sigma_angle_rad = 0.0;
  spec.filter.noise.sigma_angle_rad = spec.filter.min_sigma_angle_rad;
  const double ekf = mean_nees(run_trials(FilterKind::kEkf, spec, kNumTrials));
  const double pf = mean_nees(run_trials(FilterKind::kParticle, spec, kNumTrials));
  std::cout << "beacon noise 0: mean NEES ekf = " << ekf << ", pf = " << pf << "\n";
  EXPECT_LT(pf, 1.5 * ekf);
  EXPECT_GT(pf, ekf / 1.5);
}

INSTANTIATE_TEST_SUITE_P(BothFilters, Consistency, ::testing::Values(FilterKind::kEkf, FilterKind::kParticle),
                         [](const auto& info) { return to_string(info.param); });

TEST(NeesBand, WilsonHilferty_MatchesChiSquareTable) {
  // Independent check of the band itself: chi2(100) quantiles from a printed table.
  constexpr double kZ975 = 1.959963985;
  constexpr double kChi2_100_025 = 74.222;
  constexpr double kChi2_100_975 = 129.561;
  EXPECT_NEAR(test_support::chi2_quantile(100.0, -kZ975), kChi2_100_025, 0.1);
  EXPECT_NEAR(test_support::chi2_quantile(100.0, kZ975), kChi2_100_975, 0.1);
}

// Accuracy on the nominal trial, after the first kSettleEpochs (both start from the same prior).
constexpr int kSettleEpochs = 10;

double dead_reckoning_rmse_m(const std::vector<TrialResult>& trials) {
  double sum = 0.0;
  int n = 0;
  for (const auto& t : trials) {
    for (std::size_t k = kSettleEpochs; k < t.dr_error_m.size(); ++k) {
      sum += t.dr_error_m[k].squaredNorm();
      ++n;
    }
  }
  return std::sqrt(sum / n);
}

double beacon_only_rmse_m(const std::vector<TrialResult>& trials) {
  double sum = 0.0;
  int n = 0;
  for (const auto& t : trials) {
    for (std::size_t k = kSettleEpochs; k < t.fix_error_m.size(); ++k) {
      if (!t.fix_error_m[k]) continue;
      sum += t.fix_error_m[k]->squaredNorm();
      ++n;
    }
  }
  return std::sqrt(sum / n);
}

TEST(Accuracy, EkfAndPf_RmseAgreeWithin20Percent) {
  constexpr double kMaxRelativeGap = 0.20;
  const TrialSpec spec;
  const double ekf_m = rmse_m(run_trials(FilterKind::kEkf, spec, kNumTrials), kSettleEpochs);
  const double pf_m = rmse_m(run_trials(FilterKind::kParticle, spec, kNumTrials), kSettleEpochs);
  std::cout << "RMSE ekf = " << ekf_m << " m, pf = " << pf_m << " m\n";
  EXPECT_LE(std::abs(ekf_m - pf_m), kMaxRelativeGap * std::min(ekf_m, pf_m));
}

TEST(Accuracy, BothFilters_BeatDeadReckoningAndBeaconOnly) {
  const TrialSpec spec;
  for (const FilterKind kind : {FilterKind::kEkf, FilterKind::kParticle}) {
    const auto trials = run_trials(kind, spec, kNumTrials);
    const double filter_m = rmse_m(trials, kSettleEpochs);
    const double dr_m = dead_reckoning_rmse_m(trials);
    const double fix_m = beacon_only_rmse_m(trials);
    std::cout << to_string(kind) << ": RMSE filter = " << filter_m << " m, dead reckoning = " << dr_m
              << " m, beacon only = " << fix_m << " m\n";
    EXPECT_LT(filter_m, dr_m) << to_string(kind);
    EXPECT_LT(filter_m, fix_m) << to_string(kind);
  }
}

TEST(Accuracy, BeaconOnlyFix_IsAbout10cmPerAxisAt1km) {
  // The documented default: sigma_angle_rad = 1e-4 and sigma_range_m = 0.1 give ~0.1 m per
  // axis, i.e. a 3-D RMSE of ~0.1 sqrt(3) m at 1 km.
  constexpr double kExpected3dRmse_m = 0.1 * 1.7320508;
  constexpr double kRelativeTolerance = 0.05;
  const auto trials = run_trials(FilterKind::kEkf, TrialSpec{}, kNumTrials);
  EXPECT_NEAR(beacon_only_rmse_m(trials), kExpected3dRmse_m, kRelativeTolerance * kExpected3dRmse_m);
}

}  // namespace
}  // namespace losmimo::localization
