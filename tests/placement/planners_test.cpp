#include <gtest/gtest.h>

#include <stdexcept>

#include "losmimo/placement/bf.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/ura.h"

namespace lp = losmimo::placement;

namespace {
constexpr int kStarts = 20;
constexpr int kRequiredConverged = 19;

Eigen::Matrix3Xd start_for(const lp::Scenario& s, int seed) {
  std::mt19937_64 rng(1000 + seed);
  return lp::random_start_positions_m(s, rng);
}

template <typename MakePlanner>
int count_converged(MakePlanner make) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::RunOptions options;
  options.max_iterations = 1000;
  int converged = 0;
  for (int t = 0; t < kStarts; ++t) {
    lp::Swarm swarm(model, start_for(s, t), {}, 7 + t);
    auto planner = make(s);
    const lp::RunResult r = lp::run_placement(planner, swarm, options);
    // Independent check of the final ICN: the SVD of the full channel at the final positions.
    if (r.converged()) {
      EXPECT_GE(lp::inverse_condition_number(model.matrix(r.final_m)), 0.95 - 1e-9);
    }
    converged += r.converged();
  }
  return converged;
}
}  // namespace

TEST(GradientDescent, PaperDefaults_ConvergeFromAlmostAllRandomStarts) {
  const int n = count_converged([](const lp::Scenario& s) { return lp::GradientDescentPlanner(s, {}); });
  EXPECT_GE(n, kRequiredConverged);
}

TEST(BruteForce, PaperDefaults_ConvergeFromAlmostAllRandomStarts) {
  const int n = count_converged([](const lp::Scenario& s) { return lp::BruteForcePlanner(s, {}); });
  EXPECT_GE(n, kRequiredConverged);
}

TEST(BruteForce, OneUavStep_NeverIncreasesTheObjective) {
  // GIVEN: no actuation error, so a probe measures exactly where the UAV then goes
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  for (int t = 0; t < 5; ++t) {
    lp::Swarm swarm(model, start_for(s, t), {}, t);
    for (int m = 0; m < s.num_uavs; ++m) {
      const double before = lp::objective(swarm.channel().H());
      lp::BruteForcePlanner::step_uav(swarm, m, 0.3);
      EXPECT_LE(lp::objective(swarm.channel().H()), before * (1 + 1e-12)) << "uav " << m;
    }
  }
}

TEST(BruteForce, StepUav_MovesByTheStepTimesTheReturnedProbeDirection) {
  // GIVEN: no actuation error, so a UAV's move is exactly what the planner commands.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  constexpr double kStepM = 0.3;
  lp::Swarm swarm(model, start_for(s, 2), {}, 3);
  int moves = 0;
  for (int m = 0; m < s.num_uavs; ++m) {
    const Eigen::Vector3d before = swarm.true_positions_m().col(m);
    const int probe = lp::BruteForcePlanner::step_uav(swarm, m, kStepM);
    // THEN: the probe index is in range and the UAV moved by b z_probe (z_0 = 0: it stayed).
    ASSERT_GE(probe, 0);
    ASSERT_LT(probe, lp::kBfNumProbes);
    const Eigen::Vector3d moved = swarm.true_positions_m().col(m) - before;
    EXPECT_LE((moved - kStepM * lp::bf_probe_direction(probe)).norm(), 1e-12) << "uav " << m;
    moves += probe != 0;
  }
  EXPECT_GT(moves, 0);
}

TEST(BruteForce, ProbeDirections_AreStayThenTheSixSignedUnitAxes) {
  EXPECT_EQ(lp::bf_probe_direction(0), Eigen::Vector3d::Zero());
  for (int z = 1; z < lp::kBfNumProbes; ++z) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit((z - 1) / 2);
    EXPECT_EQ(lp::bf_probe_direction(z), (z % 2 == 1 ? 1.0 : -1.0) * e) << "probe " << z;
  }
  EXPECT_THROW(lp::bf_probe_direction(-1), std::out_of_range);
  EXPECT_THROW(lp::bf_probe_direction(lp::kBfNumProbes), std::out_of_range);
}

TEST(GradientDescent, PlannedMove_DescendsUnderPerfectLocalization) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const lp::GradientDescentPlanner gd(s, {});
  lp::Swarm swarm(model, start_for(s, 3), {}, 1);
  for (int m = 0; m < s.num_uavs; ++m) {
    const Eigen::Vector3d q = swarm.true_positions_m().col(m);
    const Eigen::Vector3d r = gd.plan_move(swarm, m, q, 1);
    const lp::UavObjective view(swarm.channel(), m);
    EXPECT_LT(view.objective_at(q + r), view.objective_at(q)) << "uav " << m;
    EXPECT_LE(r.norm(), lp::GdOptions{}.max_move_m + 1e-12);
  }
}

TEST(Ura, WithoutErrors_BothVariantsOrthogonaliseInOneIterationAndLatticeTravelsLess) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  double rigid_travel = 0.0;
  double lattice_travel = 0.0;
  for (int t = 0; t < 10; ++t) {
    for (const lp::UraVariant v : {lp::UraVariant::kRigid, lp::UraVariant::kLattice}) {
      lp::Swarm swarm(model, start_for(s, t), {}, t);
      lp::UraPlanner ura(s, v);
      const lp::RunResult r = lp::run_placement(ura, swarm, {});
      EXPECT_TRUE(r.converged());
      EXPECT_EQ(r.iterations, 1);
      // The lattice keeps orthogonality only in the paraxial approximation (ICN ~0.99).
      EXPECT_GT(lp::inverse_condition_number(model.matrix(r.final_m)), v == lp::UraVariant::kRigid ? 0.999 : 0.98);
      (v == lp::UraVariant::kRigid ? rigid_travel : lattice_travel) += r.placement_dist_m.mean();
    }
  }
  EXPECT_LT(lattice_travel, 0.5 * rigid_travel);
}

TEST(Ura, UnderErrors_RetriesEachIterationAndGetsCloserToTargets) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, start_for(s, 0), {0.0, 0.5}, 3);
  lp::UraPlanner ura(s, lp::UraVariant::kRigid);
  lp::RunOptions options;
  options.target_icn = 1.0;  // never reached: run all iterations
  options.max_iterations = 5;
  const lp::RunResult r = lp::run_placement(ura, swarm, options);
  EXPECT_EQ(r.iterations, 5);
  // Each retry flies ~ the last residual error: travel grows beyond the first leg.
  EXPECT_GT(r.trace.back().placement_dist_m, r.trace[1].placement_dist_m + 0.5);
  const double residual = (r.final_m - ura.targets_m()).colwise().norm().mean();
  EXPECT_LT(residual, 2.0);  // ~ sigma_act * sqrt(3) = 0.87 m on average
}

TEST(Ura, NeedsAsManyUavsAsAntennas) {
  lp::Scenario s;
  s.num_uavs = 20;
  EXPECT_THROW(lp::UraPlanner(s, lp::UraVariant::kRigid), std::invalid_argument);
}

TEST(RunPlacement, RecordsMilestonesConsistentlyWithTheTrace) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, start_for(s, 2), {0.02, 0.01}, 2);
  lp::GradientDescentPlanner gd(s, {});
  const lp::RunResult r = lp::run_placement(gd, swarm, {});
  ASSERT_TRUE(r.icn050.reached);
  ASSERT_EQ(static_cast<int>(r.trace.size()), r.iterations + 1);
  EXPECT_GE(r.trace[r.icn050.iteration].icn, 0.5);
  EXPECT_LT(r.trace[r.icn050.iteration - 1].icn, 0.5);
  EXPECT_DOUBLE_EQ(r.icn050.placement_dist_m, r.trace[r.icn050.iteration].placement_dist_m);
  EXPECT_DOUBLE_EQ(r.trace.back().placement_dist_m, r.placement_dist_m.mean());
}
