// Closed-loop EKF consistency: the NEES of the filter's belief against the true position, pooled
// over independent runs, inside its chi-square band; and a filter told half the beacon noise
// fails the same check. Paper scenario (16 UAVs, 4 x 4 BS, 1 km), actuation error 0.02 m,
// default beacon and dead reckoning, matched EKF, no refinement. Seeded, never retried.
//
// Model. Run s (s = 0 .. kRuns - 1) has its own start positions and run seed; inside a run every
// UAV's simulator and filter have their own seeds (closed_loop.h). UAV m at epoch k has the error
// e = mu - q and NEES = e^T P^-1 e; if the filter is consistent (e ~ N(0, P)) NEES ~ chi2(3).
// Independence: runs share nothing; inside a run the UAVs share only the swarm's trajectory,
// which enters a filter through its linearization point and the |d| term of the dead-reckoning
// sigma, never through another UAV's noise. The trajectory itself depends on past errors (GD
// moves from the beliefs), but only through centimetre shifts of where the gradient is taken; we
// treat that feedback as negligible. Then the n = kRuns x 16 errors at one epoch are independent,
// and their average NEES ~ chi2(3 n) / n. (Epochs of one UAV are
// correlated, which is why the band is applied per epoch, never to an average over epochs.)
//
// Check: at every epoch 0 .. kEpochs - 1 the pooled average must lie in the two-sided
// kConfidence band of chi2(3 n) / n (tests/support/chi_square.h: exact quantiles, bisection on the
// regularized gamma function); the filter passes when at least kMinFractionInside of the epochs
// do. If consistent, each epoch is inside with probability 0.99 (0.4 of kEpochs = 40 expected
// outside); 0.9 tolerates 4 epochs outside (the epochs are positively correlated, so excursions
// come in runs of a few), while a filter whose NEES mean is off by more than the band's half
// width (~5%) fails at nearly every epoch.
// The one-run bounds of closed_loop_test.cpp (average NEES in [2, 4.5]) stay as a smoke check;
// this test is the statistical evidence.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <vector>

#include <Eigen/Cholesky>

#include "fusion/closed_loop_fixtures.h"
#include "losmimo/fusion/closed_loop.h"
#include "support/chi_square.h"

namespace losmimo::fusion {
namespace {

using test_support::chi2_average_band;
using test_support::chi2_quantile;
using test_support::Chi2Band;
using test_support::nominal_config;
using test_support::paper_settings;
using test_support::start_positions;

constexpr int kRuns = 100;
constexpr int kEpochs = 40;                 // iteration cap: epochs 0 .. kEpochs - 1 are localized
constexpr double kConfidence = 0.99;        // of the per-epoch band
constexpr double kMinFractionInside = 0.9;  // of the epochs, for a consistent filter
constexpr std::uint64_t kFirstStartSeed = 7000;
constexpr std::uint64_t kFirstRunSeed = 9000;
constexpr int kStateDim = 3;
// The ICN is 1 only for exactly orthogonal channel rows, which a placement with errors never
// reaches: as the target it keeps every run going to the iteration cap.
constexpr double kNeverReachedIcn = 1.0;

// Sums the filter's NEES per epoch over every UAV of the runs it observes.
struct NeesPerEpoch : ClosedLoopObserver {
  std::vector<double> nees_sum = std::vector<double>(kEpochs, 0.0);
  std::vector<int> samples = std::vector<int>(kEpochs, 0);
  void on_epoch(const EpochObservation& o) override {
    if (o.epoch >= kEpochs) return;
    const Eigen::Vector3d e_m = o.filter_belief.mean_m - o.true_position_m;
    nees_sum[o.epoch] += e_m.dot(o.filter_belief.cov_m2.ldlt().solve(e_m));
    ++samples[o.epoch];
  }
};

struct EpochVerdict {
  int epoch = 0;
  int samples = 0;
  double average_nees = 0.0;
  Chi2Band band;
  bool inside = false;
};

// kRuns closed loops of the paper scenario with `config`; the pooled NEES of every epoch.
std::vector<EpochVerdict> pooled_nees(const ClosedLoopConfig& config) {
  placement::PlacementSettings settings = paper_settings(kEpochs);
  settings.run.target_icn = kNeverReachedIcn;  // every run localizes all kEpochs epochs
  NeesPerEpoch observer;
  for (int s = 0; s < kRuns; ++s)
    run_closed_loop(settings, start_positions(settings.scenario, kFirstStartSeed + s), config, kFirstRunSeed + s,
                    &observer);
  std::vector<EpochVerdict> out;
  for (int k = 0; k < kEpochs; ++k) {
    EpochVerdict v;
    v.epoch = k;
    v.samples = observer.samples[k];
    if (v.samples == 0) continue;  // every run converged before epoch k (checked by the caller)
    v.average_nees = observer.nees_sum[k] / v.samples;
    v.band = chi2_average_band(kStateDim, v.samples, kConfidence);
    v.inside = v.band.contains(v.average_nees);
    out.push_back(v);
  }
  return out;
}

double fraction_inside(const std::vector<EpochVerdict>& verdicts, const std::string& label) {
  int inside = 0;
  for (const EpochVerdict& v : verdicts) {
    inside += v.inside;
    std::cout << "[consistency] " << label << " epoch " << v.epoch << ": NEES " << v.average_nees << " over "
              << v.samples << " in [" << v.band.low << ", " << v.band.high << "]" << (v.inside ? "" : "  OUTSIDE")
              << "\n";
  }
  const double fraction = verdicts.empty() ? 0.0 : static_cast<double>(inside) / verdicts.size();
  std::cout << "[consistency] " << label << ": " << inside << " of " << verdicts.size() << " epochs inside the "
            << kConfidence << " band\n";
  return fraction;
}

TEST(ChiSquare, Quantile_MatchesPrintedTables) {
  // Abramowitz & Stegun table 26.8 / NIST handbook 1.3.6.7.4 (3 to 6 significant digits).
  EXPECT_NEAR(chi2_quantile(1, 0.95), 3.841, 1e-3);
  EXPECT_NEAR(chi2_quantile(3, 0.005), 0.0717, 1e-4);
  EXPECT_NEAR(chi2_quantile(3, 0.995), 12.838, 1e-3);
  EXPECT_NEAR(chi2_quantile(10, 0.99), 23.209, 1e-3);
  EXPECT_NEAR(chi2_quantile(100, 0.005), 67.328, 1e-3);
  EXPECT_NEAR(chi2_quantile(100, 0.995), 140.169, 1e-3);
  EXPECT_NEAR(chi2_quantile(100, 0.025), 74.222, 1e-3);
  EXPECT_NEAR(chi2_quantile(100, 0.975), 129.561, 1e-3);
  // Large dof (the pooled bands): Wilson-Hilferty, k (1 - a + z sqrt(a))^3 with a = 2 / (9 k),
  // whose relative error at k = 2400 is below 1e-5.
  const double k = 2400.0, z = 2.5758293035489, a = 2.0 / (9.0 * k);  // z: N(0, 1) at 0.995
  EXPECT_NEAR(chi2_quantile(k, 0.995), k * std::pow(1.0 - a + z * std::sqrt(a), 3), 1e-5 * k);
  EXPECT_NEAR(chi2_quantile(k, 0.005), k * std::pow(1.0 - a - z * std::sqrt(a), 3), 1e-5 * k);
}

TEST(ClosedLoopConsistency, MatchedEkf_PooledNeesInsideTheChi2BandAtMostEpochs) {
  // GIVEN: the EKF assumes the simulator's true beacon and dead-reckoning noise.
  const placement::Scenario scenario;
  const ClosedLoopConfig config = nominal_config(scenario);
  // WHEN
  const std::vector<EpochVerdict> verdicts = pooled_nees(config);
  // THEN: every epoch pooled kRuns x 16 samples (no run stopped before the cap), and the pooled NEES is
  // inside its band at >= kMinFractionInside of the epochs.
  ASSERT_EQ(static_cast<int>(verdicts.size()), kEpochs);
  for (const EpochVerdict& v : verdicts) EXPECT_EQ(v.samples, kRuns * scenario.num_uavs) << v.epoch;
  EXPECT_GE(fraction_inside(verdicts, "matched ekf"), kMinFractionInside);
}

TEST(ClosedLoopConsistency, EkfToldHalfTheBeaconNoise_FailsTheSameCheck) {
  // GIVEN: the filter assumes half the true beacon sigmas (a quarter of the variance): its
  // covariance is too small where the beacon dominates, so its NEES exceeds chi2(3)'s mean.
  const placement::Scenario scenario;
  ClosedLoopConfig config = nominal_config(scenario);
  config.filter.noise.sigma_range_m = 0.5 * config.simulator.sigma_range_m;
  config.filter.noise.sigma_angle_rad = 0.5 * config.simulator.sigma_angle_rad;
  // WHEN
  const std::vector<EpochVerdict> verdicts = pooled_nees(config);
  // THEN: the check that the matched filter passes fails.
  ASSERT_FALSE(verdicts.empty());
  EXPECT_LT(fraction_inside(verdicts, "ekf told half the beacon noise"), kMinFractionInside);
}

}  // namespace
}  // namespace losmimo::fusion
