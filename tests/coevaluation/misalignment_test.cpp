// The bs_misalignment_rad sweep: a BS array turned off its bearing is a common-mode error of
// every beacon fix, the matched Gaussian rows take gd_ekf's split of it, and the report says which
// error measure orders the outcomes.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/fusion/coevaluation/report.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/summary.h"
#include "losmimo/placement/swarm_shape.h"

namespace losmimo::coevaluation {
namespace {

constexpr double kBias_rad = 0.0009765625;  // ~1 mrad, exact in INI text

// 2 x 2 BS at 1 m spacing, 4 UAVs (ideal spacing 5 m), one trial, the sweep at 0 and kBias_rad.
experiment::ExperimentSettings settings(const std::vector<std::string>& sets) {
  common::IniConfig cfg;
  for (const char* s :
       {"experiment.sweeps=bs_misalignment_rad", "experiment.trials=1", "experiment.plots=false", "scenario.bs_rows=2",
        "scenario.bs_cols=2", "scenario.num_uavs=4", "scenario.bs_spacing_m=1", "placement.max_iterations=40",
        "errors.sigma_act_m=0", "coevaluation.misalignment_values_rad=0, 0.0009765625"})
    cfg.set_override(s);
  for (const std::string& s : sets) cfg.set_override(s);
  return experiment::load_experiment_settings(cfg, experiment_extensions());
}

const experiment::TrialRecord& record_of(const std::vector<experiment::TrialRecord>& records, const std::string& a) {
  for (const experiment::TrialRecord& r : records) {
    if (r.algorithm == a) return r;
  }
  throw std::runtime_error("no record of " + a);
}

TEST(MisalignmentSweep, GdEkfsCommonOffset_IsTheRangeTimesTheAngle_ItsShapeStaysSmall) {
  // GIVEN: gd_ekf at an aligned and a misaligned BS array.
  const experiment::ExperimentSettings s = settings({"coevaluation.misalignment_algorithms=gd_ekf"});
  const CoevaluationSettings c = load_coevaluation_settings(s);
  const double range_m = s.placement.scenario.range_m();
  // WHEN: one trial at each point.
  const experiment::TrialRecord aligned = run_misalignment_trial(s, c, 0, 0).at(0);
  const experiment::TrialRecord turned = run_misalignment_trial(s, c, 1, 0).at(0);
  // THEN: the turned array moves every fix by ~R x angle the same way (first order in the angle),
  // which shows in the common offset and not in the shape.
  const double common = turned.extension.at(kCommonLateral);
  EXPECT_NEAR(common, range_m * kBias_rad, 0.1 * range_m * kBias_rad + aligned.extension.at(kCommonLateral));
  EXPECT_GT(turned.extension.at(kLocLateralRmse), 5.0 * aligned.extension.at(kLocLateralRmse));
  EXPECT_LT(turned.extension.at(kShapeLateralRmse), 0.2 * common);
}

TEST(MisalignmentSweep, MatchedGaussians_TakeGdEkfsAbsoluteShapeAndCommonErrors) {
  // GIVEN: the default rows at the misaligned point.
  const experiment::ExperimentSettings s = settings({});
  const CoevaluationSettings c = load_coevaluation_settings(s);
  const std::vector<experiment::TrialRecord> records = run_misalignment_trial(s, c, 1, 0);
  const experiment::TrialRecord& ekf = record_of(records, "gd_ekf");
  // THEN: each matched row's expected error (by construction of its sigmas) is the ekf's measured
  // one, in the measure it matches.
  EXPECT_NEAR(record_of(records, "gd_gauss_matched").extension.at(kLocLateralRmse), ekf.extension.at(kLocLateralRmse),
              1e-12);
  EXPECT_NEAR(record_of(records, "gd_gauss_shape_matched").extension.at(kShapeLateralRmse),
              ekf.extension.at(kShapeLateralRmse), 1e-12);
  const experiment::TrialRecord& split = record_of(records, "gd_gauss_split_matched");
  EXPECT_NEAR(split.extension.at(kShapeLateralRmse), ekf.extension.at(kShapeLateralRmse), 1e-12);
  EXPECT_NEAR(split.extension.at(kCommonLateral), ekf.extension.at(kCommonLateral), 1e-12);
  // AND: the shape-matched row's common offset is only what its independent errors average to
  // (v sqrt(2 / N) against the misaligned ekf's ~R x angle).
  EXPECT_LT(record_of(records, "gd_gauss_shape_matched").extension.at(kCommonLateral),
            0.2 * ekf.extension.at(kCommonLateral));
  // AND: gd_gauss is the paper's model of the beacon noise alone: blind to the misalignment.
  EXPECT_NEAR(record_of(records, "gd_gauss").extension.at(kLocLateralRmse),
              std::sqrt(2.0) * c.misalignment_beacon_noise_m, 1e-15);
}

TEST(MisalignmentSweep, CommonModePartOfTheGaussianRows_ComesFromErrorsSigmaLocCommon) {
  // GIVEN: gd_gauss with and without [errors] sigma_loc_common_m.
  const experiment::ExperimentSettings plain = settings({"coevaluation.misalignment_algorithms=gd_gauss"});
  const experiment::ExperimentSettings common =
      settings({"coevaluation.misalignment_algorithms=gd_gauss", "errors.sigma_loc_common_m=0.5"});
  const experiment::TrialRecord a = run_misalignment_trial(plain, load_coevaluation_settings(plain), 0, 0).at(0);
  const experiment::TrialRecord b = run_misalignment_trial(common, load_coevaluation_settings(common), 0, 0).at(0);
  // THEN: the expected common offset adds 2 x 0.5^2 in quadrature, the shape is unchanged, and the
  // run differs (the planner saw the offset).
  const double v = load_coevaluation_settings(plain).misalignment_beacon_noise_m;
  const placement::ExpectedSwarmSplit independent = placement::expected_split_of_independent_errors(4, v);
  EXPECT_NEAR(a.extension.at(kCommonLateral), independent.common_lateral_rms_m, 1e-15);
  EXPECT_NEAR(b.extension.at(kCommonLateral),
              std::sqrt(independent.common_lateral_rms_m * independent.common_lateral_rms_m + 2.0 * 0.5 * 0.5), 1e-15);
  EXPECT_EQ(a.extension.at(kShapeLateralRmse), b.extension.at(kShapeLateralRmse));
  EXPECT_NE(a.final_m, b.final_m);
}

TEST(MisalignmentSweep, ARowWithoutPositions_OrAUraWithTheWrongSwarm_IsRefusedNamingTheField) {
  try {
    settings({"coevaluation.misalignment_algorithms=gd_ekf, ura_ekf", "scenario.num_uavs=3"});
    FAIL() << "accepted ura_ekf with 3 UAVs on 4 antennas";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("misalignment_algorithms"), std::string::npos) << e.what();
  }
  try {
    settings({"coevaluation.misalignment_values_rad=0, 0.5"});
    FAIL() << "accepted a misalignment of 0.5 rad";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("misalignment_values_rad"), std::string::npos) << e.what();
  }
}

// A summary row with the metrics the error-measure section reads.
experiment::SummaryRow row(const std::string& sweep, double value, const std::string& algorithm, double lateral_m,
                           double shape_m, double icn) {
  experiment::SummaryRow r;
  r.sweep = sweep;
  r.value = value;
  r.algorithm = algorithm;
  r.trials = 4;
  r.metrics = {{kLocLateralRmse.name, {lateral_m, 0.01, 4}},
               {kShapeLateralRmse.name, {shape_m, 0.01, 4}},
               {"final_icn", {icn, 0.01, 4}},
               {"sinr_nv_db", {20.0 * icn, 0.1, 4}},
               {"dist_to_icn095_m", {10.0 + lateral_m, 1.0, 4}}};
  return r;
}

TEST(ErrorMeasureSection, CorrelationsAreSpearmansAndPearsons_AndNameTheStrongerMeasure) {
  // GIVEN: misalignment points whose ICN falls exactly with the shape RMSE while the lateral RMSE
  // rises monotonically and out of step with it.
  const std::vector<experiment::SummaryRow> rows = {
      row(kSweepMisalignment, 0.0, "gd_ekf", 1.0, 0.05, 0.95), row(kSweepMisalignment, 1.0, "gd_ekf", 2.0, 0.04, 0.96),
      row(kSweepMisalignment, 2.0, "gd_ekf", 3.0, 0.07, 0.93), row(kSweepMisalignment, 3.0, "gd_ekf", 4.0, 0.03, 0.97),
      // Beacon noise: x = 1, 2, 3 and ICN 0.2, 0.4, 0.7 (Pearson 5 / sqrt(2 x 12.667) = 0.9934,
      // worked by hand), shape a constant: not evaluated.
      row(kSweepBeaconNoise, 0.0, "gd_ekf", 1.0, 0.05, 0.2), row(kSweepBeaconNoise, 1.0, "gd_ekf", 2.0, 0.05, 0.4),
      row(kSweepBeaconNoise, 2.0, "gd_ekf", 3.0, 0.05, 0.7)};
  // WHEN
  const std::string md = error_measure_section(rows);
  // THEN: on the misalignment points the shape ranks ICN exactly (-1) and the lateral RMSE does
  // not (ranks 1 2 3 4 against ICN ranks 2 3 1 4: rho = 1 - 6 x 6 / (4 x 15) = 0.4).
  EXPECT_NE(md.find("| `bs_misalignment_rad` | final ICN | 4 | 0.40 ("), std::string::npos) << md;
  EXPECT_NE(md.find("| -1.00 (-1.00) | shape RMSE |"), std::string::npos) << md;
  // AND: Pearson's on the hand-worked beacon-noise points, and a constant column is not evaluated.
  EXPECT_NE(md.find("| `beacon_noise_m` | final ICN | 3 | 1.00 (0.99) | n/a (n/a) | not evaluated"), std::string::npos)
      << md;
  // AND: the pooled points appear as their own group.
  EXPECT_NE(md.find("| all of them | final ICN | 7 |"), std::string::npos) << md;
  // AND: the answer is read off the pooled group.
  EXPECT_NE(md.find("Over all of them: final ICN is ordered better by the shape RMSE (|r| 0.61 against 0.46);"),
            std::string::npos)
      << md;
}

TEST(ErrorMeasureSection, WithoutCoevaluationRows_IsEmpty) {
  EXPECT_EQ(error_measure_section({row("sigma_loc_m", 0.0, "gd", 1.0, 0.5, 0.9)}), "");
}

TEST(MisalignmentSweep, Report_HasItsTableMatchedSectionsAndTheErrorMeasureAnswer) {
  const experiment::ExperimentSettings s = settings({});
  const CoevaluationSettings c = load_coevaluation_settings(s);
  std::vector<experiment::TrialRecord> records;
  for (int point = 0; point < 2; ++point) {
    for (experiment::TrialRecord& r : run_misalignment_trial(s, c, point, 0)) records.push_back(std::move(r));
  }
  const std::vector<experiment::SummaryRow> rows =
      experiment::summarize(records, experiment::extra_metric_names(s, experiment_extensions()));
  const std::string md = misalignment_report_section(s, rows);
  EXPECT_NE(md.find("## Co-evaluation: BS array misalignment"), std::string::npos);
  EXPECT_NE(md.find("| 0.000 | gd_ekf |"), std::string::npos) << md;  // the aligned point [mrad]
  EXPECT_NE(md.find("| 0.97"), std::string::npos) << md;              // 1e3 x kBias_rad
  EXPECT_NE(md.find("### Integrating the estimator at matched shape and common error"), std::string::npos);
  EXPECT_NE(md.find("## Which localization error predicts capacity"), std::string::npos);
}

}  // namespace
}  // namespace losmimo::coevaluation
