// The epoch-0 pose (initial_pose.h): the fix-or-prior rule with its counters, and the moments the
// EKF starts from against the sample moments of the distribution the particle filter draws.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/pose/initial_pose.h"

namespace losmimo::localization {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kDraws = 100000;

BeaconMap square_map() {
  BeaconMap map;
  map.add(1, {0.0, 0.0, 2.5});
  map.add(2, {10.0, 0.0, 0.5});
  map.add(3, {10.0, 8.0, 3.0});
  map.add(4, {0.0, 8.0, 1.0});
  return map;
}

BeaconRangeScan scan_from(const BeaconMap& map, const Eigen::Vector4d& pose, const Eigen::Vector3d& s) {
  BeaconRangeScan scan;
  for (const auto& [id, b] : map.beacons()) scan.ranges.push_back({id, range_predict(pose, s, b), s});
  return scan;
}

// Sample mean (circular heading) and covariance of draws of sample_initial_pose.
void sample_moments(const InitialPose& initial, Eigen::Vector4d& mean, Eigen::Matrix4d& cov) {
  mrpt::random::CRandomGenerator rng(7);
  std::vector<Eigen::Vector4d> x(kDraws);
  double s = 0.0, c = 0.0;
  for (auto& xi : x) {
    xi = sample_initial_pose(initial, rng);
    s += std::sin(xi(kPoseYaw));
    c += std::cos(xi(kPoseYaw));
  }
  mean.setZero();
  for (const auto& xi : x) mean.head<3>() += xi.head<3>() / kDraws;
  mean(kPoseYaw) = std::atan2(s, c);
  cov.setZero();
  for (const auto& xi : x) {
    Eigen::Vector4d e = xi - mean;
    e(kPoseYaw) = wrap_angle_rad(e(kPoseYaw));
    cov += e * e.transpose() / kDraws;
  }
}

TEST(InitialPose, BoxPrior_MomentsMatchItsSamples) {
  PoseBox box;
  box.min = Eigen::Vector4d(-1.0, 2.0, 0.0, -0.3);
  box.max = Eigen::Vector4d(1.0, 5.0, 0.0, 0.5);
  const InitialPose initial = initial_pose(box);
  Eigen::Vector4d mean;
  Eigen::Matrix4d cov;
  sample_moments(initial, mean, cov);
  const PoseBelief m = moments(initial);
  EXPECT_LT((mean - m.mean).norm(), 0.02);
  for (const int i : {kPoseX, kPoseY, kPoseYaw}) EXPECT_NEAR(cov(i, i), m.cov(i, i), 0.02 * m.cov(i, i)) << i;
  EXPECT_EQ(m.cov(kPoseZ, kPoseZ), 0.0);  // a zero-width axis stays exact
}

TEST(InitialPose, RangeFixWithHeadingPrior_MomentsMatchItsSamples) {
  // GIVEN: four beacons, an offset sensor, a box prior with a +-0.2 rad heading.
  const BeaconMap map = square_map();
  const Eigen::Vector3d s(0.4, 0.1, 0.6);
  const Eigen::Vector4d truth(3.0, 4.0, 0.0, 0.1);
  PoseBox box;
  box.min = Eigen::Vector4d(0.0, 0.0, -0.5, -0.1);
  box.max = Eigen::Vector4d(6.0, 8.0, 0.5, 0.3);
  PoseFilterConfig config;
  config.filter.noise.sigma_range_m = 0.02;
  const InitialPose initial = initial_pose({scan_from(map, truth, s)}, map, config, box);
  // THEN: a fix is taken, every reading fused; its moments match the sampled distribution.
  ASSERT_TRUE(initial.fix) << initial.note;
  EXPECT_EQ(initial.counters.ranges_received, 4);
  EXPECT_EQ(initial.counters.ranges_fused, 4);
  EXPECT_LT((initial.fix->fix.sensor_m - sensor_position_m(truth, s)).norm(), 0.01);
  Eigen::Vector4d mean;
  Eigen::Matrix4d cov;
  sample_moments(initial, mean, cov);
  const PoseBelief m = moments(initial);
  EXPECT_LT((mean - m.mean).norm(), 0.01);
  // First order in the heading spread (0.115 rad 1-sigma): 3% on the variances, 5% on x-yaw.
  for (int i = 0; i < kPoseSize; ++i) EXPECT_NEAR(cov(i, i), m.cov(i, i), 0.03 * m.cov(i, i)) << i;
  EXPECT_NEAR(cov(kPoseX, kPoseYaw), m.cov(kPoseX, kPoseYaw), 0.05 * std::abs(m.cov(kPoseX, kPoseYaw)));
}

TEST(InitialPose, TooFewOrUnusableReadings_ThePriorAndTheReasons) {
  const BeaconMap map = square_map();
  const Eigen::Vector4d truth(3.0, 4.0, 0.0, 0.0);
  BeaconRangeScan scan = scan_from(map, truth, Eigen::Vector3d::Zero());
  scan.ranges[0].beacon_id = 42;                                      // unknown
  scan.ranges[1].range_m = std::numeric_limits<double>::quiet_NaN();  // non-finite
  scan.ranges[2].range_m = 2.0 * scan.max_sensor_distance_m;          // outside the limits
  PoseBelief prior;
  prior.mean = Eigen::Vector4d(2.0, 3.0, 0.0, 0.0);
  prior.cov = Eigen::Vector4d(4.0, 4.0, 1.0, 0.1).asDiagonal();
  const InitialPose initial = initial_pose({scan}, map, PoseFilterConfig{}, prior);
  EXPECT_FALSE(initial.fix);
  EXPECT_NE(initial.note.find("1 usable range(s) < min_ranges_for_fix = 3"), std::string::npos) << initial.note;
  EXPECT_EQ(initial.counters.ranges_received, 4);
  EXPECT_EQ(initial.counters.rejected_unknown_beacon, 1);
  EXPECT_EQ(initial.counters.rejected_non_finite_range, 1);
  EXPECT_EQ(initial.counters.rejected_outside_sensor_limits, 1);
  EXPECT_EQ(initial.counters.ranges_fused, 0);
  EXPECT_EQ(initial.usable_ranges_not_fused, 1);
  EXPECT_EQ(moments(initial).mean, prior.mean);
}

TEST(InitialPose, BadPrior_NamesTheField) {
  PoseBox box;
  box.min = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);  // min_x > max_x
  EXPECT_THROW(initial_pose(box), std::invalid_argument);
  box.min = Eigen::Vector4d(0.0, 0.0, 0.0, -4.0);
  box.max = Eigen::Vector4d(0.0, 0.0, 0.0, 4.0);  // yaw wider than 2 pi
  try {
    initial_pose(box);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("yaw width"), std::string::npos) << e.what();
  }
  PoseBelief not_spd;
  not_spd.cov = -Eigen::Matrix4d::Identity();
  EXPECT_THROW(initial_pose(not_spd), std::invalid_argument);
  box.min = Eigen::Vector4d(0.0, 0.0, 0.0, -kPi);
  box.max = Eigen::Vector4d(0.0, 0.0, 0.0, kPi);
  EXPECT_NO_THROW(initial_pose(box));
}

}  // namespace
}  // namespace losmimo::localization
