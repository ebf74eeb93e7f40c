// Multilateration (range_fix.h): exact recovery, its covariance against a Monte Carlo of the fix,
// the consistency test, the prior deciding what the ranges leave open; the chi-square quantile
// against tables.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <random>
#include <vector>

#include "losmimo/localization/pose/range_fix.h"

namespace losmimo::localization {
namespace {

const std::vector<Eigen::Vector3d> kBeacons = {
    {0.0, 0.0, 2.5}, {10.0, 0.0, 0.5}, {10.0, 8.0, 3.0}, {0.0, 8.0, 1.0}, {5.0, -3.0, 2.0}};

std::vector<RangeReading> readings_from(const Eigen::Vector3d& c_m, double sigma_m, std::mt19937_64* rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<RangeReading> out;
  for (const Eigen::Vector3d& b : kBeacons) {
    out.push_back({b, (c_m - b).norm() + (rng ? sigma_m * n(*rng) : 0.0), sigma_m});
  }
  return out;
}

TEST(RangeFix, NoiseFreeRanges_RecoverThePointFromAFarPrior) {
  const Eigen::Vector3d truth(3.0, 4.0, 1.2);
  const RangeFixResult r =
      range_fix(readings_from(truth, 0.01, nullptr), {6.0, 1.0, 1.5}, 25.0 * Eigen::Matrix3d::Identity());
  ASSERT_TRUE(r.fix) << r.problem;
  EXPECT_LT((r.fix->sensor_m - truth).norm(), 1e-4);  // the wide prior pulls by ~sigma^2/P0
  EXPECT_EQ(r.fix->ranges_used, 5);
}

TEST(RangeFix, Covariance_MatchesMonteCarloOfTheFix) {
  // Independent check: the spread of fixes over many noisy scans.
  constexpr int kScans = 3000;
  constexpr double kSigma_m = 0.02;
  const Eigen::Vector3d truth(3.0, 4.0, 1.2);
  const Eigen::Matrix3d P0 = 100.0 * Eigen::Matrix3d::Identity();
  std::mt19937_64 rng(31);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_sq = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d predicted = Eigen::Matrix3d::Zero();
  for (int k = 0; k < kScans; ++k) {
    const RangeFixResult r = range_fix(readings_from(truth, kSigma_m, &rng), truth, P0);
    ASSERT_TRUE(r.fix) << r.problem;
    const Eigen::Vector3d e = r.fix->sensor_m - truth;
    sum += e;
    sum_sq += e * e.transpose();
    predicted += r.fix->cov_m2 / kScans;
  }
  const Eigen::Matrix3d sample = sum_sq / kScans - (sum / kScans) * (sum / kScans).transpose();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(sample(i, i), predicted(i, i), 0.08 * predicted(i, i)) << i;
  EXPECT_LT((sum / kScans).norm(), 4.0 * std::sqrt(predicted.trace() / kScans));  // unbiased
}

TEST(RangeFix, GrossErrorInOneRange_IsInconsistentNoFix) {
  const Eigen::Vector3d truth(3.0, 4.0, 1.2);
  std::vector<RangeReading> readings = readings_from(truth, 0.01, nullptr);
  readings[2].range_m += 1.0;  // 100 sigma
  const RangeFixResult r = range_fix(readings, truth, 25.0 * Eigen::Matrix3d::Identity());
  EXPECT_FALSE(r.fix);
  EXPECT_NE(r.problem.find("inconsistent"), std::string::npos) << r.problem;
}

TEST(RangeFix, CoplanarBeacons_ThePriorPicksTheSide) {
  // Beacons all at z = 0: z = +h and z = -h explain the ranges equally; the prior decides.
  const std::vector<Eigen::Vector3d> plane = {{0, 0, 0}, {10, 0, 0}, {10, 8, 0}, {0, 8, 0}};
  const Eigen::Vector3d truth(4.0, 3.0, 2.0);
  std::vector<RangeReading> readings;
  for (const Eigen::Vector3d& b : plane) readings.push_back({b, (truth - b).norm(), 0.01});
  const Eigen::Matrix3d P0 = Eigen::Vector3d(25.0, 25.0, 1.0).asDiagonal();
  const RangeFixResult above = range_fix(readings, {5.0, 5.0, 1.5}, P0);
  const RangeFixResult below = range_fix(readings, {5.0, 5.0, -1.5}, P0);
  ASSERT_TRUE(above.fix && below.fix);
  EXPECT_NEAR(above.fix->sensor_m.z(), 2.0, 1e-3);
  EXPECT_NEAR(below.fix->sensor_m.z(), -2.0, 1e-3);
}

TEST(RangeFix, BadInputs_NoFixWithTheReason) {
  EXPECT_EQ(range_fix({}, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity()).problem, "no usable range");
  EXPECT_FALSE(
      range_fix({{Eigen::Vector3d::Zero(), 1.0, 0.0}}, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity()).fix);
  EXPECT_FALSE(
      range_fix({{Eigen::Vector3d::Zero(), 1.0, 0.1}}, Eigen::Vector3d::Zero(), -Eigen::Matrix3d::Identity()).fix);
}

TEST(Chi2Quantile, WilsonHilferty_MatchesTablesAtP999) {
  // chi2(p = 0.999) from a printed table: 10.828 (1 dof), 16.266 (3), 29.588 (10), 59.703 (30).
  EXPECT_NEAR(chi2_quantile(1.0, kNormalQuantile999), 10.828, 0.035 * 10.828);
  EXPECT_NEAR(chi2_quantile(3.0, kNormalQuantile999), 16.266, 0.02 * 16.266);
  EXPECT_NEAR(chi2_quantile(10.0, kNormalQuantile999), 29.588, 0.01 * 29.588);
  EXPECT_NEAR(chi2_quantile(30.0, kNormalQuantile999), 59.703, 0.005 * 59.703);
}

}  // namespace
}  // namespace losmimo::localization
