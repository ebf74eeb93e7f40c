#include <gtest/gtest.h>

#include <limits>

#include "support/numdiff.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/swarm_channel.h"
#include "losmimo/placement/ura.h"

namespace lp = losmimo::placement;

namespace {
constexpr double kStep_m = 1e-5;
// Central differences err by ~(k h)^2 / 6 relative (k = 2 pi / lambda: 3e-5 at 60 GHz) plus
// rounding of phases ~1e6 rad (~1e-5 relative at h = 1e-5 m). A wrong formula errs by O(1).
constexpr double kGradTolerance = 1e-4;
constexpr double kGradAbsTolerance = 1e-6;

// Checks UAV m's analytic gradient against central differences of the *full recompute* of f.
void expect_gradient_matches(const lp::ChannelModel& model, Eigen::Matrix3Xd q, int m,
                             double rel_tolerance = kGradTolerance) {
  const lp::SwarmChannel swarm(model, q);
  const lp::UavObjective view(swarm, m);
  const Eigen::Vector3d analytic = view.gradient_at(q.col(m));
  const std::function<double(const Eigen::Vector3d&)> f = [&](const Eigen::Vector3d& qm) {
    Eigen::Matrix3Xd moved = q;
    moved.col(m) = qm;
    return lp::objective(model.matrix(moved));
  };
  const Eigen::Vector3d numeric = losmimo::test_support::central_gradient<3>(f, q.col(m), kStep_m);
  EXPECT_LT((analytic - numeric).norm(), rel_tolerance * numeric.norm() + kGradAbsTolerance)
      << "analytic " << analytic.transpose() << " numeric " << numeric.transpose();
}

Eigen::Matrix3Xd random_start(const lp::Scenario& s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return lp::random_start_positions_m(s, rng);
}
}  // namespace

TEST(UavGradient, RandomPlacements_MatchCentralDifferences) {
  for (const lp::GainModel gm : {lp::GainModel::kFarField, lp::GainModel::kExact}) {
    lp::Scenario s;
    s.gain_model = gm;
    const lp::ChannelModel model(s);
    for (int seed = 0; seed < 5; ++seed) expect_gradient_matches(model, random_start(s, seed), seed % 16);
  }
}

TEST(UavGradient, LowerCarrier_MatchesCentralDifferences) {
  for (const lp::GainModel gm : {lp::GainModel::kFarField, lp::GainModel::kExact}) {
    lp::Scenario s;
    s.carrier_hz = 6e9;
    s.gain_model = gm;
    const lp::ChannelModel model(s);
    for (int seed = 0; seed < 3; ++seed) {
      expect_gradient_matches(model, random_start(s, seed), 2 * seed);
    }
  }
}

TEST(UavGradient, NearDegeneratePlacement_MatchesCentralDifferences) {
  // GIVEN: UAV 3 almost on top of UAV 7 (two nearly equal rows, ICN ~ 0)
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  Eigen::Matrix3Xd q = random_start(s, 11);
  q.col(3) = q.col(7) + Eigen::Vector3d(1e-3, 2e-3, -1e-3);
  expect_gradient_matches(model, q, 3);
  expect_gradient_matches(model, q, 7);
}

TEST(UavGradient, ConvergedPlacement_IsNearStationaryAndMatches) {
  lp::Scenario s;
  s.gain_model = lp::GainModel::kExact;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd q = lp::optimal_ura_positions_m(s);
  expect_gradient_matches(model, q, 5);
  const lp::SwarmChannel swarm(model, q);
  // At the URA f ~ 0 and so is its gradient, compared with a random start's (~1e3).
  EXPECT_LT(lp::UavObjective(swarm, 5).gradient_at(q.col(5)).norm(), 1.0);
}

TEST(UavGradient, WrongSign_IsCaughtByTheCheck) {
  // The comparison itself must be able to fail: a flipped gradient differs by 2x its norm.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd q = random_start(s, 1);
  const lp::SwarmChannel swarm(model, q);
  const Eigen::Vector3d g = lp::UavObjective(swarm, 0).gradient_at(q.col(0));
  const std::function<double(const Eigen::Vector3d&)> f = [&](const Eigen::Vector3d& qm) {
    Eigen::Matrix3Xd moved = q;
    moved.col(0) = qm;
    return lp::objective(model.matrix(moved));
  };
  const Eigen::Vector3d numeric = losmimo::test_support::central_gradient<3>(f, q.col(0), kStep_m);
  EXPECT_GT(((-g) - numeric).norm() / numeric.norm(), 1.0);
}

TEST(UavObjective, RowReplacement_EqualsFullRecompute) {
  for (const lp::GainModel gm : {lp::GainModel::kFarField, lp::GainModel::kExact}) {
    lp::Scenario s;
    s.gain_model = gm;
    const lp::ChannelModel model(s);
    Eigen::Matrix3Xd q = random_start(s, 5);
    const lp::SwarmChannel swarm(model, q);
    const Eigen::Vector3d elsewhere(1003.0, 4.0, -9.0);
    const double cached = lp::UavObjective(swarm, 2).objective_at(elsewhere);
    q.col(2) = elsewhere;
    const double full = lp::objective(model.matrix(q));
    EXPECT_NEAR(cached, full, 1e-10 * full);
  }
}

TEST(SwarmChannel, CachedGramAfter1000Moves_EqualsFullRecompute) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  Eigen::Matrix3Xd q = random_start(s, 8);
  lp::SwarmChannel swarm(model, q);
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<int> pick(0, 15);
  std::normal_distribution<double> step(0.0, 0.5);
  constexpr int kMoves = 1000;
  for (int i = 0; i < kMoves; ++i) {
    const int m = pick(rng);
    q.col(m) += Eigen::Vector3d(step(rng), step(rng), step(rng));
    swarm.set_position(m, q.col(m));
  }
  const double full = lp::objective(model.matrix(q));
  EXPECT_NEAR(swarm.objective(), full, 1e-9 * full);
  EXPECT_LT((swarm.gram() - model.matrix(q).adjoint() * model.matrix(q)).norm(), 1e-9 * swarm.gram().norm());
}

TEST(SwarmChannel, ObjectiveAskedAfterEveryKindOfChange_IsTheNewChannels) {
  // objective() is kept per channel version: every change must make it recompute.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  Eigen::Matrix3Xd q = random_start(s, 12);
  lp::SwarmChannel swarm(model, q);
  const auto expect_current = [&](const char* after) {
    const double full = lp::objective(swarm.H());
    EXPECT_NEAR(swarm.objective(), full, 1e-9 * full) << after;
    EXPECT_EQ(swarm.objective(), swarm.objective()) << after;  // asked twice: the same value
  };
  expect_current("construction");
  q.col(3) += Eigen::Vector3d(0.2, -0.4, 0.1);
  swarm.set_position(3, q.col(3));
  expect_current("set_position");
  swarm.set_row(5, model.row(Eigen::Vector3d(1004.0, -3.0, 2.0)));
  expect_current("set_row");
  q.array() += 0.05;
  swarm.set_positions(q);
  expect_current("set_positions");
  swarm.refresh();
  expect_current("refresh");
  EXPECT_NEAR(swarm.objective(), lp::objective(model.matrix(q)), 1e-9 * swarm.objective());
}

TEST(SwarmChannel, GramStaysExactlyHermitianThroughUpdatesAndRefreshes) {
  // GIVEN: 600 moves (two periodic refreshes), exact-gain rows (not unit modulus)
  lp::Scenario s;
  s.gain_model = lp::GainModel::kExact;
  const lp::ChannelModel model(s);
  Eigen::Matrix3Xd q = random_start(s, 5);
  lp::SwarmChannel swarm(model, q);
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> pick(0, 15);
  std::normal_distribution<double> step(0.0, 0.3);
  for (int i = 0; i < 600; ++i) {
    const int m = pick(rng);
    q.col(m) += Eigen::Vector3d(step(rng), step(rng), step(rng));
    swarm.set_position(m, q.col(m));
    // THEN: G(l, k) is conj(G(k, l)) to the bit and the diagonal is real, after every update
    const Eigen::MatrixXcd& G = swarm.gram();
    for (Eigen::Index k = 0; k < G.cols(); ++k) {
      ASSERT_EQ(G(k, k).imag(), 0.0) << "move " << i;
      for (Eigen::Index l = k + 1; l < G.rows(); ++l) {
        ASSERT_EQ(G(l, k), std::conj(G(k, l))) << "move " << i << " entry " << l << "," << k;
      }
    }
  }
}

TEST(SwarmChannel, GramIsFinite_FindsAnInfOrNanEntryAnywhereInTheGram) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd q = lp::optimal_ura_positions_m(s);
  for (const double bad : {1e200, std::numeric_limits<double>::quiet_NaN()}) {
    for (const int k : {0, 7, 15}) {  // the first, a middle and the last antenna
      lp::SwarmChannel channel(model, q);
      ASSERT_TRUE(channel.gram_is_finite());
      Eigen::VectorXcd x = model.row(q.col(3));
      x(k) = {bad, 0.0};  // |x_k|^2 overflows to inf, or NaN: row and column k of G
      channel.set_row(3, x);
      EXPECT_FALSE(channel.gram_is_finite()) << bad << " at " << k;
      EXPECT_FALSE(channel.gram_is_finite()) << "asked again";  // kept per channel version
      channel.set_row(3, model.row(q.col(3)));                  // the rank update leaves inf - inf or NaN in G
      EXPECT_FALSE(channel.gram_is_finite()) << bad << " at " << k;
      channel.refresh();  // G from the finite rows again
      EXPECT_TRUE(channel.gram_is_finite()) << bad << " at " << k;
    }
  }
}
