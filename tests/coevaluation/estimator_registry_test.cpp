// The two registries: a planner and an estimator registered from the test tree run through the
// experiment and the co-evaluation with no change to either engine; rows are (planner,
// estimator) pairs with today's names as aliases. Its own executable: the test entries it
// registers never reach another suite's registry listings (registries_markdown_test.cpp).
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/estimator_registry.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/trial.h"
#include "losmimo/placement/planner_registry.h"

namespace losmimo::coevaluation {
namespace {

constexpr double kStepY_m = 0.01;  // the test planner's move per UAV and iteration
constexpr int kSteps = 3;          // its own stop rule

// A planner that moves every UAV by kStepY_m along +y per iteration, for kSteps iterations: its
// result is known in closed form (start + kSteps * kStepY_m along y, without actuation error).
class StepPlanner : public placement::Planner {
 public:
  std::string name() const override { return "test_step"; }
  void iterate(placement::Swarm& swarm, int /*iteration*/) override {
    for (int m = 0; m < swarm.num_uavs(); ++m) {
      swarm.move(m, Eigen::Vector3d(0.0, kStepY_m, 0.0), placement::MotionKind::kPlacement);
    }
  }
};

// Registered once per process (ctest runs each test in its own).
void register_test_entries() {
  if (!placement::find_planner("test_step")) {
    placement::PlannerEntry p;
    p.name = "test_step";
    p.summary = "test only: every UAV 1 cm along +y per iteration, 3 iterations";
    p.uses_positions = false;
    p.make = [](const placement::PlacementSettings&) { return std::make_unique<StepPlanner>(); };
    p.stop_rule = [](const placement::PlacementSettings&, placement::RunOptions run) {
      run.max_iterations = kSteps;
      run.target_icn = 1.0;  // never reached: the cap stops it
      return run;
    };
    placement::register_planner(std::move(p));
  }
  if (!find_estimator("test_told")) {
    // truth's run, with the localization columns saying what it was told: RMSE 0.
    EstimatorEntry e;
    e.name = "test_told";
    e.summary = "test only: the true positions, reported as an estimator with zero error";
    e.refuses = [](const placement::PlannerEntry&) { return std::nullopt; };
    e.run = [](const CoevalRow& row, const placement::PlannerEntry& planner, const CoevalTrial& t) {
      experiment::TrialRecord r = estimator_entry("truth").run(row, planner, t);
      r.extension.set(kLocRmse, 0.0);
      r.extension.set(kLocLateralRmse, 0.0);
      return r;
    };
    register_estimator(std::move(e));
  }
}

experiment::ExperimentSettings settings(const std::vector<std::string>& sets) {
  common::IniConfig cfg;
  cfg.set_override("experiment.trials=2");
  cfg.set_override("errors.sigma_act_m=0");
  for (const std::string& s : sets) cfg.set_override(s);
  return experiment::load_experiment_settings(cfg, experiment_extensions());
}

TEST(Registries, TestPlanner_RunsInTheBuiltInSweep_ToItsClosedFormPositions) {
  register_test_entries();
  // GIVEN: the built-in sigma_loc sweep with the test planner beside random.
  const experiment::ExperimentSettings s =
      settings({"experiment.sweeps=sigma_loc_m", "experiment.sigma_loc_values_m=0, 0.1",
                "experiment.algorithms=random, test_step", "experiment.plots=false"});
  // WHEN: the experiment's engine runs it.
  const experiment::ExperimentResults results = experiment::run_experiment(s, experiment_extensions(), 2);
  // THEN: every test_step record is the start moved kSteps * 1 cm along y, after kSteps iterations.
  int seen = 0;
  for (const experiment::TrialRecord& r : results.records) {
    if (r.algorithm != "test_step") continue;
    ++seen;
    Eigen::Matrix3Xd expected = experiment::trial_start_positions_m(s, r.trial);
    expected.row(1).array() += kSteps * kStepY_m;
    EXPECT_EQ(r.iterations, kSteps);
    EXPECT_EQ(r.status, "iteration_cap");
    EXPECT_LT((r.final_m - expected).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(r.dist_placement_m, kSteps * kStepY_m, 1e-12);
  }
  EXPECT_EQ(seen, 4);  // 2 points x 2 trials
}

TEST(Registries, TestPlannerAndEstimator_RunAsCoevaluationRows_LikeTheirBuiltInNeighbours) {
  register_test_entries();
  // GIVEN: co-evaluation rows pairing the test planner with truth, and gd with the test estimator.
  const experiment::ExperimentSettings s =
      settings({"experiment.sweeps=beacon_noise_m", "coevaluation.beacon_noise_values_m=0.05",
                "placement.max_iterations=40", "coevaluation.algorithms=test_step+truth, gd+test_told, gd+truth"});
  const CoevaluationSettings c = load_coevaluation_settings(s);
  ASSERT_EQ(c.algorithms.size(), 3u);
  EXPECT_EQ(c.algorithms[0].name, "test_step+truth");
  for (int trial = 0; trial < 2; ++trial) {
    const std::vector<experiment::TrialRecord> records = run_beacon_noise_trial(s, c, 0, trial);
    ASSERT_EQ(records.size(), 3u);
    // THEN: the test planner's row is its closed form; the test estimator's row is gd on the
    // true positions (the same run as gd+truth) with the columns it set.
    Eigen::Matrix3Xd expected = experiment::trial_start_positions_m(s, trial);
    expected.row(1).array() += kSteps * kStepY_m;
    EXPECT_LT((records[0].final_m - expected).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(records[1].algorithm, "gd+test_told");
    EXPECT_EQ(records[1].final_m, records[2].final_m);
    EXPECT_EQ(records[1].iterations, records[2].iterations);
    EXPECT_EQ(records[1].extension.at(kLocRmse), 0.0);
    EXPECT_TRUE(std::isnan(records[2].extension.at(kLocRmse)));
  }
}

TEST(Registries, TodaysNames_AreAliasesOfPairs_AndAnExplicitPairTakesItsAlias) {
  const experiment::ExperimentSettings s = settings(
      {"experiment.sweeps=beacon_noise_m", "coevaluation.algorithms=gd+ekf, bf, ura_ekf, cap+ekf, gd+gauss_matched"});
  const CoevaluationSettings c = load_coevaluation_settings(s);
  const std::vector<std::vector<std::string>> expected = {{"gd_ekf", "gd", "ekf"},
                                                          {"bf", "bf", "truth"},
                                                          {"ura_ekf", "ura", "ekf"},
                                                          {"cap_ekf", "cap", "ekf"},
                                                          {"gd_gauss_matched", "gd", "gauss_matched"}};
  ASSERT_EQ(c.algorithms.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(c.algorithms[i].name, expected[i][0]);
    EXPECT_EQ(c.algorithms[i].planner, expected[i][1]);
    EXPECT_EQ(c.algorithms[i].estimator, expected[i][2]);
  }
  // ura_ekf follows ura_variant.
  const CoevaluationSettings lattice = load_coevaluation_settings(settings(
      {"experiment.sweeps=beacon_noise_m", "coevaluation.algorithms=ura_ekf", "coevaluation.ura_variant=lattice"}));
  EXPECT_EQ(lattice.algorithms.at(0).planner, "ura_lattice");
}

std::string error_of(const std::vector<std::string>& sets) {
  try {
    load_coevaluation_settings(settings(sets));
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Registries, PairsTheirEstimatorRefuses_AndDuplicates_AreRefusedNamingTheKey) {
  const std::string sweep = "experiment.sweeps=beacon_noise_m";
  const auto refused = [](const std::string& message, const std::string& reason) {
    EXPECT_NE(message.find("[coevaluation] algorithms: " + reason), std::string::npos) << message;
  };
  refused(error_of({sweep, "coevaluation.algorithms=bf+ekf"}),
          "bf+ekf: bf does not place from position estimates: ekf cannot reach it (pair it with truth)");
  refused(error_of({sweep, "coevaluation.algorithms=ura+ekf_ceres"}),
          "ura+ekf_ceres: ekf_ceres refines with the closed loop's CSI: it pairs with gd only");
  refused(error_of({sweep, "coevaluation.algorithms=gd_ekf, gd+ekf"}), "algorithm 'gd_ekf' listed twice");
  EXPECT_NE(error_of({sweep, "coevaluation.algorithms=gd+kalman"}).find("unknown estimator 'kalman' (known: truth, "),
            std::string::npos);
  EXPECT_NE(error_of({sweep, "coevaluation.algorithms=ga+ekf"}).find("unknown planner 'ga' (known: random, gd, "),
            std::string::npos);
  EXPECT_NE(error_of({"experiment.sweeps=beacon_outage", "coevaluation.outage_algorithms=ura+ekf"})
                .find("ura_ekf: the outage sweep runs gd's closed loop"),
            std::string::npos);
  // The experiment's built-in sweeps take iterative planners only.
  try {
    settings({"experiment.algorithms=gd, centralized"});
    ADD_FAILURE() << "centralized accepted in [experiment] algorithms";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'centralized' computes its placement at once"), std::string::npos)
        << e.what();
  }
}

TEST(Registries, RegisteringANameTwice_OrAMalformedEntry_IsRefused) {
  placement::PlannerEntry gd;
  gd.name = "gd";
  gd.make = [](const placement::PlacementSettings&) { return std::unique_ptr<placement::Planner>(); };
  EXPECT_THROW(placement::register_planner(gd), std::invalid_argument);
  placement::PlannerEntry none;
  none.name = "test_none";  // neither make nor solve
  EXPECT_THROW(placement::register_planner(none), std::invalid_argument);
  placement::PlannerEntry bad = gd;
  bad.name = "Bad Name";
  EXPECT_THROW(placement::register_planner(bad), std::invalid_argument);
  EstimatorEntry truth;
  truth.name = "truth";
  truth.refuses = [](const placement::PlannerEntry&) { return std::nullopt; };
  truth.run = estimator_entry("truth").run;
  EXPECT_THROW(register_estimator(truth), std::invalid_argument);
}

}  // namespace
}  // namespace losmimo::coevaluation
