// The co-evaluation's metric table (coevaluation_metrics()) against its columns written out here,
// and every algorithm's record of both sweeps against the table: each declared metric set.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/metrics.h"

namespace losmimo::coevaluation {
namespace {

using experiment::ExtensionMetric;
using experiment::TrialRecord;

TEST(CoevaluationMetricTable, NamesOrderAndUnits_AreTheDocumentedColumns) {
  const std::vector<std::pair<std::string, std::string>> expected = {{"loc_rmse_m", "m"},
                                                                     {"loc_lateral_rmse_m", "m"},
                                                                     {"common_lateral_m", "m"},
                                                                     {"shape_lateral_rmse_m", "m"},
                                                                     {"shape_nees", ""},
                                                                     {"nees", ""},
                                                                     {"bf_fallback_fraction", ""},
                                                                     {"beacon_lateral_rmse_m", "m"},
                                                                     {"paired_travel_diff_m", "m"},
                                                                     {"paired_iterations_diff", "iterations"}};
  std::vector<std::pair<std::string, std::string>> table;
  for (const ExtensionMetric& m : coevaluation_metrics()) {
    table.emplace_back(m.name, m.unit);
    EXPECT_GT(std::string(m.doc).size(), 10u) << m.name << ": document it";
  }
  EXPECT_EQ(table, expected);
  // AND both sweeps declare that table
  for (const experiment::ExperimentExtension& e : experiment_extensions()) {
    ASSERT_EQ(e.metrics.size(), expected.size()) << e.sweep;
    for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(e.metrics[i].name, expected[i].first) << e.sweep;
  }
}

TEST(CoevaluationMetricTable, EveryAlgorithmOfBothSweeps_SetsEveryDeclaredMetric) {
  // GIVEN every algorithm of both sweeps, one short trial each
  common::IniConfig config;
  for (const char* o :
       {"experiment.sweeps=beacon_noise_m, beacon_outage", "experiment.trials=1", "placement.max_iterations=40",
        "coevaluation.beacon_noise_values_m=0.1", "closed_loop.num_particles=100", "coevaluation.outage_values=4",
        "coevaluation.outage_algorithms=gd_ekf, gd_ekf_nofallback, gd_pf, gd_ekf_ceres",
        "coevaluation.algorithms=gd_gauss, gd_gauss_matched, gd_gauss_shape_matched, gd_ekf, gd_ekf_nofallback, "
        "gd_pf, gd_ekf_ceres, bf, ura_ekf, centralized"}) {
    config.set_override(o);
  }
  const experiment::ExperimentSettings s = experiment::load_experiment_settings(config, experiment_extensions());
  std::vector<TrialRecord> records = run_beacon_noise_trial(s, 0, 0);
  ASSERT_EQ(records.size(), 10u);
  for (TrialRecord& r : run_outage_trial(s, 0, 0)) records.push_back(std::move(r));
  ASSERT_EQ(records.size(), 14u);
  // THEN each record sets every declared metric (extension_columns refuses one left unset)
  for (const TrialRecord& r : records) {
    std::vector<double> columns;
    ASSERT_NO_THROW(columns = experiment::extension_columns(r, coevaluation_metrics()))
        << r.sweep << " " << r.algorithm;
    // AND NaN where the algorithm has no value: BF and the centralized solution estimate nothing
    if (r.algorithm == "bf" || r.algorithm == "centralized") {
      for (const double v : columns) EXPECT_TRUE(std::isnan(v)) << r.algorithm;
    } else {
      EXPECT_TRUE(std::isfinite(r.extension.at(kLocLateralRmse))) << r.sweep << " " << r.algorithm;
    }
    const bool matched = r.algorithm == "gd_gauss_matched" || r.algorithm == "gd_gauss_shape_matched";
    EXPECT_EQ(std::isnan(r.extension.at(kPairedIterationsDiff)), !matched) << r.algorithm;
    // AND a shape NEES exactly where there are beliefs with covariances: the filter rows
    const bool filter = r.algorithm.find("ekf") != std::string::npos || r.algorithm.find("pf") != std::string::npos;
    EXPECT_EQ(std::isfinite(r.extension.at(kShapeNees)), filter) << r.sweep << " " << r.algorithm;
  }
}

}  // namespace
}  // namespace losmimo::coevaluation
