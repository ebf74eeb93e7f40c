// The MRPT-based particle filter against the EKF on one epoch, and its own options.

#include <gtest/gtest.h>

#include <cmath>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/ekf.h"
#include "losmimo/localization/position/particle_filter.h"

namespace losmimo::localization {
namespace {

Belief prior_at(const Eigen::Vector3d& mean_m, double sigma_m) {
  Belief b;
  b.mean_m = mean_m;
  b.cov_m2 = sigma_m * sigma_m * Eigen::Matrix3d::Identity();
  return b;
}

TEST(ParticleFilter, OneEpochWithManyParticles_MatchesEkfPosterior) {
  // GIVEN: a near-linear problem at 1 km (the EKF is essentially exact there) and 50000
  // particles. THEN: the PF posterior mean and covariance agree with the EKF's within Monte
  // Carlo error.
  constexpr int kParticles = 50000;
  FilterConfig config;
  config.num_particles = kParticles;
  const Belief prior = prior_at({1000.0, 10.0, 20.0}, 0.15);
  const Eigen::Vector3d d(0.5, 0.5, 0.0);
  const BeaconMeasurement z = to_measurement(beacon_predict(prior.mean_m + d + Eigen::Vector3d(0.05, -0.1, 0.08)));
  EkfPositionFilter ekf(config, prior);
  ParticlePositionFilter pf(config, prior, 21);
  ekf.step(d, z);
  pf.step(d, z);
  const Belief e = ekf.belief();
  const Belief p = pf.belief();
  for (int i = 0; i < 3; ++i) {
    const double sigma_m = std::sqrt(e.cov_m2(i, i));
    // Weighted-sample mean error ~ sigma / sqrt(ESS), ESS >= ~5000 here: 0.05 sigma is > 3.5x.
    EXPECT_NEAR(p.mean_m(i), e.mean_m(i), 0.05 * sigma_m) << "axis " << i;
    EXPECT_NEAR(p.cov_m2(i, i), e.cov_m2(i, i), 0.08 * e.cov_m2(i, i)) << "axis " << i;
  }
}

TEST(ParticleFilter, NumParticles_IsHonoured) {
  FilterConfig config;
  config.num_particles = 137;
  ParticlePositionFilter pf(config, prior_at({1000.0, 0.0, 0.0}, 0.2), 1);
  EXPECT_EQ(pf.num_particles(), 137);
  pf.step(Eigen::Vector3d::Zero(), to_measurement(beacon_predict({1000.0, 0.0, 0.0})));
  EXPECT_EQ(pf.num_particles(), 137);
}

TEST(ParticleFilter, EssThreshold_ControlsResampling) {
  // ESS / N < 1 after any informative update, so threshold 1 resamples at every fused beacon;
  // a tiny threshold never does on this short run.
  constexpr int kEpochs = 20;
  const Belief prior = prior_at({1000.0, 0.0, 0.0}, 0.2);
  const BeaconMeasurement z = to_measurement(beacon_predict({1000.0, 0.05, 0.0}));
  FilterConfig always;
  always.ess_threshold = 1.0;
  FilterConfig never;
  never.ess_threshold = 1e-12;
  ParticlePositionFilter a(always, prior, 3);
  ParticlePositionFilter n(never, prior, 3);
  for (int k = 0; k < kEpochs; ++k) {
    a.step(Eigen::Vector3d::Zero(), z);
    n.step(Eigen::Vector3d::Zero(), z);
  }
  EXPECT_EQ(a.counters().resamplings, a.counters().beacons_fused);
  EXPECT_EQ(a.counters().beacons_fused, kEpochs);
  EXPECT_EQ(n.counters().resamplings, 0);
  EXPECT_LT(n.last_normalized_ess(), 0.5);  // it would have needed one
}

TEST(ParticleFilter, EveryResamplingMethod_ConvergesOnTheTruth) {
  const Eigen::Vector3d truth_m(1000.0, 3.0, -4.0);
  for (const auto method : {ResamplingMethod::kMultinomial, ResamplingMethod::kResidual, ResamplingMethod::kStratified,
                            ResamplingMethod::kSystematic}) {
    FilterConfig config;
    config.resampling = method;
    config.ess_threshold = 0.9;
    ParticlePositionFilter pf(config, prior_at(truth_m + Eigen::Vector3d(0.2, -0.2, 0.1), 0.3), 4);
    const BeaconMeasurement z = to_measurement(beacon_predict(truth_m));
    for (int k = 0; k < 30; ++k) pf.step(Eigen::Vector3d::Zero(), z);
    EXPECT_GT(pf.counters().resamplings, 0) << to_string(method);
    // Noise-free beacons on a static UAV: the belief tightens around the truth.
    EXPECT_LT((pf.belief().mean_m - truth_m).norm(), 0.05) << to_string(method);
  }
}

TEST(ParticleFilter, FoldSeed_SpreadsNearbySeeds) {
  EXPECT_NE(fold_seed(1), fold_seed(2));
  EXPECT_NE(fold_seed(0), fold_seed(1ULL << 32U));  // high bits matter too
}

}  // namespace
}  // namespace losmimo::localization
