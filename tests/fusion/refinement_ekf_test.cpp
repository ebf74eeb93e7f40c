// The refinement closing the loop on localization's own EKF and sensor simulator (
// "refinement reduces lateral RMSE versus the filter alone"). Seeded, never retried.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <iostream>
#include <random>

#include "losmimo/fusion/refinement.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/filter.h"
#include "losmimo/localization/position/simulator.h"

namespace losmimo::fusion {
namespace {

constexpr int kRuns = 200;
constexpr int kEpochs = 12;  // per run; the refiner keeps the last W = 5
constexpr double kZ975 = 1.959963985;

double chi2_quantile(double k, double z) {  // Wilson-Hilferty, see refinement_test.cpp
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}

double nees(const localization::Belief& b, const Eigen::Vector3d& truth_m) {
  const Eigen::Vector3d e = b.mean_m - truth_m;
  return e.dot(b.cov_m2.ldlt().solve(e));
}

TEST(RefinementOnEkf, LargestBeaconNoise_CsiCutsLateralRmseOfTheFilterAndStaysConsistent) {
  // GIVEN: the default scenario, a UAV flying placement-sized steps, localization's simulator
  // (beacon 0.18 m cross-range, its default range and dead-reckoning noise) and its EKF; the
  // UAV measures its CSI row every epoch.
  const placement::Scenario scenario;
  const placement::ChannelModel model(scenario);
  localization::SimulatorConfig sim_config;
  sim_config.sigma_angle_rad = 1.8e-4;
  localization::FilterConfig filter_config;
  filter_config.noise.sigma_range_m = sim_config.sigma_range_m;
  filter_config.noise.sigma_angle_rad = sim_config.sigma_angle_rad;
  filter_config.noise.dr_sigma_floor_m = sim_config.dr_sigma_floor_m;
  filter_config.noise.dr_sigma_fraction = sim_config.dr_sigma_fraction;
  const RefinementConfig config = refinement_config_from(filter_config.noise, scenario.noise_variance());

  std::mt19937_64 rng(51);
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> cube(-25.0, 25.0);
  std::uniform_real_distribution<double> step_len(0.1, 1.0);
  double sq_ekf = 0.0, sq_refined = 0.0, nees_ekf = 0.0, nees_refined = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    localization::SensorSimulator sim(sim_config, 1000 + run);
    Eigen::Vector3d q(1000.0 + cube(rng), cube(rng), cube(rng));
    const std::optional<localization::BeaconMeasurement> z0 = sim.measure_beacon(q, 0);
    ASSERT_TRUE(z0.has_value());
    const localization::Belief initial =
        localization::beacon_fix(*z0, sim_config.sigma_range_m, sim_config.sigma_angle_rad);
    const auto ekf = localization::make_filter(localization::FilterKind::kEkf, filter_config, initial, 7);
    SlidingWindowRefiner refiner(scenario, config);
    refiner.add_epoch({initial, std::nullopt, z0, {simulate_csi(model, q, scenario.noise_variance(), rng)}});
    for (int k = 1; k < kEpochs; ++k) {
      const Eigen::Vector3d d = step_len(rng) * Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized();
      q += d;
      const Eigen::Vector3d d_meas = sim.measure_displacement(d);
      const std::optional<localization::BeaconMeasurement> z = sim.measure_beacon(q, k);
      ekf->step(d_meas, z);
      refiner.add_epoch({ekf->belief(), d_meas, z, {simulate_csi(model, q, scenario.noise_variance(), rng)}});
    }
    // WHEN
    const RefinementResult r = refiner.refine();
    ASSERT_EQ(r.covariance_source, CovarianceSource::kCeres);
    const localization::Belief filter = ekf->belief();
    sq_ekf += (filter.mean_m - q).tail<2>().squaredNorm();
    sq_refined += (r.belief.mean_m - q).tail<2>().squaredNorm();
    nees_ekf += nees(filter, q);
    nees_refined += nees(r.belief, q);
  }
  const double rmse_ekf = std::sqrt(sq_ekf / (2.0 * kRuns));
  const double rmse_refined = std::sqrt(sq_refined / (2.0 * kRuns));
  nees_ekf /= kRuns;
  nees_refined /= kRuns;
  const double low = chi2_quantile(3.0 * kRuns, -kZ975) / kRuns;
  const double high = chi2_quantile(3.0 * kRuns, kZ975) / kRuns;
  std::cout << "lateral RMSE per axis [m]: EKF " << rmse_ekf << ", EKF + CSI refinement " << rmse_refined
            << "\naverage NEES: EKF " << nees_ekf << ", refined " << nees_refined << " (95% band [" << low << ", "
            << high << "])\n";
  // THEN: CSI cuts the filter's lateral error and the refined covariance is consistent.
  // Expected ratio, from the information alone: the EKF's lateral variance after 12 beacons
  // (~0.065^2 m^2) fused with five CSI rows (~0.16 m each per axis, csi.h) is ~0.74 of its RMSE.
  EXPECT_LT(rmse_refined, 0.85 * rmse_ekf);
  EXPECT_GT(nees_refined, low);
  EXPECT_LT(nees_refined, high);
}

}  // namespace
}  // namespace losmimo::fusion
