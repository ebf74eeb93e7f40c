// icn_below, the cheap proof that ICN(G) < threshold, against the ICN of the SVD of H: it must
// never claim "below" for a channel at or above the threshold (whatever its warm vectors hold),
// it must prove the clear cases, and its warm vectors must follow G's extreme eigenvectors.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <random>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/run.h"
#include "losmimo/placement/scenario.h"
#include "losmimo/placement/ura.h"

namespace lp = losmimo::placement;

namespace {

// The optimal URA with every coordinate jittered by N(0, sigma_m): ICN from ~1 down to ~0.1.
Eigen::MatrixXcd jittered_ura_channel(const lp::ChannelModel& model, const lp::Scenario& s, double sigma_m,
                                      std::mt19937_64& rng) {
  Eigen::Matrix3Xd q = lp::optimal_ura_positions_m(s);
  std::normal_distribution<double> jitter(0.0, sigma_m);
  for (Eigen::Index i = 0; i < q.size(); ++i) q(i) += jitter(rng);
  return model.matrix(q);
}

Eigen::VectorXcd random_unit_vector(Eigen::Index n, std::mt19937_64& rng) {
  std::normal_distribution<double> n01;
  Eigen::VectorXcd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v(i) = {n01(rng), n01(rng)};
  return v.normalized();
}

}  // namespace

TEST(IcnBelow, NeverClaimsBelowForAChannelAtOrAboveTheThreshold_AndProvesTheClearCases) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(3);
  int clear_cases = 0, clear_proven = 0, checked_above = 0;
  for (int t = 0; t < 400; ++t) {
    const double sigma_m = 0.002 * (t % 40) * (t % 40);  // 0 .. 3 m
    const Eigen::MatrixXcd H = jittered_ura_channel(model, s, sigma_m, rng);
    const Eigen::MatrixXcd G = H.adjoint() * H;
    const double icn = lp::inverse_condition_number(H);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(G);
    for (const double threshold : {0.3, 0.5, 0.95}) {
      // Warm vectors of every kind: none, random, and the worst (top and bottom swapped).
      lp::IcnWarmStart random{random_unit_vector(16, rng), random_unit_vector(16, rng)};
      lp::IcnWarmStart swapped{eig.eigenvectors().col(0), eig.eigenvectors().col(15)};
      const bool cold = lp::icn_below(G, 16, threshold);
      const bool warm_random = lp::icn_below(G, 16, threshold, &random);
      const bool warm_swapped = lp::icn_below(G, 16, threshold, &swapped);
      if (icn >= threshold) {
        ++checked_above;
        EXPECT_FALSE(cold || warm_random || warm_swapped) << "ICN " << icn << ", threshold " << threshold;
      }
      if (icn < 0.5 * threshold) {
        ++clear_cases;
        clear_proven += cold && warm_random && warm_swapped;
      }
    }
  }
  EXPECT_GT(checked_above, 100);
  EXPECT_GT(clear_cases, 100);
  EXPECT_EQ(clear_proven, clear_cases);
}

TEST(IcnBelow, WarmVectors_FollowTheExtremeEigenvectorsOfASlowlyChangingG) {
  // A random swarm drifting by 2 cm per step: after some calls the bottom vector's Rayleigh
  // quotient lies in the lower part of the spectrum and the top one's at lambda_max.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(5);
  Eigen::Matrix3Xd q = lp::random_start_positions_m(s, rng);
  std::normal_distribution<double> step(0.0, 0.02);
  lp::IcnWarmStart warm;
  double r_bottom = 0.0, r_top = 0.0, lambda_min = 0.0, lambda_max = 0.0, lambda_mean = 0.0;
  for (int call = 0; call < 300; ++call) {
    for (Eigen::Index i = 0; i < q.size(); ++i) q(i) += step(rng);
    const Eigen::MatrixXcd H = model.matrix(q);
    const Eigen::MatrixXcd G = H.adjoint() * H;
    lp::icn_below(G, 16, 0.95, &warm);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd>(G, Eigen::EigenvaluesOnly).eigenvalues();
    ASSERT_EQ(warm.top.size(), 16);
    ASSERT_EQ(warm.bottom.size(), 16);
    r_top = warm.top.dot(G * warm.top).real();
    r_bottom = warm.bottom.dot(G * warm.bottom).real();
    lambda_min = ev(0);
    lambda_max = ev(15);
    lambda_mean = ev.mean();
  }
  EXPECT_NEAR(warm.top.norm(), 1.0, 1e-12);
  EXPECT_NEAR(warm.bottom.norm(), 1.0, 1e-12);
  EXPECT_GT(r_top, 0.95 * lambda_max);
  EXPECT_LT(r_bottom, lambda_min + 0.5 * (lambda_mean - lambda_min));
}

TEST(IcnBelow, NonFiniteGram_IsNeverProvenBelow) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(7);
  const Eigen::MatrixXcd H = jittered_ura_channel(model, s, 2.0, rng);
  const Eigen::MatrixXcd G = H.adjoint() * H;
  lp::IcnWarmStart warm;
  ASSERT_TRUE(lp::icn_below(G, 16, 0.95, &warm));  // a clear case, and warm vectors for the next call
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Eigen::MatrixXcd broken = G;
    broken(3, 7) = {bad, 0.0};
    lp::IcnWarmStart copy = warm;
    EXPECT_FALSE(lp::icn_below(broken, 16, 0.95, &copy)) << bad;
    EXPECT_FALSE(lp::icn_below(broken, 16, 0.95)) << bad;
  }
}

TEST(IcnBelow, WarmVectorsThatStoppedProving_AreTriedAgainAndProveOnceGDriftsSlowly) {
  // GIVEN: 40 unrelated channels (the URA jittered by 10 cm: ICN ~0.8-0.9, a new G every call,
  // as under the URA's actuation error), where the warm vectors carry nothing over
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(11);
  lp::IcnWarmStart warm;
  for (int call = 0; call < 40; ++call) {
    const Eigen::MatrixXcd H = jittered_ura_channel(model, s, 0.1, rng);
    const bool below = lp::icn_below(H.adjoint() * H, 16, 0.95, &warm);
    if (below) {
      EXPECT_LT(lp::inverse_condition_number(H), 0.95);
    }
  }
  EXPECT_GE(warm.stage0_misses, 8);
  // WHEN the channel then drifts by 2 cm per call (a random swarm, ICN far below 0.95)
  Eigen::Matrix3Xd q = lp::random_start_positions_m(s, rng);
  std::normal_distribution<double> step(0.0, 0.02);
  int proven_by_warm_vectors_at = -1;
  for (int call = 0; call < 100 && proven_by_warm_vectors_at < 0; ++call) {
    for (Eigen::Index i = 0; i < q.size(); ++i) q(i) += step(rng);
    const Eigen::MatrixXcd H = model.matrix(q);
    EXPECT_TRUE(lp::icn_below(H.adjoint() * H, 16, 0.95, &warm));
    if (warm.stage0_misses == 0) proven_by_warm_vectors_at = call;
  }
  // THEN the warm vectors prove it again within a few of their periodic tries
  EXPECT_GE(proven_by_warm_vectors_at, 0);
  EXPECT_LT(proven_by_warm_vectors_at, 40);
}
