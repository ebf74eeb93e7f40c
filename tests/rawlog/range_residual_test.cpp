// The replay's post-fit range residual RMS covers the ranges the filter fused; gated outliers are
// counted (skipped_gate), not scored.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Core>

#include "losmimo/fusion/rawlog/mrpt_logs/range_replay.h"

namespace losmimo::mrpt_logs {
namespace {

using localization::FilterKind;

TEST(RangeReplayResidual, GrossOutliers_AreGatedAndLeftOutOfTheResidualRms) {
  // GIVEN: a straight path past four beacons, ranges with 2 cm noise, and every 4th frame from
  // frame 8 on a reading of beacon 10 that is 3 m too long.
  constexpr int kFrames = 60;
  constexpr double kSigma_m = 0.02;
  constexpr double kOutlier_m = 3.0;
  const std::vector<Eigen::Vector3d> beacons = {{-3.0, -2.0, 1.0}, {6.0, -1.0, 0.5}, {5.0, 7.0, 2.0}, {-2.0, 6.0, 0.0}};
  localization::BeaconMap map;
  for (std::size_t b = 0; b < beacons.size(); ++b) map.add(static_cast<std::int32_t>(b + 10), beacons[b]);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, kSigma_m);
  RangeLog log;
  int outliers = 0;
  for (int k = 0; k < kFrames; ++k) {
    const Eigen::Vector3d p(0.1 * k, 0.5, 0.0);  // heading 0, 0.1 m per frame along x
    RangeFrame f;
    f.step = k;
    f.timestamp_s = k;
    if (k > 0) {
      f.has_odometry = true;
      f.odometry.delta = Eigen::Vector4d(0.1, 0.0, 0.0, 0.0);
      f.odometry.cov = Eigen::Vector4d(1e-4, 1e-4, 1e-8, 1e-6).asDiagonal();
    }
    localization::BeaconRangeScan scan;
    scan.std_error_m = kSigma_m;
    for (std::size_t b = 0; b < beacons.size(); ++b) {
      localization::BeaconRange r;
      r.beacon_id = static_cast<std::int32_t>(b + 10);
      r.range_m = (p - beacons[b]).norm() + noise(rng);
      if (b == 0 && k >= 8 && k % 4 == 0) {
        r.range_m += kOutlier_m;
        ++outliers;
      }
      scan.ranges.push_back(r);
    }
    f.scans.push_back(scan);
    log.frames.push_back(f);
    ++log.beacon_observations;
    log.ranges += static_cast<std::int64_t>(beacons.size());
  }
  for (const FilterKind kind : {FilterKind::kEkf, FilterKind::kParticle}) {
    RangeReplayOptions o;
    o.estimator = kind;
    o.config.use_observation_std = true;
    localization::PoseBelief start;
    start.mean = Eigen::Vector4d(0.0, 0.5, 0.0, 0.0);
    start.cov = Eigen::Vector4d(0.01, 0.01, 1e-6, 1e-3).asDiagonal();
    o.prior = start;
    const RangeReplayResult r = replay_ranges(log, map, o);
    // THEN: every outlier is gated, every other reading fused, and the residual RMS is over
    // exactly the fused readings and within 2 sigma.
    EXPECT_EQ(r.counters.rejected_range_gate, outliers) << to_string(kind);
    EXPECT_EQ(r.counters.ranges_fused, log.ranges - outliers) << to_string(kind);
    EXPECT_EQ(r.residuals, r.counters.ranges_fused) << to_string(kind);
    EXPECT_LT(r.residual_rms_settled_m, 2.0 * kSigma_m) << to_string(kind);
    // AND: scored over every reading instead (the outliers included), the RMS is far larger.
    double sq = 0.0;
    int n = 0;
    for (std::size_t k = static_cast<std::size_t>(o.settle_steps); k < r.track.size(); ++k)
      for (const localization::BeaconRange& b : log.frames[k].scans[0].ranges) {
        const double e = b.range_m - localization::range_predict(r.track[k].belief.mean, b.sensor_on_robot_m,
                                                                 *map.find(b.beacon_id));
        sq += e * e;
        ++n;
      }
    EXPECT_GT(std::sqrt(sq / n), 10.0 * r.residual_rms_settled_m) << to_string(kind);
  }
}

}  // namespace
}  // namespace losmimo::mrpt_logs
