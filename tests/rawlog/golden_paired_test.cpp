// The golden missions' particle-filter replays judged against the EKF on the same log: the EKF
// is the reference (near-linear beacon model, Gaussian noise: it is close to the exact
// posterior), so a correct PF's NEES and RMSE differ from the EKF's only by its Monte Carlo
// error, which the PF's own spread over filter seeds measures. A PF that stays plausible but is
// wrong (a jitter that inflates the cloud, a resampling that never runs) moves away from the EKF
// by many times that spread while its NEES stays inside the chi-square bands of invariants.ini.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "rawlog/golden_invariants.h"
#include "rawlog/rawlog_test_util.h"

namespace losmimo::rawlog::golden {
namespace {

using test_support::load_log;
using test_support::source_path;

constexpr int kSeeds = 6;

struct Spread {
  double mean = 0.0, sd = 0.0;
};
Spread spread(const std::vector<double>& v) {
  Spread s;
  for (const double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  for (const double x : v) s.sd += (x - s.mean) * (x - s.mean);
  s.sd = std::sqrt(s.sd / static_cast<double>(v.size() - 1));
  return s;
}

class PairedWithEkf : public ::testing::TestWithParam<std::string> {};

TEST_P(PairedWithEkf, PfReplays_DifferFromTheEkfsOnTheSameLog_OnlyByTheirSeedSpread) {
  const MissionLog log = load_log(source_path("datasets/missions/" + GetParam() + "/mission.rawlog"));
  ASSERT_TRUE(log.complete);
  ReplayOptions ekf_options;
  ekf_options.estimator = localization::FilterKind::kEkf;
  ekf_options.refine = false;
  const ReplayResult ekf_run = replay_mission(log, ekf_options);
  const ReplayFigures ekf = figures_of(log, ekf_run);
  // The PF at kSeeds filter seeds (the logged ones, each UAV's shifted by s).
  std::vector<double> nees_diff, rmse_diff, logdet, gap;
  for (int s = 1; s <= kSeeds; ++s) {
    MissionLog seeded = log;
    for (std::uint64_t& seed : seeded.filter_seeds) seed += static_cast<std::uint64_t>(s) * 0x9E3779B97F4A7C15ULL;
    ReplayOptions pf_options = ekf_options;
    pf_options.estimator = localization::FilterKind::kParticle;
    const ReplayResult pf_run = replay_mission(seeded, pf_options);
    const ReplayFigures pf = figures_of(seeded, pf_run);
    double ld = 0.0, g = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < pf_run.estimates.size(); ++i) {
      const localization::Belief& a = pf_run.estimates[i].filter_belief;
      const localization::Belief& b = ekf_run.estimates[i].filter_belief;
      ld += std::log(a.cov_m2.determinant() / b.cov_m2.determinant()) / 3.0;
      const Eigen::Vector3d d = a.mean_m - b.mean_m;
      g += d.dot(b.cov_m2.ldlt().solve(d));
      ++n;
    }
    logdet.push_back(ld / n);
    gap.push_back(g / n);
    nees_diff.push_back(pf.average_nees - ekf.average_nees);
    rmse_diff.push_back(pf.rmse_m - ekf.rmse_m);
  }
  const Spread n = spread(nees_diff), r = spread(rmse_diff), l = spread(logdet), gp = spread(gap);
  std::cout << "[paired] " << GetParam() << ": EKF NEES " << ekf.average_nees << ", RMSE " << ekf.rmse_m
            << " m; PF - EKF over " << kSeeds << " seeds: NEES " << n.mean << " (sd " << n.sd << "), RMSE " << r.mean
            << " m (sd " << r.sd << "); log-det ratio " << l.mean << " (sd " << l.sd << "), mean gap " << gp.mean
            << " (sd " << gp.sd << ")\n";
  // THEN: the PF's covariance is not wider than the reference's beyond its Monte Carlo error. A
  // PF whose jitter keeps the cloud's moments can only lose spread to finite sampling (measured
  // per axis -1.4%, -4.6%, -1.4% in log-det / 3 on nominal, high_beacon_noise, beacon_outage, seed sd
  // 0.005-0.013); the jitter without its shrink inflates it (+3.0% to +3.7%, 8 to 23 standard
  // errors above 0).
  const double se = 1.0 / std::sqrt(static_cast<double>(kSeeds));
  EXPECT_LE(l.mean, 3.0 * l.sd * se) << "the PF's covariance is wider than the EKF's on the same log";
  // ... nor collapsed (a PF a tenth narrower per axis than the exact posterior is degenerate).
  EXPECT_GE(l.mean, -0.1);
  // THEN: its NEES is not below the reference's beyond its Monte Carlo error (measured +0.05 to
  // +0.20; without the shrink -0.05 to -0.06 on the two low-noise missions).
  EXPECT_GE(n.mean, -3.0 * n.sd * se) << "the PF is more pessimistic than the EKF on the same log";
  // THEN: its means stay within the reference's 1-sigma on average (squared Mahalanobis gap,
  // measured 0.03 to 0.30: the Monte Carlo error of the weighted mean).
  EXPECT_LT(gp.mean, 1.0);
}

INSTANTIATE_TEST_SUITE_P(Golden, PairedWithEkf, ::testing::Values("nominal", "high_beacon_noise", "beacon_outage"),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

}  // namespace
}  // namespace losmimo::rawlog::golden
