// split_swarm_error (swarm_shape.h) against constructed errors whose parts are known, its least
// squares conditions, and the property it stands for: ICN does not see a common lateral
// translation of the swarm (second order), while an independent error of the same size breaks it.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/scenario.h"
#include "losmimo/placement/swarm_shape.h"
#include "losmimo/placement/ura.h"
#include "support/shape_nees.h"

namespace losmimo::placement {
namespace {

Eigen::Matrix3Xd ura() { return optimal_ura_positions_m(Scenario{}); }

TEST(SwarmShape, ACommonTranslation_IsAllCommon_NoShapeNoRotation) {
  const Eigen::Matrix3Xd truth = ura();
  const Eigen::Vector3d t(0.3, 0.1, -0.2);
  const SwarmErrorSplit s = split_swarm_error(truth, truth.colwise() + t);
  EXPECT_NEAR(s.common_boresight_m, 0.3, 1e-12);
  EXPECT_LT((s.common_lateral_m - Eigen::Vector2d(0.1, -0.2)).norm(), 1e-12);
  EXPECT_LT(std::abs(s.rotation_rad), 1e-12);
  EXPECT_LT(s.shape_lateral_rmse_m, 1e-12);
  EXPECT_NEAR(s.lateral_rmse_m, std::hypot(0.1, 0.2), 1e-12);
}

TEST(SwarmShape, ASmallRotationAboutBoresight_IsTheRotation_ToSecondOrder) {
  const Eigen::Matrix3Xd truth = ura();
  const Eigen::Vector2d centroid = truth.bottomRows<2>().rowwise().mean();
  const double theta = 1e-3;
  Eigen::Matrix3Xd est = truth;
  for (Eigen::Index n = 0; n < truth.cols(); ++n) {
    const Eigen::Vector2d r = truth.col(n).tail<2>() - centroid;
    est.col(n).tail<2>() = centroid + Eigen::Vector2d(std::cos(theta) * r.x() - std::sin(theta) * r.y(),
                                                      std::sin(theta) * r.x() + std::cos(theta) * r.y());
  }
  const SwarmErrorSplit s = split_swarm_error(truth, est);
  EXPECT_NEAR(s.rotation_rad, theta, 1e-9);  // sin(theta) vs theta: theta^3 / 6
  // The rotation's second-order part, (cos theta - 1) r: theta^2 / 2 times the swarm's radius.
  const double radius_m = (truth.bottomRows<2>().colwise() - centroid).colwise().norm().maxCoeff();
  EXPECT_LT(s.shape_lateral_rmse_m, theta * theta * radius_m);
  EXPECT_LT(s.common_lateral_m.norm(), 1e-12);
}

TEST(SwarmShape, AnyError_SplitsIntoOrthogonalParts) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01;
  const Eigen::Matrix3Xd truth = ura();
  Eigen::Matrix3Xd est = truth;
  for (Eigen::Index n = 0; n < est.cols(); ++n) est.col(n) += Eigen::Vector3d(n01(rng), n01(rng), n01(rng)) * 0.05;
  const SwarmErrorSplit s = split_swarm_error(truth, est);
  // Least squares: the residuals sum to zero and are orthogonal to J r ...
  const Eigen::Vector2d centroid = truth.bottomRows<2>().rowwise().mean();
  double dot = 0.0, jr_sq = 0.0;
  for (Eigen::Index n = 0; n < truth.cols(); ++n) {
    const Eigen::Vector2d r = truth.col(n).tail<2>() - centroid;
    const Eigen::Vector2d jr(-r.y(), r.x());
    dot += jr.dot(s.shape_lateral_m.col(n));
    jr_sq += jr.squaredNorm();
  }
  EXPECT_LT(s.shape_lateral_m.rowwise().sum().norm(), 1e-12);
  EXPECT_LT(std::abs(dot), 1e-12);
  // ... so the squares add up: N |c|^2 + theta^2 |J r|^2 + sum |residual|^2 = sum |e_lat|^2.
  const double n = static_cast<double>(truth.cols());
  const double total = n * s.lateral_rmse_m * s.lateral_rmse_m;
  const double parts = n * s.common_lateral_m.squaredNorm() + s.rotation_rad * s.rotation_rad * jr_sq +
                       n * s.shape_lateral_rmse_m * s.shape_lateral_rmse_m;
  EXPECT_NEAR(parts, total, 1e-12 * total);
}

TEST(SwarmShape, MismatchedOrNonFiniteInput_IsRefused) {
  const Eigen::Matrix3Xd truth = ura();
  EXPECT_THROW(split_swarm_error(truth, truth.leftCols(3)), std::invalid_argument);
  EXPECT_THROW(split_swarm_error(Eigen::Matrix3Xd(3, 0), Eigen::Matrix3Xd(3, 0)), std::invalid_argument);
  Eigen::Matrix3Xd bad = truth;
  bad(1, 2) = std::nan("");
  EXPECT_THROW(split_swarm_error(truth, bad), std::invalid_argument);
}

TEST(SwarmShape, Icn_IsBlindToACommonLateralTranslation_NotToAnIndependentErrorOfTheSameSize) {
  const Scenario scenario;
  const ChannelModel model(scenario);
  const Eigen::Matrix3Xd truth = ura();
  const double icn0 = inverse_condition_number(model.matrix(truth));
  ASSERT_GT(icn0, 0.999);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  for (const double size_m : {0.1, 1.0}) {
    // A common lateral translation: the split says common, not shape; ICN moves by second-order
    // terms only (measured: ICN 0.999555 unchanged to 1e-6 at 0.1 m, 0.999541 at 1 m; an independent
    // error of the same size: 0.915 and 0.483).
    const Eigen::Matrix3Xd moved = truth.colwise() + Eigen::Vector3d(0.0, size_m, 0.0);
    const double icn_moved = inverse_condition_number(model.matrix(moved));
    EXPECT_LT(std::abs(icn_moved - icn0), 1e-3) << size_m;
    EXPECT_LT(split_swarm_error(truth, moved).shape_lateral_rmse_m, 1e-12);
    // Negative control: each UAV off by the same lateral size, in its own direction.
    Eigen::Matrix3Xd scattered = truth;
    for (Eigen::Index n = 0; n < truth.cols(); ++n) {
      const double a = angle(rng);
      scattered.col(n) += Eigen::Vector3d(0.0, size_m * std::cos(a), size_m * std::sin(a));
    }
    const double icn_scattered = inverse_condition_number(model.matrix(scattered));
    std::cout << "[shape] " << size_m << " m: ICN " << icn0 << " -> translated " << icn_moved << ", scattered "
              << icn_scattered << "\n";
    EXPECT_GT(icn0 - icn_scattered, 0.02) << size_m;
    EXPECT_GT(icn0 - icn_scattered, 20.0 * std::abs(icn_moved - icn0)) << size_m;
    EXPECT_GT(split_swarm_error(truth, scattered).shape_lateral_rmse_m, 0.7 * size_m);
  }
}

// Independent errors drawn per UAV from a random (anisotropic, UAV-specific) lateral covariance.
struct Draws {
  std::vector<Eigen::Matrix2d> cov_m2;
  std::vector<Eigen::Matrix2d> chol;  // lower factors
};

Draws random_covariances(Eigen::Index n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.5, 2.0), a(0.0, M_PI);
  Draws d;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double th = a(rng);
    Eigen::Matrix2d r;
    r << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
    const Eigen::Matrix2d c = 1e-4 * r * Eigen::Vector2d(u(rng), 4.0 * u(rng)).asDiagonal() * r.transpose();
    d.cov_m2.push_back(0.5 * (c + c.transpose()));
    d.chol.push_back(d.cov_m2.back().llt().matrixL());
  }
  return d;
}

Eigen::Matrix3Xd draw(const Eigen::Matrix3Xd& truth, const Draws& d, double scale, std::mt19937_64& rng) {
  std::normal_distribution<double> n01;
  Eigen::Matrix3Xd est = truth;
  for (Eigen::Index k = 0; k < truth.cols(); ++k) {
    est(0, k) += 0.3 * n01(rng);  // boresight error: outside the shape, must not count
    est.col(k).tail<2>() += scale * d.chol[static_cast<std::size_t>(k)] * Eigen::Vector2d(n01(rng), n01(rng));
  }
  return est;
}

TEST(SwarmShape, DegreesOfFreedom_AreTwoPerUavLessTranslationAndRotation) {
  EXPECT_EQ(shape_dof(ura()), 2 * 16 - 3);
  EXPECT_EQ(shape_dof(Eigen::Matrix3Xd::Zero(3, 1)), 0);
  EXPECT_EQ(shape_dof(Eigen::Matrix3Xd::Zero(3, 4)), 2 * 4 - 2);  // all at one point: no rotation
}

TEST(SwarmShape, ExpectedSplitOfIndependentErrors_MatchesMonteCarlo) {
  const Eigen::Matrix3Xd truth = ura();
  const double sigma_m = 0.04;
  const ExpectedSwarmSplit want = expected_split_of_independent_errors(static_cast<int>(truth.cols()), sigma_m);
  EXPECT_EQ(expected_split_of_independent_errors(1, sigma_m).shape_lateral_rmse_m, 0.0);
  EXPECT_THROW(expected_split_of_independent_errors(0, sigma_m), std::invalid_argument);
  EXPECT_THROW(expected_split_of_independent_errors(4, std::nan("")), std::invalid_argument);
  EXPECT_NEAR(want.common_lateral_rms_m, sigma_m * std::sqrt(2.0 / 16.0), 1e-15);
  std::mt19937_64 rng(21);
  std::normal_distribution<double> n01;
  SwarmShapeAccumulator acc;
  const int epochs = 4000;
  for (int i = 0; i < epochs; ++i) {
    Eigen::Matrix3Xd est = truth;
    for (Eigen::Index k = 0; k < truth.cols(); ++k)
      est.col(k) += sigma_m * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    acc.add(truth, est);
  }
  // Mean squares of chi-square sums: relative sd sqrt(2 / dof / epochs) (0.5% shape, 1.6% common).
  const double shape_ms = acc.shape_lateral_rmse_m() * acc.shape_lateral_rmse_m();
  const double common_ms = acc.common_lateral_rms_m() * acc.common_lateral_rms_m();
  const double want_shape_ms = want.shape_lateral_rmse_m * want.shape_lateral_rmse_m;
  const double want_common_ms = want.common_lateral_rms_m * want.common_lateral_rms_m;
  EXPECT_NEAR(shape_ms / want_shape_ms, 1.0, 4.0 * std::sqrt(2.0 / 29.0 / epochs));
  EXPECT_NEAR(common_ms / want_common_ms, 1.0, 4.0 * std::sqrt(2.0 / 2.0 / epochs));
  // Negative control: the whole lateral RMSE, sqrt(2) sigma, is not the shape's.
  EXPECT_GT(std::abs(std::sqrt(2.0) * sigma_m / want.shape_lateral_rmse_m - 1.0), 0.04);
}

TEST(SwarmShape, ShapeNees_OfIsotropicCovariance_IsTheShapeResidualOverSigmaSquared) {
  // With S = sigma^2 I the projection commutes with S: NEES = |shape residual|^2 / sigma^2 / dof,
  // the residual taken from split_swarm_error's least squares, a different computation.
  const Eigen::Matrix3Xd truth = ura();
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01;
  Eigen::Matrix3Xd est = truth;
  for (Eigen::Index k = 0; k < est.cols(); ++k) est.col(k) += 0.02 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
  est.bottomRows<2>().colwise() += Eigen::Vector2d(0.5, -0.3);  // a common offset: not in the shape
  const double sigma_m = 0.03;
  const std::vector<Eigen::Matrix2d> cov(16, sigma_m * sigma_m * Eigen::Matrix2d::Identity());
  const SwarmErrorSplit split = split_swarm_error(truth, est);
  const double want = split.shape_lateral_m.squaredNorm() / (sigma_m * sigma_m) / shape_dof(truth);
  EXPECT_NEAR(shape_nees_per_dof(truth, est, cov), want, 1e-9 * want);
}

TEST(SwarmShape, ShapeNees_OfAnisotropicCovariances_IsThePseudoInverseForm) {
  const Eigen::Matrix3Xd truth = ura();
  std::mt19937_64 rng(12);
  const Draws d = random_covariances(truth.cols(), rng);
  for (int i = 0; i < 5; ++i) {
    const Eigen::Matrix3Xd est = draw(truth, d, 1.0, rng);
    const double want = test_support::shape_nees_by_pseudo_inverse(truth, est, d.cov_m2);
    EXPECT_NEAR(shape_nees_per_dof(truth, est, d.cov_m2), want, 1e-9 * want) << i;
  }
}

TEST(SwarmShape, ShapeNees_IsOneForConsistentBeliefs_TwoForBeliefsTwiceTooSure) {
  const Eigen::Matrix3Xd truth = ura();
  std::mt19937_64 rng(8);
  const Draws d = random_covariances(truth.cols(), rng);
  SwarmShapeAccumulator consistent, overconfident;
  std::vector<Eigen::Matrix2d> half;
  for (const auto& c : d.cov_m2) half.push_back(0.5 * c);
  const int epochs = 2000;
  for (int i = 0; i < epochs; ++i) {
    const Eigen::Matrix3Xd est = draw(truth, d, 1.0, rng);
    consistent.add(truth, est, d.cov_m2);
    overconfident.add(truth, est, half);
  }
  // chi-square(29) / 29 averaged over 2000 epochs: sd sqrt(2 / 29 / 2000) = 0.006.
  const double sd = std::sqrt(2.0 / 29.0 / epochs);
  EXPECT_NEAR(consistent.shape_nees_per_dof(), 1.0, 4.0 * sd);
  EXPECT_NEAR(overconfident.shape_nees_per_dof(), 2.0, 8.0 * sd);
  EXPECT_EQ(consistent.epochs(), epochs);
}

TEST(SwarmShape, ShapeNees_RefusesBadCovariances) {
  const Eigen::Matrix3Xd truth = ura();
  std::vector<Eigen::Matrix2d> cov(16, 1e-4 * Eigen::Matrix2d::Identity());
  EXPECT_THROW(shape_nees_per_dof(truth, truth, std::vector<Eigen::Matrix2d>(15, cov[0])), std::invalid_argument);
  cov[4](0, 0) = -1.0;
  EXPECT_THROW(shape_nees_per_dof(truth, truth, cov), std::invalid_argument);
  cov[4] = Eigen::Matrix2d::Identity();
  cov[4](0, 1) = 0.5;  // not symmetric
  EXPECT_THROW(shape_nees_per_dof(truth, truth, cov), std::invalid_argument);
  EXPECT_TRUE(std::isnan(shape_nees_per_dof(truth.leftCols(1), truth.leftCols(1), {cov[0]})));
}

}  // namespace
}  // namespace losmimo::placement
