// The range-only pose smoother (fusion/range_smoother.h) and its residuals
// (fusion/pose_cost_functors.h): Jacobians against central differences, and on synthetic logs
// with known truth (localization/range_simulator.h) its error and consistency against the EKF's.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <random>

#include "fusion/gradient_probe.h"
#include "fusion/range_track_simulator.h"
#include "losmimo/placement/common/field_error.h"
#include "losmimo/fusion/pose_cost_functors.h"
#include "losmimo/fusion/range_smoother.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/simulator.h"

namespace losmimo::fusion {
namespace {

using namespace localization;
using test_support::filter_config;
using test_support::four_beacons;
using test_support::kSteps;
using test_support::probe;
using test_support::simulate;
using test_support::Synthetic;

constexpr int kJacobianPoints = 50;

Eigen::Matrix4d random_spd(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix4d A;
  for (int i = 0; i < 16; ++i) A(i / 4, i % 4) = n(rng);
  return A * A.transpose() + 0.1 * Eigen::Matrix4d::Identity();
}

Eigen::Vector4d random_pose(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-10.0, 10.0), yaw(-3.0, 3.0);
  return {u(rng), u(rng), 0.2 * u(rng), yaw(rng)};
}

TEST(PoseCostFunctors, AutodiffJacobians_MatchCentralDifferences) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> small(-0.8, 0.8);
  for (int t = 0; t < kJacobianPoints; ++t) {
    Eigen::Vector4d a = random_pose(rng);
    // b near a (a typical increment), yaw differences off the wrap's cut.
    Eigen::Vector4d b = a + Eigen::Vector4d(small(rng), small(rng), 0.1 * small(rng), small(rng));
    const Eigen::Vector4d u(0.3 * n(rng), 0.1 * n(rng), 0.01 * n(rng), 0.1 * n(rng));
    const Eigen::Vector3d sensor(0.3 * n(rng), 0.3 * n(rng), 1.0 + 0.2 * n(rng));
    const Eigen::Vector3d beacon(5.0 * n(rng), 5.0 * n(rng), 2.0 * n(rng));
    std::string log;
    const std::unique_ptr<ceres::CostFunction> range(RangeCost::Create(7.0, sensor, beacon, 0.05));
    EXPECT_TRUE(probe(*range, {b.data()}, &log)) << "range, point " << t << ": " << log;
    const std::unique_ptr<ceres::CostFunction> odometry(OdometryCost::Create(u, random_spd(rng)));
    EXPECT_TRUE(probe(*odometry, {a.data(), b.data()}, &log)) << "odometry, point " << t << ": " << log;
    const std::unique_ptr<ceres::CostFunction> prior(
        PosePriorCost::Create(b + Eigen::Vector4d::Constant(0.1), random_spd(rng)));
    EXPECT_TRUE(probe(*prior, {a.data()}, &log)) << "prior, point " << t << ": " << log;
  }
}

TEST(PoseCostFunctors, OdometryResidual_ZeroExactlyForTheComposedPose) {
  // The residual inverts odometry_model.h's composition: x_b = x_a (+) u gives r = 0, also
  // when the heading crosses +-pi.
  const Eigen::Vector4d a(1.0, -2.0, 0.3, 3.1);
  const Eigen::Vector4d u(0.4, -0.1, 0.05, 0.2);
  Eigen::Vector4d b = compose(a, u);
  const std::unique_ptr<ceres::CostFunction> cost(OdometryCost::Create(u, Eigen::Matrix4d::Identity() * 1e-4));
  Eigen::Vector4d r;
  const double* blocks[] = {a.data(), b.data()};
  ASSERT_TRUE(cost->Evaluate(blocks, r.data(), nullptr));
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-9) << r.transpose();
}

TEST(PoseCostFunctors, RangeResidual_IsTheRangeModelsPrediction) {
  const Eigen::Vector4d x(2.0, 1.0, 0.0, 0.7);
  const Eigen::Vector3d s(0.16, 0.05, 1.12), b(-3.0, 4.0, 2.5);
  const std::unique_ptr<ceres::CostFunction> cost(RangeCost::Create(6.0, s, b, 0.1));
  double r = 0.0;
  const double* blocks[] = {x.data()};
  ASSERT_TRUE(cost->Evaluate(blocks, &r, nullptr));
  EXPECT_NEAR(r, (range_predict(x, s, b) - 6.0) / 0.1, 1e-12);
}

struct Score {
  double rmse_m = 0.0;
  double mean_nees = 0.0;  // x-y, 2 dof
};

Score score(const std::vector<PoseBelief>& track, const std::vector<Eigen::Vector4d>& truth) {
  Score s;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    const Eigen::Vector2d e = track[k].mean.head<2>() - truth[k].head<2>();
    s.rmse_m += e.squaredNorm();
    s.mean_nees += e.dot(track[k].cov.topLeftCorner<2, 2>().ldlt().solve(e));
  }
  s.rmse_m = std::sqrt(s.rmse_m / static_cast<double>(truth.size()));
  s.mean_nees /= static_cast<double>(truth.size());
  return s;
}

std::vector<PoseBelief> filter_track(const Synthetic& s) {
  std::vector<PoseBelief> t;
  for (const SmootherFrame& f : s.frames) t.push_back(f.filter_belief);
  return t;
}

constexpr int kSeeds = 4;
// Measured over these seeds: the batch smoother's RMSE is 0.64-0.73 of the EKF's (0.79 with 10 %
// outliers); required: below 0.8 (0.85 with outliers).
constexpr double kMaxRmseRatio = 0.8;
constexpr double kMaxRmseRatioWithOutliers = 0.85;

TEST(RangeSmoother, KnownTruth_BatchRmseWellBelowTheEkfsAndConsistent) {
  double nees_sum = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    // GIVEN: a synthetic log and the EKF's track over it.
    const Synthetic s = simulate(static_cast<std::uint64_t>(seed), 0.0);
    // WHEN
    const RangeSmootherResult r = smooth_range_track(filter_config(), four_beacons(), s.frames, {});
    // THEN: one problem, converged, a covariance for every frame.
    EXPECT_EQ(r.problems, 1);
    EXPECT_EQ(r.not_converged, 0);
    EXPECT_EQ(r.covariance_fallbacks, 0);
    const Score ekf = score(filter_track(s), s.truth);
    const Score smoothed = score(r.track, s.truth);
    std::cout << "seed " << seed << ": EKF RMSE " << ekf.rmse_m << " m (NEES " << ekf.mean_nees << "), smoother "
              << smoothed.rmse_m << " m (NEES " << smoothed.mean_nees << ")\n";
    EXPECT_LT(smoothed.rmse_m, kMaxRmseRatio * ekf.rmse_m) << "seed " << seed;
    nees_sum += smoothed.mean_nees;
  }
  // AND: consistent: the mean 2-dof NEES over the seeds' frames near 2 (frames are correlated,
  // so the band is wider than a chi-square band for independent samples).
  const double nees = nees_sum / kSeeds;
  EXPECT_GT(nees, 1.4);
  EXPECT_LT(nees, 2.8);
}

TEST(RangeSmoother, RangeOutliers_DownWeightedAndStillBelowTheEkf) {
  // GIVEN: 10 % of the ranges with a 2 m error (20 sigma).
  const Synthetic s = simulate(11, 0.1);
  const RangeSmootherResult r = smooth_range_track(filter_config(), four_beacons(), s.frames, {});
  const Score ekf = score(filter_track(s), s.truth);
  const Score smoothed = score(r.track, s.truth);
  std::cout << "outliers: EKF RMSE " << ekf.rmse_m << " m, smoother " << smoothed.rmse_m << " m, down-weighted "
            << r.ranges_down_weighted << " of " << r.ranges_used << "\n";
  EXPECT_LT(smoothed.rmse_m, kMaxRmseRatioWithOutliers * ekf.rmse_m);
  // THEN: the outliers (~10 % of the readings, most beyond 3.29 sigma) are the down-weighted ones.
  EXPECT_GT(r.ranges_down_weighted, r.ranges_used / 20);
  EXPECT_LT(r.ranges_down_weighted, r.ranges_used / 7);
}

TEST(RangeSmoother, SlidingWindow_OneProblemPerFrameAndNoWorseThanTheEkf) {
  const Synthetic s = simulate(3, 0.0);
  RangeSmootherConfig c;
  c.window_frames = 10;
  const RangeSmootherResult r = smooth_range_track(filter_config(), four_beacons(), s.frames, c);
  EXPECT_EQ(r.problems, kSteps - 1);
  const Score ekf = score(filter_track(s), s.truth);
  const Score windowed = score(r.track, s.truth);
  std::cout << "window 10: EKF RMSE " << ekf.rmse_m << " m, windowed " << windowed.rmse_m << " m\n";
  EXPECT_LT(windowed.rmse_m, 1.05 * ekf.rmse_m);
  // Frame 0 is the filter's.
  EXPECT_EQ(r.track[0].mean, s.frames[0].filter_belief.mean);
}

TEST(RangeSmoother, SameInput_BitIdenticalTrack) {
  const Synthetic s = simulate(5, 0.1);
  for (const int window : {0, 6}) {
    RangeSmootherConfig c;
    c.window_frames = window;
    const RangeSmootherResult a = smooth_range_track(filter_config(), four_beacons(), s.frames, c);
    const RangeSmootherResult b = smooth_range_track(filter_config(), four_beacons(), s.frames, c);
    ASSERT_EQ(a.track.size(), b.track.size());
    for (std::size_t k = 0; k < a.track.size(); ++k) {
      EXPECT_TRUE(a.track[k].mean == b.track[k].mean && a.track[k].cov == b.track[k].cov)
          << "window " << window << ", frame " << k << ": mean diff " << (a.track[k].mean - b.track[k].mean).transpose()
          << ", cov diff " << (a.track[k].cov - b.track[k].cov).cwiseAbs().maxCoeff() << ", iterations " << a.iterations
          << " vs " << b.iterations;
    }
  }
}

TEST(ChainMarginals, BlockTridiagonal_MatchTheDenseInverse) {
  // GIVEN: a random block-tridiagonal SPD information matrix of 7 poses (a Gram matrix of a
  // chain-shaped Jacobian, so positive definite).
  constexpr int kPoses = 7;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(4 + 8 * (kPoses - 1), 4 * kPoses);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) J(r, c) = n(rng);
  for (int i = 1; i < kPoses; ++i)
    for (int r = 0; r < 8; ++r)
      for (int c = 0; c < 8; ++c) J(4 + 8 * (i - 1) + r, 4 * (i - 1) + c) = n(rng);
  const Eigen::MatrixXd H = J.transpose() * J;
  std::vector<Eigen::Matrix4d> diagonal, upper;
  for (int i = 0; i < kPoses; ++i) {
    diagonal.push_back(H.block<4, 4>(4 * i, 4 * i));
    if (i + 1 < kPoses) upper.push_back(H.block<4, 4>(4 * i, 4 * i + 4));
  }
  // WHEN
  const auto C = chain_marginal_covariances(diagonal, upper);
  // THEN: the diagonal blocks of H^-1.
  ASSERT_TRUE(C.has_value());
  const Eigen::MatrixXd H_inv = H.inverse();
  for (int i = 0; i < kPoses; ++i) {
    const Eigen::Matrix4d expected = H_inv.block<4, 4>(4 * i, 4 * i);
    EXPECT_LT(((*C)[static_cast<std::size_t>(i)] - expected).cwiseAbs().maxCoeff(),
              1e-9 * expected.cwiseAbs().maxCoeff())
        << "pose " << i;
  }
  // AND: a singular chain (pose 3 unobserved in yaw) is refused, not inverted.
  for (Eigen::Matrix4d* m : {&diagonal[3], &upper[2], &upper[3]}) {
    m->row(3).setZero();
    if (m == &diagonal[3]) m->col(3).setZero();
  }
  upper[2].col(3).setZero();
  EXPECT_FALSE(chain_marginal_covariances(diagonal, upper).has_value());
}

TEST(RangeSmoother, UnusableSettings_FieldErrorNamingTheField) {
  const auto field_of = [](const RangeSmootherConfig& c) {
    try {
      validate(c);
    } catch (const common::FieldError& e) {
      return e.field() + ": " + e.what();
    }
    return std::string("accepted");
  };
  RangeSmootherConfig c;
  c.window_frames = 1;
  EXPECT_EQ(field_of(c).rfind("window_frames: range_smoother.window_frames = 1", 0), 0u) << field_of(c);
  c.window_frames = -3;
  EXPECT_EQ(field_of(c).rfind("window_frames: range_smoother.window_frames = -3", 0), 0u) << field_of(c);
  c.window_frames = 2;
  EXPECT_EQ(field_of(c), "accepted");
  c.max_iterations = 0;
  EXPECT_EQ(field_of(c).rfind("max_iterations:", 0), 0u) << field_of(c);
  EXPECT_THROW(smooth_range_track(filter_config(), four_beacons(), {}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace losmimo::fusion
