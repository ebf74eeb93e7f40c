// The health rules both filter families share (filter_health.h), on their own: the covariance
// floor at both state sizes, the degraded rule, and the wording of a belief's first problem.
#include "losmimo/localization/filter_health.h"

#include <gtest/gtest.h>

#include <limits>
#include <optional>
#include <string>

namespace losmimo::localization {
namespace {

constexpr double kTolerance = 1e-12;

TEST(MakeSpd, IndefiniteMatrix_FlooredAndSymmetric_AtBothStateSizes) {
  // GIVEN: an asymmetric P with a negative eigenvalue, and the same block inside a 4x4 one
  Eigen::Matrix3d P3;
  P3 << 1.0, 0.2, 0.0, 0.1, -0.5, 0.0, 0.0, 0.0, 2.0;
  Eigen::Matrix4d P4 = Eigen::Matrix4d::Identity();
  P4.topLeftCorner<3, 3>() = P3;
  // WHEN
  const bool repaired3 = make_spd<3>(P3, 1e-6, 1.0);
  const bool repaired4 = make_spd<4>(P4, 1e-6, 1.0);
  // THEN: both repaired, symmetric, smallest eigenvalue at the floor, the same 3x3 block
  EXPECT_TRUE(repaired3);
  EXPECT_TRUE(repaired4);
  EXPECT_LT((P3 - P3.transpose()).cwiseAbs().maxCoeff(), kTolerance);
  EXPECT_NEAR(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(P3).eigenvalues().minCoeff(), 1e-6, kTolerance);
  EXPECT_LT((P4.topLeftCorner<3, 3>() - P3).cwiseAbs().maxCoeff(), kTolerance);
}

TEST(MakeSpd, NonFiniteMatrix_BecomesTheFallback) {
  Eigen::Matrix4d P = Eigen::Matrix4d::Identity();
  P(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(make_spd<4>(P, 1e-6, 2.5));
  EXPECT_EQ(P, 2.5 * Eigen::Matrix4d::Identity());
}

TEST(RepairCovariance, NonFiniteMean_IsCountedEvenWithAFiniteCovariance) {
  FilterConfig config;
  FilterCounters counters;
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  repair_covariance<3>(Eigen::Vector3d(std::numeric_limits<double>::infinity(), 0.0, 0.0), P, config, counters);
  EXPECT_EQ(counters.non_finite_state, 1);
  EXPECT_EQ(counters.covariance_repairs, 0);
}

TEST(IsDegraded, TimeoutOrWideCovariance) {
  FilterConfig config;  // degraded after 10 epochs or above 1 m
  const Eigen::Matrix3d narrow = 0.01 * Eigen::Matrix3d::Identity();
  EXPECT_FALSE(is_degraded(config, 9, narrow));
  EXPECT_TRUE(is_degraded(config, 10, narrow));
  EXPECT_TRUE(is_degraded(config, 0, Eigen::Vector3d(0.01, 1.21, 0.01).asDiagonal()));
}

TEST(MomentsProblem, NamesTheFirstProblemWithTheCallersNames) {
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();
  Eigen::Matrix4d cov = Eigen::Matrix4d::Identity();
  EXPECT_EQ(moments_problem<4>(mean, cov, "mean", "cov"), std::nullopt);
  cov(3, 3) = -0.5;
  EXPECT_EQ(moments_problem<4>(mean, cov, "mean", "cov"), std::optional<std::string>("cov(3, 3) = -0.5 < 0"));
  mean(1) = std::numeric_limits<double>::infinity();
  EXPECT_EQ(moments_problem<4>(mean, cov, "mean_m", "cov_m2"), std::optional<std::string>("mean_m(1) = inf"));
}

TEST(NonFiniteStateProblem, CountsEpochs) {
  FilterCounters counters;
  EXPECT_EQ(non_finite_state_problem(counters), std::nullopt);
  counters.non_finite_state = 2;
  EXPECT_EQ(non_finite_state_problem(counters),
            std::optional<std::string>("state became non-finite in 2 epoch(s), covariance reset"));
}

}  // namespace
}  // namespace losmimo::localization
