// The one NEES and the error sums every estimator report is built from (estimation_errors.h),
// against values worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "losmimo/localization/position/estimation_errors.h"

namespace losmimo::localization {
namespace {

constexpr double kTol = 1e-12;

TEST(Nees, DiagonalCovariance_IsTheSumOfSquaredStandardisedErrors) {
  // e = (1, -2, 0.5), P = diag(4, 1, 0.25): 1/4 + 4/1 + 0.25/0.25 = 5.25.
  Belief b;
  b.mean_m = Eigen::Vector3d(11.0, 18.0, 30.5);
  b.cov_m2 = Eigen::Vector3d(4.0, 1.0, 0.25).asDiagonal();
  EXPECT_NEAR(nees(b, Eigen::Vector3d(10.0, 20.0, 30.0)), 5.25, kTol);
}

TEST(Nees, CorrelatedCovariance_UsesTheInverse) {
  // 2-D: P = [[2, 1], [1, 2]], P^-1 = [[2, -1], [-1, 2]] / 3, e = (1, 1): (2 - 1 - 1 + 2) / 3 = 2/3.
  const Eigen::Matrix2d P = (Eigen::Matrix2d() << 2.0, 1.0, 1.0, 2.0).finished();
  EXPECT_NEAR(nees<2>(Eigen::Vector2d(1.0, 1.0), P), 2.0 / 3.0, kTol);
  // e = (1, -1): (2 + 1 + 1 + 2) / 3 = 2.
  EXPECT_NEAR(nees<2>(Eigen::Vector2d(1.0, -1.0), P), 2.0, kTol);
}

TEST(ErrorAccumulator, RmseLateralAndNees_AreTheHandSums) {
  // Two beliefs, unit covariance: errors (3, 0, 4) and (0, 1, 0).
  ErrorAccumulator acc;
  Belief a, b;
  a.mean_m = Eigen::Vector3d(3.0, 0.0, 4.0);
  b.mean_m = Eigen::Vector3d(0.0, 1.0, 0.0);
  acc.add(a, Eigen::Vector3d::Zero());
  acc.add(b, Eigen::Vector3d::Zero());
  // RMSE sqrt((25 + 1) / 2) = sqrt(13); lateral (y, z): sqrt((16 + 1) / 2); NEES (25 + 1) / 2 = 13.
  EXPECT_NEAR(acc.rmse_m(), std::sqrt(13.0), kTol);
  EXPECT_NEAR(acc.lateral_rmse_m(), std::sqrt(8.5), kTol);
  EXPECT_NEAR(acc.average_nees(), 13.0, kTol);
  EXPECT_EQ(acc.samples(), 2);
}

TEST(ErrorAccumulator, PointEstimates_HaveNoNees_AndEmptyIsNaN) {
  ErrorAccumulator acc;
  EXPECT_TRUE(std::isnan(acc.rmse_m()));
  EXPECT_TRUE(std::isnan(acc.average_nees()));
  acc.add(Eigen::Vector3d(0.0, 3.0, 4.0), Eigen::Vector3d::Zero());
  EXPECT_NEAR(acc.rmse_m(), 5.0, kTol);
  EXPECT_NEAR(acc.lateral_rmse_m(), 5.0, kTol);
  EXPECT_EQ(acc.nees_samples(), 0);
  EXPECT_TRUE(std::isnan(acc.average_nees()));
}

TEST(ErrorAccumulator, Merging_GivesTheSameBitsAsAddingEpochByEpoch) {
  // The replay sums per epoch, then epochs into the run: the same order of additions.
  const Eigen::Vector3d truth(1.0, 2.0, 3.0);
  ErrorAccumulator total, by_epoch;
  double sq = 0.0;
  for (int k = 0; k < 5; ++k) {
    ErrorAccumulator epoch;
    double epoch_sq = 0.0;
    for (int m = 0; m < 3; ++m) {
      Belief b;
      b.mean_m = truth + Eigen::Vector3d(0.1 * k, -0.03 * m, 0.007 * (k + m));
      epoch.add(b, truth);
      epoch_sq += (b.mean_m - truth).squaredNorm();
    }
    by_epoch += epoch;
    sq += epoch_sq;
  }
  EXPECT_EQ(by_epoch.sum_squared_m2(), sq);
  EXPECT_EQ(by_epoch.samples(), 15);
}

}  // namespace
}  // namespace losmimo::localization
