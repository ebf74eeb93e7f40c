// The settings for the paper's open modelling choices (sigma convention, fixed localization
// error, stop test on the belief, commanded distance, BF probe actuation, URA geometry and retry
// rule): each changes what it names and nothing else, and its default is the setting's documented default behaviour.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "losmimo/placement/bf.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/settings.h"
#include "losmimo/placement/ura.h"

namespace lp = losmimo::placement;

namespace {
constexpr std::uint64_t kSeed = 11;
constexpr int kIterations = 40;

Eigen::Matrix3Xd start_for(const lp::Scenario& s, int seed) {
  std::mt19937_64 rng(500 + seed);
  return lp::random_start_positions_m(s, rng);
}

// A run of `planner` from start 0 with the given errors and options.
template <typename Planner>
lp::RunResult run(Planner planner, const lp::ErrorModel& errors, lp::RunOptions options = {},
                  std::uint64_t seed = kSeed) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, start_for(s, 0), errors, seed);
  return lp::run_placement(planner, swarm, options);
}

lp::RunOptions capped(int iterations) {
  lp::RunOptions o;
  o.max_iterations = iterations;
  o.target_icn = 1.0;
  return o;
}
}  // namespace

TEST(SigmaConvention, Rms3d_DrawsSigmaOverSqrt3PerAxis_TheSameDraws) {
  // GIVEN one swarm with per-axis sigma s and one with rms_3d sigma s sqrt(3), the same seed
  const lp::Scenario sc;
  const lp::ChannelModel model(sc);
  const Eigen::Matrix3Xd q = start_for(sc, 1);
  constexpr double kSigma = 0.1;
  lp::ErrorModel per_axis{kSigma, kSigma};
  lp::ErrorModel rms{kSigma * std::sqrt(3.0), kSigma * std::sqrt(3.0), lp::SigmaConvention::kRms3d};
  lp::Swarm a(model, q, per_axis, kSeed);
  lp::Swarm b(model, q, rms, kSeed);
  EXPECT_NEAR(rms.axis_sigma_loc_m(), kSigma, 1e-15);
  EXPECT_EQ(per_axis.axis_sigma_loc_m(), kSigma);  // per axis: the value as given, bit for bit
  // THEN every localization and actuation draw is the same (to rounding)
  for (int i = 0; i < 50; ++i) {
    EXPECT_LT((a.estimate_position(i % 16) - b.estimate_position(i % 16)).norm(), 1e-14);
    EXPECT_LT((a.move(i % 16, Eigen::Vector3d(0.1, 0, 0), lp::MotionKind::kPlacement) -
               b.move(i % 16, Eigen::Vector3d(0.1, 0, 0), lp::MotionKind::kPlacement))
                  .norm(),
              1e-14);
  }
}

TEST(LocError, FixedPerUav_IsOneBiasPerUavAndLeavesTheActuationDrawsAlone) {
  const lp::Scenario sc;
  const lp::ChannelModel model(sc);
  const Eigen::Matrix3Xd q = start_for(sc, 2);
  lp::ErrorModel fixed{0.2, 0.05};
  fixed.loc_error = lp::LocError::kFixedPerUav;
  lp::Swarm biased(model, q, fixed, kSeed);
  lp::Swarm no_loc(model, q, lp::ErrorModel{0.0, 0.05}, kSeed);
  const Eigen::Vector3d bias0 = biased.estimate_position(0) - q.col(0);
  const Eigen::Vector3d bias1 = biased.estimate_position(1) - q.col(1);
  EXPECT_GT(bias0.norm(), 0.0);
  EXPECT_NE(bias0, bias1);
  for (int i = 0; i < 20; ++i) {
    // THEN the same error at every estimate, wherever the UAV is
    biased.move(0, Eigen::Vector3d(0.2, -0.1, 0.0), lp::MotionKind::kPlacement);
    no_loc.move(0, Eigen::Vector3d(0.2, -0.1, 0.0), lp::MotionKind::kPlacement);
    EXPECT_LT((biased.estimate_position(0) - biased.true_positions_m().col(0) - bias0).norm(), 1e-12);
  }
  // AND the actuation draws are those of a swarm without localization error
  EXPECT_EQ(biased.true_positions_m(), no_loc.true_positions_m());
}

TEST(LocError, Fresh_IsTheDefaultAndDrawsAtEveryEstimate) {
  const lp::ErrorModel e;
  EXPECT_EQ(e.loc_error, lp::LocError::kFresh);
  EXPECT_EQ(e.sigma_convention, lp::SigmaConvention::kPerAxis);
  const lp::Scenario sc;
  const lp::ChannelModel model(sc);
  lp::Swarm swarm(model, start_for(sc, 3), lp::ErrorModel{0.2, 0.0}, kSeed);
  EXPECT_NE(swarm.estimate_position(0), swarm.estimate_position(0));
}

TEST(StopOn, Belief_StopsTheUraWhenItBelievesItArrived_BfHasNoBeliefAndIsUnchanged) {
  const lp::Scenario sc;
  const lp::ErrorModel loc{0.18, 0.0};
  lp::RunOptions belief;
  belief.stop_on = lp::StopOn::kBelief;
  belief.max_iterations = kIterations;
  lp::RunOptions csi = belief;
  csi.stop_on = lp::StopOn::kCsi;
  // The URA believes it sits on its (orthogonal) targets after one iteration.
  const lp::RunResult ura_belief = run(lp::UraPlanner(sc, lp::UraVariant::kRigid), loc, belief);
  const lp::RunResult ura_csi = run(lp::UraPlanner(sc, lp::UraVariant::kRigid), loc, csi);
  EXPECT_TRUE(ura_belief.converged());
  EXPECT_EQ(ura_belief.iterations, 1);
  EXPECT_FALSE(ura_csi.converged());  // the true ICN stays below 0.95 at 0.18 m
  EXPECT_LT(lp::inverse_condition_number(lp::ChannelModel(sc).matrix(ura_belief.final_m)), 0.95);
  // BF keeps no belief: the stop test stays on the channel, bit for bit the same run.
  lp::BfOptions bf;
  const lp::RunResult bf_belief = run(lp::BruteForcePlanner(sc, bf), lp::ErrorModel{0.0, 0.02}, belief);
  const lp::RunResult bf_csi = run(lp::BruteForcePlanner(sc, bf), lp::ErrorModel{0.0, 0.02}, csi);
  EXPECT_EQ(bf_belief.final_m, bf_csi.final_m);
  EXPECT_EQ(bf_belief.iterations, bf_csi.iterations);
}

TEST(StopOn, GdBelief_IsEstimatePlusCommandedMoves) {
  // Without errors the belief is the true position (the estimate is exact, the move too).
  const lp::Scenario sc;
  const lp::ChannelModel model(sc);
  lp::Swarm swarm(model, start_for(sc, 4), {}, kSeed);
  lp::GradientDescentPlanner gd(sc, {});
  gd.start(swarm);
  EXPECT_FALSE(gd.believed_positions().has_value());
  gd.iterate(swarm, 1);
  ASSERT_TRUE(gd.believed_positions().has_value());
  EXPECT_LT((*gd.believed_positions() - swarm.true_positions_m()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Distance, Commanded_CountsTheCommandedMovesAndChangesNoPosition) {
  const lp::Scenario sc;
  lp::UraOptions once;
  once.retry = lp::UraRetry::kOnce;
  const lp::ErrorModel act{0.0, 0.1};
  lp::RunOptions commanded = capped(3);
  commanded.distance = lp::DistanceKind::kCommanded;
  const lp::RunResult c = run(lp::UraPlanner(sc, lp::UraVariant::kRigid, once), act, commanded);
  const lp::RunResult t = run(lp::UraPlanner(sc, lp::UraVariant::kRigid, once), act, capped(3));
  EXPECT_EQ(c.final_m, t.final_m);
  EXPECT_EQ(c.iterations, t.iterations);
  // One commanded move per UAV: start (exact estimate) to target.
  lp::UraPlanner ura(sc, lp::UraVariant::kRigid, once);
  const lp::ChannelModel model(sc);
  lp::Swarm swarm(model, start_for(sc, 0), {}, kSeed);
  ura.start(swarm);
  for (int m = 0; m < sc.num_uavs; ++m) {
    EXPECT_NEAR(c.placement_dist_m(m), (ura.targets_m().col(m) - c.start_m.col(m)).norm(), 1e-12) << m;
    EXPECT_NE(c.placement_dist_m(m), t.placement_dist_m(m)) << m;  // the true path differs
  }
}

TEST(Distance, MilestoneWithProbes_AddsBfProbeFlightsOnly) {
  const lp::Scenario sc;
  lp::RunOptions with = capped(200);
  with.target_icn = 0.95;
  with.milestone_distance_includes_probes = true;
  lp::RunOptions without = with;
  without.milestone_distance_includes_probes = false;
  const lp::RunResult bf_with = run(lp::BruteForcePlanner(sc, {}), {}, with);
  const lp::RunResult bf_without = run(lp::BruteForcePlanner(sc, {}), {}, without);
  ASSERT_TRUE(bf_with.icn050.reached);
  const auto& at = bf_with.trace[bf_with.icn050.iteration];
  EXPECT_EQ(bf_with.icn050.placement_dist_m, at.placement_dist_m + at.probe_dist_m);
  EXPECT_EQ(bf_without.icn050.placement_dist_m, at.placement_dist_m);
  EXPECT_EQ(bf_with.final_m, bf_without.final_m);
  const lp::RunResult gd_with = run(lp::GradientDescentPlanner(sc, {}), {}, with);
  const lp::RunResult gd_without = run(lp::GradientDescentPlanner(sc, {}), {}, without);
  EXPECT_EQ(gd_with.icn095.placement_dist_m, gd_without.icn095.placement_dist_m);
}

TEST(ProbeActuation, KeptMoveOnly_ProbesDoNotMoveTheUav_WithoutErrorTheRunIsTheSame) {
  const lp::Scenario sc;
  const lp::ChannelModel model(sc);
  // GIVEN actuation error: a UAV whose best probe is "stay" ends exactly where it was
  lp::Swarm exact(model, start_for(sc, 5), lp::ErrorModel{0.0, 0.05}, kSeed);
  lp::Swarm noisy(model, start_for(sc, 5), lp::ErrorModel{0.0, 0.05}, kSeed);
  const Eigen::Vector3d before = exact.true_positions_m().col(0);
  const int z = lp::BruteForcePlanner::step_uav(exact, 0, 1e-9, lp::ProbeActuation::kKeptMoveOnly);
  lp::BruteForcePlanner::step_uav(noisy, 0, 1e-9, lp::ProbeActuation::kEveryLeg);
  if (z == 0) {
    EXPECT_EQ(exact.true_positions_m().col(0), before);
  }
  EXPECT_NE(noisy.true_positions_m().col(0), before);          // six noisy legs moved it
  EXPECT_NEAR(exact.probe_distance_m()(0), 12 * 1e-9, 1e-20);  // still flown and counted
  // AND without actuation error both readings are the same run
  lp::BfOptions kept;
  kept.probe_actuation = lp::ProbeActuation::kKeptMoveOnly;
  const lp::RunResult a = run(lp::BruteForcePlanner(sc, kept), {}, capped(kIterations));
  const lp::RunResult b = run(lp::BruteForcePlanner(sc, {}), {}, capped(kIterations));
  EXPECT_LT((a.final_m - b.final_m).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(a.probe_dist_m.mean(), b.probe_dist_m.mean(), 1e-9);
}

TEST(UraGeometry, SpacingMultipleCoprimeWithTheArray_IsOrthogonal_OthersAreRefused) {
  const lp::Scenario sc;
  const lp::ChannelModel model(sc);
  const Eigen::Matrix3Xd k1 = lp::optimal_ura_positions_m(sc, 1);
  const Eigen::Matrix3Xd k3 = lp::optimal_ura_positions_m(sc, 3);
  EXPECT_EQ(k1, lp::optimal_ura_positions_m(sc));
  EXPECT_NEAR((k3.col(1) - k3.col(0)).norm(), 3 * (k1.col(1) - k1.col(0)).norm(), 1e-9);
  EXPECT_GT(lp::inverse_condition_number(model.matrix(k3)), 0.98);  // paraxial: 0.988
  lp::UraOptions two;
  two.spacing_multiple = 2;
  EXPECT_THROW(lp::UraPlanner(sc, lp::UraVariant::kRigid, two), std::invalid_argument);
  EXPECT_LT(lp::inverse_condition_number(model.matrix(lp::optimal_ura_positions_m(sc, 2))), 0.1);
}

TEST(UraGeometry, OwnDepth_KeepsEachUavsDepthAndTheSlotsDirection) {
  const lp::Scenario sc;
  const lp::ChannelModel model(sc);
  lp::UraOptions own;
  own.depth = lp::UraDepth::kOwn;
  own.spacing_multiple = 3;
  lp::UraPlanner ura(sc, lp::UraVariant::kRigid, own);
  const Eigen::Matrix3Xd start = start_for(sc, 6);
  lp::Swarm swarm(model, start, {}, kSeed);
  ura.start(swarm);
  const Eigen::Matrix3Xd slots = lp::optimal_ura_positions_m(sc, 3);
  for (int m = 0; m < sc.num_uavs; ++m) {
    const Eigen::Vector3d t = ura.targets_m().col(m);
    EXPECT_EQ(t.x(), start(0, m));
    bool on_a_ray = false;  // t = slot * (x / R) for one slot
    for (int k = 0; k < slots.cols(); ++k) {
      on_a_ray |= (t - slots.col(k) * (t.x() / sc.cube_center_m.x())).norm() < 1e-9;
    }
    EXPECT_TRUE(on_a_ray) << m;
  }
  EXPECT_GT(lp::inverse_condition_number(model.matrix(ura.targets_m())), 0.98);
}

TEST(UraRetry, OnceMovesInTheFirstIterationOnly_AverageShrinksTheLocalizationError) {
  const lp::Scenario sc;
  const lp::ErrorModel loc{0.18, 0.0};
  lp::UraOptions once, average;
  once.retry = lp::UraRetry::kOnce;
  average.retry = lp::UraRetry::kAverage;
  const lp::RunResult r1 = run(lp::UraPlanner(sc, lp::UraVariant::kRigid, once), loc, capped(1));
  const lp::RunResult r20 = run(lp::UraPlanner(sc, lp::UraVariant::kRigid, once), loc, capped(20));
  EXPECT_EQ(r1.final_m, r20.final_m);
  const lp::RunResult every = run(lp::UraPlanner(sc, lp::UraVariant::kRigid), loc, capped(200));
  const lp::RunResult avg = run(lp::UraPlanner(sc, lp::UraVariant::kRigid, average), loc, capped(200));
  lp::UraPlanner ura(sc, lp::UraVariant::kRigid);
  const lp::ChannelModel model(sc);
  lp::Swarm swarm(model, start_for(sc, 0), {}, kSeed);
  ura.start(swarm);  // the exact targets (the assignment of the noisy start may differ: compare RMS)
  const auto rms_to_slots = [&](const Eigen::Matrix3Xd& q) {
    double sum = 0.0;
    for (int m = 0; m < q.cols(); ++m) {
      double best = 1e9;
      for (int k = 0; k < q.cols(); ++k) best = std::min(best, (q.col(m) - ura.targets_m().col(k)).norm());
      sum += best * best;
    }
    return std::sqrt(sum / q.cols());
  };
  EXPECT_LT(rms_to_slots(avg.final_m), 0.5 * rms_to_slots(every.final_m));
  // Without errors the three rules are the same run.
  const lp::RunResult exact_every = run(lp::UraPlanner(sc, lp::UraVariant::kRigid), {}, capped(3));
  const lp::RunResult exact_avg = run(lp::UraPlanner(sc, lp::UraVariant::kRigid, average), {}, capped(3));
  EXPECT_LT((exact_every.final_m - exact_avg.final_m).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(RunOverride, SetFieldsReplaceThePlacementOnes) {
  lp::RunOptions run;
  EXPECT_EQ(lp::with_override(run, {}).max_iterations, run.max_iterations);
  EXPECT_EQ(lp::with_override(run, {}).target_icn, run.target_icn);
  const lp::RunOptions o = lp::with_override(run, lp::RunOverride{1.0, 2000});
  EXPECT_EQ(o.max_iterations, 2000);
  EXPECT_EQ(o.target_icn, 1.0);
}
