// Numerical health of a placement run: run_placement ends with kNumericalFault,
// naming the UAV and the quantity, as soon as a move, a position, a channel row or the Gram
// matrix is non-finite; a planner can end the run with its own fault (Planner::fault).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <string>

#include "losmimo/placement/gd.h"
#include "losmimo/placement/run.h"

namespace lp = losmimo::placement;

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

Eigen::Matrix3Xd start_for(const lp::Scenario& s, int seed) {
  std::mt19937_64 rng(1000 + seed);
  return lp::random_start_positions_m(s, rng);
}

// Moves every UAV by a small step each iteration; at `bad_iteration` UAV `bad_uav` is
// commanded `bad_move` instead.
class ScriptedPlanner : public lp::Planner {
 public:
  ScriptedPlanner(int bad_iteration, int bad_uav, const Eigen::Vector3d& bad_move)
      : bad_iteration_(bad_iteration), bad_uav_(bad_uav), bad_move_(bad_move) {}
  std::string name() const override { return "scripted"; }
  void iterate(lp::Swarm& swarm, int iteration) override {
    for (int m = 0; m < swarm.num_uavs(); ++m) {
      const bool bad = iteration == bad_iteration_ && m == bad_uav_;
      swarm.move(m, bad ? bad_move_ : Eigen::Vector3d(0.0, 1e-3, 0.0), lp::MotionKind::kPlacement);
    }
  }

 private:
  int bad_iteration_, bad_uav_;
  Eigen::Vector3d bad_move_;
};

// Reports a fault of its own from `fault_iteration` on.
class FaultyPlanner : public lp::Planner {
 public:
  explicit FaultyPlanner(int fault_iteration) : fault_iteration_(fault_iteration) {}
  std::string name() const override { return "faulty"; }
  void iterate(lp::Swarm& /*swarm*/, int iteration) override { iteration_ = iteration; }
  std::optional<lp::PlannerFault> fault() const override {
    if (iteration_ < fault_iteration_) return std::nullopt;
    return lp::PlannerFault{lp::RunStatus::kUavUnresponsive, 6, "UAV 6: silent"};
  }

 private:
  int fault_iteration_;
  int iteration_ = 0;
};

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(RunStatus, ToString_NamesEveryStatus) {
  EXPECT_EQ(lp::to_string(lp::RunStatus::kConverged), "converged");
  EXPECT_EQ(lp::to_string(lp::RunStatus::kIterationCap), "iteration_cap");
  EXPECT_EQ(lp::to_string(lp::RunStatus::kUavUnresponsive), "uav_unresponsive");
  EXPECT_EQ(lp::to_string(lp::RunStatus::kNumericalFault), "numerical_fault");
}

TEST(RunHealth, NanMoveOfOneUav_EndsTheRunWithANumericalFaultNamingItAndTheSwarmStaysFinite) {
  // GIVEN: UAV 3 is commanded a NaN move at iteration 4.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, start_for(s, 0), {}, 1);
  ScriptedPlanner planner(4, 3, Eigen::Vector3d(kNan, 0.0, 0.0));
  lp::RunOptions options;
  options.max_iterations = 50;
  // WHEN
  const lp::RunResult r = lp::run_placement(planner, swarm, options);
  // THEN: the run ends in that iteration, names UAV 3 and the move; the move was refused.
  EXPECT_EQ(r.status, lp::RunStatus::kNumericalFault);
  EXPECT_TRUE(r.faulted());
  EXPECT_FALSE(r.converged());
  EXPECT_EQ(r.iterations, 4);
  EXPECT_EQ(r.fault_uav, 3);
  EXPECT_TRUE(contains(r.fault, "UAV 3: commanded move is non-finite (r = (nan, 0, 0))")) << r.fault;
  EXPECT_TRUE(contains(r.fault, "at iteration 4")) << r.fault;
  EXPECT_TRUE(r.final_m.allFinite());
  EXPECT_TRUE(swarm.channel().gram().allFinite());
  EXPECT_FALSE(lp::check_finite(swarm).has_value());
  ASSERT_EQ(r.trace.size(), 4u);  // iterations 0..3: the faulted iteration is not evaluated
  for (const lp::IterationRecord& rec : r.trace) EXPECT_TRUE(std::isfinite(rec.icn));
}

TEST(RunHealth, StartWithAnOverflowingDistance_EndsAtIterationZeroNamingTheUav) {
  // GIVEN: UAV 2 starts at x = 1e308 m: finite, but its distance to the BS overflows.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  Eigen::Matrix3Xd start = start_for(s, 1);
  start(0, 2) = 1e308;
  lp::Swarm swarm(model, start, {}, 1);
  ScriptedPlanner planner(2, 2, Eigen::Vector3d(1e308, 0.0, 0.0));
  lp::RunOptions options;
  options.max_iterations = 50;
  // WHEN
  const lp::RunResult r = lp::run_placement(planner, swarm, options);
  // THEN: the start has a non-finite channel row; the run stops at iteration 0, before any
  // move and without evaluating the ICN.
  EXPECT_EQ(r.status, lp::RunStatus::kNumericalFault);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.fault_uav, 2);
  EXPECT_TRUE(contains(r.fault, "UAV 2: channel row is non-finite (H(2, 0) = ")) << r.fault;
  EXPECT_TRUE(contains(r.fault, "at iteration 0")) << r.fault;
  EXPECT_TRUE(r.trace.empty());
}

TEST(RunHealth, SwarmRefusesAMoveToAnInfinitePosition) {
  // GIVEN: a swarm whose UAV 5 sits at x = 1e308 m (far, but finite).
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  Eigen::Matrix3Xd start = start_for(s, 2);
  start(0, 5) = 1e308;
  lp::Swarm swarm(model, start, {}, 1);
  // WHEN: it is moved by another 1e308 m.
  const Eigen::Vector3d actual = swarm.move(5, Eigen::Vector3d(1e308, 0.0, 0.0), lp::MotionKind::kPlacement);
  // THEN: nothing moved; the fault names the UAV, its position and the move.
  EXPECT_EQ(actual, Eigen::Vector3d::Zero());
  EXPECT_EQ(swarm.true_positions_m().col(5), start.col(5));
  ASSERT_TRUE(swarm.numerical_fault().has_value());
  EXPECT_EQ(swarm.numerical_fault()->uav, 5);
  EXPECT_TRUE(contains(swarm.numerical_fault()->reason, "UAV 5: move leaves a non-finite position"))
      << swarm.numerical_fault()->reason;
  EXPECT_EQ(swarm.placement_distance_m()(5), 0.0);
}

TEST(RunHealth, FinitePositionWithAnOverflowingChannelRow_IsFoundByTheChannelCheck) {
  // GIVEN: at iteration 3 UAV 7 flies to x ~ 1e200 m: a finite position whose distance to the
  // BS overflows (|q - p|^2 = 1e400), so its channel row becomes NaN.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, start_for(s, 3), {}, 1);
  ScriptedPlanner planner(3, 7, Eigen::Vector3d(1e200, 0.0, 0.0));
  lp::RunOptions options;
  options.max_iterations = 50;
  // WHEN
  const lp::RunResult r = lp::run_placement(planner, swarm, options);
  // THEN
  EXPECT_EQ(r.status, lp::RunStatus::kNumericalFault);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_EQ(r.fault_uav, 7);
  EXPECT_TRUE(r.final_m.allFinite());
  EXPECT_TRUE(contains(r.fault, "UAV 7: channel row is non-finite (H(7, ")) << r.fault;
  EXPECT_TRUE(contains(r.fault, "at iteration 3")) << r.fault;
}

TEST(RunHealth, PlannerFault_EndsTheRunWithItsStatusAndReason) {
  // GIVEN: a planner that reports an unresponsive UAV from iteration 3 on.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, start_for(s, 4), {}, 1);
  FaultyPlanner planner(3);
  lp::RunOptions options;
  options.max_iterations = 100;
  // WHEN
  const lp::RunResult r = lp::run_placement(planner, swarm, options);
  // THEN: not 100 iterations to the cap; the faulted (finite) iteration is still recorded.
  EXPECT_EQ(r.status, lp::RunStatus::kUavUnresponsive);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_EQ(r.fault_uav, 6);
  EXPECT_EQ(r.fault, "UAV 6: silent at iteration 3");
  EXPECT_EQ(r.trace.size(), 4u);
}

TEST(RunHealth, HealthyGdRun_HasNoFault) {
  // GIVEN: the paper's GD from a random start, no errors.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  lp::Swarm swarm(model, start_for(s, 5), {}, 1);
  lp::GradientDescentPlanner planner(s, {});
  // WHEN
  const lp::RunResult r = lp::run_placement(planner, swarm, lp::RunOptions{});
  // THEN
  EXPECT_TRUE(r.status == lp::RunStatus::kConverged || r.status == lp::RunStatus::kIterationCap);
  EXPECT_FALSE(r.faulted());
  EXPECT_TRUE(r.fault.empty());
  EXPECT_EQ(r.fault_uav, -1);
  EXPECT_FALSE(swarm.numerical_fault().has_value());
  EXPECT_FALSE(lp::check_finite(swarm).has_value());
  EXPECT_EQ(r.trace.size(), static_cast<std::size_t>(r.iterations) + 1);
}
