// Sliding-window refinement (fusion/refinement.h) on simulated windows: seeded, never retried.
#include "losmimo/fusion/refinement.h"

#include "fusion/window_simulator.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

namespace losmimo::fusion {
namespace {

using test_support::draw_window;
using test_support::DrawnWindow;
using test_support::kPriorSigma_m;
constexpr int kMonteCarloRuns = 500;
constexpr int kStateDim = 3;
constexpr double kZ975 = 1.959963985;  // standard normal 0.975 quantile

// Chi-square quantile with k dof at standard-normal quantile z (Wilson-Hilferty; relative error
// < 1e-4 for k in the hundreds).
double chi2_quantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}
// 95% two-sided band of the average NEES over kMonteCarloRuns runs.
const double kNeesLow = chi2_quantile(kStateDim * kMonteCarloRuns, -kZ975) / kMonteCarloRuns;
const double kNeesHigh = chi2_quantile(kStateDim * kMonteCarloRuns, kZ975) / kMonteCarloRuns;

TEST(Chi2Quantile, MatchesTabulatedValues) {
  // chi2 with 600 and 1500 dof at 0.025 / 0.975, by bisection on the series of the regularised
  // incomplete gamma function: 534.019 / 669.769 and 1394.555 / 1609.233.
  EXPECT_NEAR(chi2_quantile(600, -kZ975), 534.019, 0.05);
  EXPECT_NEAR(chi2_quantile(600, kZ975), 669.769, 0.05);
  EXPECT_NEAR(chi2_quantile(1500, -kZ975), 1394.555, 0.05);
  EXPECT_NEAR(chi2_quantile(1500, kZ975), 1609.233, 0.05);
}

// The hardest case: beacon angle noise 1.8e-4 rad (0.18 m cross-range at 1 km, the
// paper's largest sigma_loc); range and dead reckoning as localization's defaults.
RefinementConfig largest_beacon_noise_config(const placement::Scenario& scenario) {
  localization::NoiseModel noise;
  noise.sigma_angle_rad = 1.8e-4;
  return refinement_config_from(noise, scenario.noise_variance());
}

double nees(const RefinementResult& r, const Eigen::Vector3d& truth_m) {
  const Eigen::Vector3d e = r.belief.mean_m - truth_m;
  return e.dot(r.belief.cov_m2.ldlt().solve(e));
}

double lateral_sq(const Eigen::Vector3d& estimate_m, const Eigen::Vector3d& truth_m) {
  return (estimate_m - truth_m).tail<2>().squaredNorm();
}

TEST(RefinementConfig, BadField_ThrowsNamingFieldAndValue) {
  RefinementConfig c;
  c.dr_sigma_floor_m = -0.5;
  try {
    validate(c);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dr_sigma_floor_m = -0.5"), std::string::npos) << e.what();
  }
  RefinementConfig w;
  w.window_epochs = 0;
  EXPECT_THROW(validate(w), std::invalid_argument);
  RefinementConfig v;
  v.csi_noise_variance = std::nan("");
  EXPECT_THROW(validate(v), std::invalid_argument);
  EXPECT_NO_THROW(validate(RefinementConfig{}));
}

TEST(RefineWindow, ExactMeasurements_RecoverEveryPosition) {
  const placement::ChannelModel model(placement::Scenario{});
  const RefinementConfig config;
  std::mt19937_64 rng(31);
  const DrawnWindow w = draw_window(model, config, config.window_epochs, rng, /*noise_scale=*/0.0);
  // Start the solver away from the truth: the prior mean is off by 10 cm laterally.
  std::vector<RefinementEpoch> epochs = w.epochs;
  epochs.front().filter_belief.mean_m += Eigen::Vector3d(0.0, 0.1, -0.1);
  const RefinementResult r = refine_window(model, config, epochs);
  EXPECT_EQ(r.covariance_source, CovarianceSource::kCeres);
  EXPECT_EQ(r.num_epochs, config.window_epochs);
  EXPECT_EQ(r.num_beacons, config.window_epochs - 1);
  EXPECT_EQ(r.num_csi, config.window_epochs);
  // The perturbed prior is the only inconsistent term; CSI and beacons pull the lateral back.
  EXPECT_LT((r.belief.mean_m - w.truth_m.col(config.window_epochs - 1)).tail<2>().norm(), 0.03);
}

TEST(RefineWindow, MissingDisplacement_Throws) {
  const placement::ChannelModel model(placement::Scenario{});
  const RefinementConfig config;
  std::mt19937_64 rng(32);
  DrawnWindow w = draw_window(model, config, 3, rng);
  w.epochs[2].displacement_m.reset();
  EXPECT_THROW(refine_window(model, config, w.epochs), std::invalid_argument);
  EXPECT_THROW(refine_window(model, config, {}), std::invalid_argument);
}

TEST(RefineWindow, LostFilterWithoutBeaconOrCsi_FallsBackToDeadReckoningCovariance) {
  // GIVEN: a lost filter (prior variance 1e16 m^2) and neither beacon nor CSI: only dead
  // reckoning, which observes no absolute position.
  const placement::ChannelModel model(placement::Scenario{});
  RefinementConfig config;
  config.use_beacons = false;
  config.use_csi = false;
  std::mt19937_64 rng(33);
  DrawnWindow w = draw_window(model, config, config.window_epochs, rng);
  w.epochs.front().filter_belief.cov_m2 = 1e16 * Eigen::Matrix3d::Identity();
  // WHEN
  const RefinementResult r = refine_window(model, config, w.epochs);
  // THEN: the covariance is the prior carried by dead reckoning, flagged and degraded.
  EXPECT_EQ(r.covariance_source, CovarianceSource::kDeadReckoning);
  EXPECT_TRUE(r.belief.degraded);
  Eigen::Matrix3d expected = w.epochs.front().filter_belief.cov_m2;
  for (int i = 1; i < config.window_epochs; ++i) {
    const double s = config.dr_sigma_floor_m + config.dr_sigma_fraction * w.epochs[i].displacement_m->norm();
    expected += s * s * Eigen::Matrix3d::Identity();
  }
  EXPECT_TRUE(r.belief.cov_m2.isApprox(expected, 1e-12));
}

TEST(RefineWindow, LostFilterWithCsiOnly_ObservesLateralButHardlyDepth) {
  // GIVEN: the same lost filter, no beacon, but CSI at every epoch.
  const placement::ChannelModel model(placement::Scenario{});
  RefinementConfig config;
  config.use_beacons = false;
  std::mt19937_64 rng(36);
  DrawnWindow w = draw_window(model, config, config.window_epochs, rng);
  w.epochs.front().filter_belief.cov_m2 = 1e16 * Eigen::Matrix3d::Identity();
  // Start the solver near the truth: without a prior nothing else anchors the solution.
  w.epochs.front().filter_belief.mean_m = w.truth_m.col(0) + Eigen::Vector3d(0.5, 0.1, -0.1);
  config.csi_max_prior_sigma_m = 1e9;  // lift the wide-prior gate: this start is near the truth
  const RefinementResult r = refine_window(model, config, w.epochs);
  EXPECT_FALSE(r.csi_gated);
  // THEN: a Ceres covariance (the spherical wavefront leaves range weakly observable): tight
  // across the line of sight (CSI measures the direction), tens of metres along it.
  ASSERT_EQ(r.covariance_source, CovarianceSource::kCeres);
  const Eigen::Vector3d u = r.belief.mean_m.normalized();
  const Eigen::Vector3d e1 = u.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d e2 = u.cross(e1);
  EXPECT_LT(std::sqrt(e1.dot(r.belief.cov_m2 * e1)), 0.15);
  EXPECT_LT(std::sqrt(e2.dot(r.belief.cov_m2 * e2)), 0.15);
  EXPECT_GT(std::sqrt(u.dot(r.belief.cov_m2 * u)), 10.0);
  const Eigen::Vector3d error = r.belief.mean_m - w.truth_m.col(config.window_epochs - 1);
  EXPECT_LT(std::hypot(e1.dot(error), e2.dot(error)), 0.5);
}

TEST(RefineWindow, LostFilterWithCsiOnly_DefaultGatesCsiInsteadOfLockingOntoALobe) {
  // GIVEN: a lost filter (lateral 1-sigma 10 m, far wider than CSI's ~+-3 m phase lobes), no
  // beacon, CSI at every epoch, and a mean 4 m off the truth laterally: a wrong lobe is near.
  const placement::ChannelModel model(placement::Scenario{});
  RefinementConfig config;
  config.use_beacons = false;
  std::mt19937_64 rng(36);
  DrawnWindow w = draw_window(model, config, config.window_epochs, rng);
  w.epochs.front().filter_belief.cov_m2 = 100.0 * Eigen::Matrix3d::Identity();
  w.epochs.front().filter_belief.mean_m = w.truth_m.col(0) + Eigen::Vector3d(0.0, 4.0, 0.0);
  const RefinementResult r = refine_window(model, config, w.epochs);
  // THEN: CSI is not used, and the belief stays as wide as the prior says (no false certainty).
  EXPECT_TRUE(r.csi_gated);
  EXPECT_EQ(r.num_csi, 0);
  EXPECT_GT(std::sqrt(r.belief.cov_m2(1, 1)), 5.0);
  EXPECT_GT(std::sqrt(r.belief.cov_m2(2, 2)), 5.0);
}

TEST(SlidingWindowRefiner, KeepsLastWEpochs_AndRestartsAfterGap) {
  const placement::Scenario scenario;
  const placement::ChannelModel model(scenario);
  RefinementConfig config;
  config.window_epochs = 3;
  SlidingWindowRefiner refiner(scenario, config);
  EXPECT_THROW(refiner.refine(), std::logic_error);
  std::mt19937_64 rng(34);
  const DrawnWindow w = draw_window(model, config, 6, rng);
  for (const RefinementEpoch& e : w.epochs) refiner.add_epoch(e);
  EXPECT_EQ(refiner.size(), 3);
  const RefinementResult r = refiner.refine();
  EXPECT_EQ(r.num_epochs, 3);
  // Same answer as the last three epochs solved directly.
  const std::vector<RefinementEpoch> last3(w.epochs.end() - 3, w.epochs.end());
  EXPECT_TRUE(r.belief.mean_m.isApprox(refine_window(model, config, last3).belief.mean_m, 1e-12));
  RefinementEpoch gap = w.epochs.back();
  gap.displacement_m.reset();
  refiner.add_epoch(gap);
  EXPECT_EQ(refiner.size(), 1);
}

// Monte Carlo over seeded windows: the newest position's lateral error of
//   - the prior carried forward by dead reckoning (what a filter that never saw the window's
//     beacons would say),
//   - the refinement without CSI (prior + beacons + dead reckoning: the filter's information),
//   - the refinement with CSI,
// and the NEES of both refinements.
struct MonteCarlo {
  double rmse_dr_m = 0.0, rmse_no_csi_m = 0.0, rmse_csi_m = 0.0;
  double nees_no_csi = 0.0, nees_csi = 0.0;
  double us_per_call_csi = 0.0;
  int fallbacks = 0;
};

MonteCarlo run_monte_carlo(std::uint64_t seed) {
  const placement::Scenario scenario;
  const placement::ChannelModel model(scenario);
  const RefinementConfig with_csi = largest_beacon_noise_config(scenario);
  RefinementConfig without_csi = with_csi;
  without_csi.use_csi = false;
  std::mt19937_64 rng(seed);
  MonteCarlo mc;
  double seconds_csi = 0.0;
  for (int run = 0; run < kMonteCarloRuns; ++run) {
    const DrawnWindow w = draw_window(model, with_csi, with_csi.window_epochs, rng);
    const Eigen::Vector3d truth = w.truth_m.col(with_csi.window_epochs - 1);
    Eigen::Vector3d dr = w.epochs.front().filter_belief.mean_m;
    for (int i = 1; i < with_csi.window_epochs; ++i) dr += *w.epochs[i].displacement_m;
    const auto t0 = std::chrono::steady_clock::now();
    const RefinementResult r_csi = refine_window(model, with_csi, w.epochs);
    seconds_csi += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const RefinementResult r_no = refine_window(model, without_csi, w.epochs);
    mc.fallbacks +=
        (r_csi.covariance_source != CovarianceSource::kCeres) + (r_no.covariance_source != CovarianceSource::kCeres);
    mc.rmse_dr_m += lateral_sq(dr, truth);
    mc.rmse_no_csi_m += lateral_sq(r_no.belief.mean_m, truth);
    mc.rmse_csi_m += lateral_sq(r_csi.belief.mean_m, truth);
    mc.nees_no_csi += nees(r_no, truth);
    mc.nees_csi += nees(r_csi, truth);
  }
  // Lateral RMSE per axis (y and z pooled).
  const double n = kMonteCarloRuns;
  mc.rmse_dr_m = std::sqrt(mc.rmse_dr_m / (2.0 * n));
  mc.rmse_no_csi_m = std::sqrt(mc.rmse_no_csi_m / (2.0 * n));
  mc.rmse_csi_m = std::sqrt(mc.rmse_csi_m / (2.0 * n));
  mc.nees_no_csi /= n;
  mc.nees_csi /= n;
  mc.us_per_call_csi = 1e6 * seconds_csi / n;
  return mc;
}

TEST(RefineWindow, SeededScenario_CsiReducesLateralRmseAndStaysConsistent) {
  // GIVEN: 1 km, 60 GHz, 4x4 BS at 0.25 m, SNR 10 dB, W = 5, prior 0.15 m lateral, beacon
  // 0.18 m cross-range.
  const MonteCarlo mc = run_monte_carlo(35);
  std::cout << "lateral RMSE per axis [m]: dead reckoning " << mc.rmse_dr_m << ", no CSI " << mc.rmse_no_csi_m
            << ", with CSI " << mc.rmse_csi_m << "\naverage NEES (3 dof): no CSI " << mc.nees_no_csi << ", with CSI "
            << mc.nees_csi << " (95% band [" << kNeesLow << ", " << kNeesHigh
            << "])\nrefinement with CSI: " << mc.us_per_call_csi << " us per call\n";
  // THEN: CSI beats both the prior carried forward and the beacon + DR refinement, clearly.
  EXPECT_EQ(mc.fallbacks, 0);
  EXPECT_LT(mc.rmse_csi_m, 0.85 * mc.rmse_no_csi_m);
  EXPECT_LT(mc.rmse_csi_m, 0.5 * mc.rmse_dr_m);
  // AND: both covariances are consistent.
  EXPECT_GT(mc.nees_csi, kNeesLow);
  EXPECT_LT(mc.nees_csi, kNeesHigh);
  EXPECT_GT(mc.nees_no_csi, kNeesLow);
  EXPECT_LT(mc.nees_no_csi, kNeesHigh);
}

}  // namespace
}  // namespace losmimo::fusion
