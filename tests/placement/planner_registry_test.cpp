// The planner registry: builtin entries and their stop rules, registration refusals, and a direct
// planner's straight flight against an independent ICN computation (SVD of H).
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/planner_registry.h"
#include "losmimo/placement/scenario.h"
#include "losmimo/placement/settings.h"
#include "losmimo/placement/ura.h"

namespace losmimo::placement {
namespace {

TEST(PlannerRegistry, Builtins_InTheirDocumentedOrder_WithTheirSections) {
  const std::vector<std::string> names = planner_names();
  const std::vector<std::string> builtin = {"random", "gd", "bf", "ura", "ura_lattice", "ura_lattice_exact", "cap"};
  ASSERT_GE(names.size(), builtin.size());
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 7), builtin);
  EXPECT_EQ(planner_entry("gd").sections, std::vector<std::string>{"gd"});
  EXPECT_EQ(planner_entry("ura_lattice").sections, std::vector<std::string>{"ura"});
  EXPECT_FALSE(planner_entry("bf").uses_positions);
  EXPECT_FALSE(planner_entry("random").uses_positions);
  EXPECT_TRUE(planner_entry("cap").uses_positions);
  EXPECT_EQ(find_planner("nope"), nullptr);
  EXPECT_THROW(planner_entry("nope"), std::invalid_argument);
}

TEST(PlannerRegistry, StopRules_TakeEachPlannersOwnOverride_AndTheScenariosNoise) {
  PlacementSettings p;
  p.gd_run.max_iterations = 7;
  p.bf_run.target_icn = 0.9;
  p.ura_run.max_iterations = 3;
  p.cap_run.target_icn = 0.8;
  p.scenario.snr_db = 13.0;  // another noise variance
  RunOptions run;
  run.max_iterations = 100;
  run.target_icn = 0.95;
  run.noise_variance = -1.0;
  const double noise = p.scenario.noise_variance();
  EXPECT_EQ(planner_run_options(planner_entry("gd"), p, run).max_iterations, 7);
  EXPECT_EQ(planner_run_options(planner_entry("gd"), p, run).target_icn, 0.95);
  EXPECT_EQ(planner_run_options(planner_entry("bf"), p, run).target_icn, 0.9);
  EXPECT_EQ(planner_run_options(planner_entry("bf"), p, run).max_iterations, 100);
  EXPECT_EQ(planner_run_options(planner_entry("ura_lattice_exact"), p, run).max_iterations, 3);
  EXPECT_EQ(planner_run_options(planner_entry("cap"), p, run).target_icn, 0.8);
  EXPECT_EQ(planner_run_options(planner_entry("random"), p, run).max_iterations, 0);
  EXPECT_EQ(planner_run_options(planner_entry("gd"), p, run).noise_variance, noise);
}

TEST(PlannerRegistry, MalformedOrDuplicateEntries_AreRefused) {
  PlannerEntry e;
  e.name = "gd";
  e.make = [](const PlacementSettings&) { return std::unique_ptr<Planner>(); };
  EXPECT_THROW(register_planner(e), std::invalid_argument);  // taken
  e.name = "";
  EXPECT_THROW(register_planner(e), std::invalid_argument);
  e.name = "Upper";
  EXPECT_THROW(register_planner(e), std::invalid_argument);
  e.name = "both_kinds";
  e.solve = [](const PlacementSettings&, const Eigen::Matrix3Xd& s) { return DirectSolution{s, true}; };
  EXPECT_THROW(register_planner(e), std::invalid_argument);
  e.make = nullptr;
  e.solve = nullptr;
  EXPECT_THROW(register_planner(e), std::invalid_argument);
  EXPECT_EQ(find_planner("both_kinds"), nullptr);
}

// ICN as sigma_min / sigma_max of H, by SVD: independent of the Gram-matrix path.
double icn_by_svd(const ChannelModel& model, const Eigen::Matrix3Xd& q_m) {
  const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(model.matrix(q_m));
  const Eigen::VectorXd s = svd.singularValues();
  return s(s.size() - 1) / s(0);
}

TEST(FlyStraight, MilestonesAreTheFirstSampledPointsAboveThreshold_AtTheMeanDistanceFlownThen) {
  const Scenario scenario;
  std::mt19937_64 rng(11);
  const Eigen::Matrix3Xd start = random_start_positions_m(scenario, rng);
  const Eigen::Matrix3Xd target = optimal_ura_positions_m(scenario);
  const RunResult r = fly_straight(scenario, "direct", start, {target, true}, 200);
  EXPECT_EQ(r.planner, "direct");
  EXPECT_EQ(r.status, RunStatus::kConverged);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.final_m, target);
  const Eigen::VectorXd flown = (target - start).colwise().norm().transpose();
  EXPECT_LT((r.placement_dist_m - flown).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(r.probe_dist_m.size(), start.cols());
  EXPECT_EQ(r.probe_dist_m.cwiseAbs().maxCoeff(), 0.0);
  // The first of the 201 sampled points whose ICN (by SVD) reaches each threshold.
  const ChannelModel model(scenario);
  for (const auto& [milestone, threshold] : {std::pair{&r.icn050, 0.5}, std::pair{&r.icn095, 0.95}}) {
    int first = -1;
    for (int k = 0; k <= 200 && first < 0; ++k) {
      const double t = k / 200.0;
      if (icn_by_svd(model, start + t * (target - start)) >= threshold) first = k;
    }
    ASSERT_GE(first, 0) << threshold;  // the URA itself is above both
    EXPECT_TRUE(milestone->reached);
    EXPECT_NEAR(milestone->placement_dist_m, first / 200.0 * flown.mean(), 1e-9) << threshold;
  }
  // Infeasible: the iteration cap's status, same flight.
  EXPECT_EQ(fly_straight(scenario, "direct", start, {target, false}).status, RunStatus::kIterationCap);
  // Staying at a random start reaches neither milestone.
  const RunResult stay = fly_straight(scenario, "direct", start, {start, false});
  EXPECT_FALSE(stay.icn095.reached);
}

}  // namespace
}  // namespace losmimo::placement
