// Centralized solution of eq. 4 (fusion/centralized.h): seeded starts, checked independently.
#include "losmimo/fusion/centralized.h"

#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "losmimo/placement/assignment.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/ura.h"

namespace losmimo::fusion {
namespace {

TEST(TravelStats, TwoUavs_SumsMeansAndSquares) {
  Eigen::Matrix3Xd from(3, 2), to(3, 2);
  from << 0, 0, 0, 0, 0, 0;
  to << 3, 0, 4, 0, 0, 0;  // columns (3,4,0) and (0,0,0)
  const TravelStats t = travel_stats(from, to);
  EXPECT_DOUBLE_EQ(t.total_m, 5.0);
  EXPECT_DOUBLE_EQ(t.mean_m, 2.5);
  EXPECT_DOUBLE_EQ(t.max_m, 5.0);
  EXPECT_DOUBLE_EQ(t.total_squared_m2, 25.0);
  EXPECT_DOUBLE_EQ(t.mean_squared_m2, 12.5);
}

TEST(CentralizedConfig, BadField_ThrowsNamingFieldAndValue) {
  CentralizedConfig c;
  c.mu_growth = 0.5;
  try {
    validate(c);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mu_growth = 0.5"), std::string::npos) << e.what();
  }
  CentralizedConfig a;
  a.target_icn = 1.0;
  EXPECT_THROW(validate(a), std::invalid_argument);
  EXPECT_NO_THROW(validate(CentralizedConfig{}));
}

// The rigid URA's eq. 4 travel, computed here from placement's slots and assignment only.
double rigid_ura_squared_travel(const placement::Scenario& scenario, const Eigen::Matrix3Xd& start) {
  const Eigen::Matrix3Xd slots = placement::optimal_ura_positions_m(scenario);
  const int n = static_cast<int>(start.cols());
  Eigen::MatrixXd cost(n, n);
  for (int m = 0; m < n; ++m) {
    for (int s = 0; s < n; ++s) cost(m, s) = (slots.col(s) - start.col(m)).squaredNorm();
  }
  const std::vector<int> slot_of = placement::min_cost_assignment(cost);
  double total = 0.0;
  for (int m = 0; m < n; ++m) total += cost(m, slot_of[m]);
  return total;
}

constexpr int kNumStarts = 4;

TEST(SolveCentralized, SeededStarts_MeetIcnAndTravelLessThanRigidUra) {
  const placement::Scenario scenario;  // paper defaults: 16 UAVs, 4x4 BS, 1 km, 60 GHz
  const placement::ChannelModel model(scenario);
  const CentralizedConfig config;
  std::mt19937_64 rng(41);
  for (int trial = 0; trial < kNumStarts; ++trial) {
    const Eigen::Matrix3Xd start = placement::random_start_positions_m(scenario, rng);
    const CentralizedResult r = solve_centralized(scenario, start, config);
    std::cout << "start " << trial << ": " << to_string(r.status) << " from " << to_string(r.best_start)
              << (r.best_is_raw_ura ? " (raw)" : "") << ", ICN " << r.icn << ", mean travel " << r.travel.mean_m
              << " m (squared mean " << r.travel.mean_squared_m2 << " m^2), polished " << r.polished << ", solves "
              << r.num_solves << "\n  lattice URA: ICN " << r.lattice_ura_icn << ", mean travel "
              << r.lattice_ura_travel.mean_m << " m (squared " << r.lattice_ura_travel.mean_squared_m2
              << ")\n  rigid URA:   ICN " << r.rigid_ura_icn << ", mean travel " << r.rigid_ura_travel.mean_m
              << " m (squared " << r.rigid_ura_travel.mean_squared_m2 << ")\n";
    ASSERT_EQ(r.status, CentralizedStatus::kFeasible);
    // ICN recomputed from the positions by placement's SVD, independent of the solver.
    EXPECT_GE(placement::inverse_condition_number(model.matrix(r.positions_m)), config.target_icn);
    const double travel2 = (r.positions_m - start).squaredNorm();
    EXPECT_LE(travel2, rigid_ura_squared_travel(scenario, start));
    // And no more than the lattice URA, computed here by placement's own planner.
    placement::Swarm swarm(model, start, placement::ErrorModel{}, 1);
    placement::UraPlanner lattice(scenario, placement::UraVariant::kLattice);
    lattice.start(swarm);
    if (placement::inverse_condition_number(model.matrix(lattice.targets_m())) >= config.target_icn) {
      EXPECT_LE(travel2, (lattice.targets_m() - start).squaredNorm());
    }
    // Euclidean travel too: below the rigid URA of placement's own planner (Euclidean assignment).
    placement::UraPlanner rigid(scenario, placement::UraVariant::kRigid);
    rigid.start(swarm);
    EXPECT_LE((r.positions_m - start).colwise().norm().sum(), (rigid.targets_m() - start).colwise().norm().sum());
    // The reported travel is that of the reported positions.
    EXPECT_NEAR(r.travel.total_squared_m2, travel2, 1e-9 * travel2);
  }
}

TEST(SolveCentralized, PenaltyAndRigidUraOnly_StillFeasibleAndNoWorseThanRigidUra) {
  // Without the GD and lattice starts, the penalty continuation from the start positions may
  // stall (local minima with ICN < alpha); the rigid URA then bounds the result.
  const placement::Scenario scenario;
  const placement::ChannelModel model(scenario);
  CentralizedConfig config;
  config.start_from_gd = false;
  config.start_from_lattice_ura = false;
  std::mt19937_64 rng(42);
  for (int trial = 0; trial < 2; ++trial) {
    const Eigen::Matrix3Xd start = placement::random_start_positions_m(scenario, rng);
    const CentralizedResult r = solve_centralized(scenario, start, config);
    ASSERT_EQ(r.status, CentralizedStatus::kFeasible);
    EXPECT_NE(r.best_start, CentralizedStart::kGd);
    EXPECT_NE(r.best_start, CentralizedStart::kLatticeUra);
    EXPECT_GE(placement::inverse_condition_number(model.matrix(r.positions_m)), config.target_icn);
    EXPECT_LE((r.positions_m - start).squaredNorm(), rigid_ura_squared_travel(scenario, start));
  }
}

TEST(SolveCentralized, UnreachableAlpha_StatusMatchesPositions) {
  // alpha above the rigid URA's own ICN at 1 km (0.9996): infeasible, or feasible for real.
  const placement::Scenario scenario;
  const placement::ChannelModel model(scenario);
  CentralizedConfig config;
  config.target_icn = 0.99999;
  config.start_from_gd = false;
  config.mu_max = 1.0;
  std::mt19937_64 rng(43);
  const Eigen::Matrix3Xd start = placement::random_start_positions_m(scenario, rng);
  const CentralizedResult r = solve_centralized(scenario, start, config);
  std::cout << "alpha " << config.target_icn << ": " << to_string(r.status) << ", ICN " << r.icn << "\n";
  if (r.status == CentralizedStatus::kFeasible) {
    EXPECT_GE(placement::inverse_condition_number(model.matrix(r.positions_m)), config.target_icn);
  } else {
    EXPECT_EQ(r.best_start, CentralizedStart::kNone);
    EXPECT_TRUE(r.positions_m.isApprox(start));
    EXPECT_EQ(r.travel.total_m, 0.0);
  }
  EXPECT_LT(r.rigid_ura_icn, config.target_icn);
}

TEST(SolveCentralized, WrongStartShape_Throws) {
  const placement::Scenario scenario;
  EXPECT_THROW(solve_centralized(scenario, Eigen::Matrix3Xd::Zero(3, 5), CentralizedConfig{}), std::invalid_argument);
}

}  // namespace
}  // namespace losmimo::fusion
