// The metric tables drive trials.csv, summary.csv, the exact records and the reports' look-ups:
// these tests hold them to the documented columns, units and TrialRecord's fields, written out
// here independently, and check that an extension record cannot leave a declared metric unset.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/channel_sweeps.h"
#include "losmimo/placement/experiment/csv.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/metrics.h"
#include "losmimo/placement/experiment/records.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::experiment {
namespace {

TEST(MetricTable, TrialsCsvHeader_IsTheDocumentedOne) {
  std::ostringstream out;
  write_trials_header(out, {"loc_rmse_m"});
  EXPECT_EQ(out.str(),
            "sweep,value,algorithm,trial,seed,iterations,converged,final_icn,dist_to_icn050_m,dist_to_icn095_m,"
            "dist_total_m,probe_dist_m,sinr_nv_db,sinr_zf_db,sinr_mf_db,sum_rate_nv_bps_hz,sum_rate_zf_bps_hz,"
            "mean_sinr_nv_db,mean_sinr_zf_db,mean_sinr_mf_db,dist_placement_m,start_seed,status,loc_rmse_m\n");
}

TEST(MetricTable, SummaryColumns_KeepTheirHistoricalOrder) {
  EXPECT_EQ(
      summary_metric_names(),
      (std::vector<std::string>{"final_icn", "dist_to_icn050_m", "dist_to_icn095_m", "dist_total_m", "probe_dist_m",
                                "iterations", "sinr_nv_db", "sinr_zf_db", "sinr_mf_db", "mean_sinr_nv_db",
                                "mean_sinr_zf_db", "mean_sinr_mf_db", "sum_rate_nv_bps_hz", "sum_rate_zf_bps_hz"}));
}

TEST(MetricTable, EveryEntry_ReadsAndWritesTheFieldOfItsName) {
  TrialRecord r;
  int k = 0;
  std::set<std::string> names;
  for (const Metric& m : kMetrics) {
    EXPECT_TRUE(names.insert(m.name).second) << m.name << " listed twice";
    m.set(r, m.flag ? 1.0 : 10.0 + k++);
  }
  // GIVEN distinct values set through the table, THEN each named field holds its own.
  const std::pair<const char*, double> expected[] = {{"iterations", r.iterations},
                                                     {"final_icn", r.final_icn},
                                                     {"dist_to_icn050_m", r.dist_to_icn050_m},
                                                     {"dist_to_icn095_m", r.dist_to_icn095_m},
                                                     {"dist_total_m", r.dist_total_m},
                                                     {"probe_dist_m", r.probe_dist_m},
                                                     {"sinr_nv_db", r.sinr_nv_db},
                                                     {"sinr_zf_db", r.sinr_zf_db},
                                                     {"sinr_mf_db", r.sinr_mf_db},
                                                     {"sum_rate_nv_bps_hz", r.sum_rate_nv_bps_hz},
                                                     {"sum_rate_zf_bps_hz", r.sum_rate_zf_bps_hz},
                                                     {"mean_sinr_nv_db", r.mean_sinr_nv_db},
                                                     {"mean_sinr_zf_db", r.mean_sinr_zf_db},
                                                     {"mean_sinr_mf_db", r.mean_sinr_mf_db},
                                                     {"dist_placement_m", r.dist_placement_m}};
  std::set<double> values;
  for (const auto& [name, value] : expected) {
    const Metric* m = nullptr;
    for (const Metric& e : kMetrics) {
      if (std::string(e.name) == name) m = &e;
    }
    ASSERT_NE(m, nullptr) << name;
    EXPECT_EQ(m->get(r), value) << name;
    EXPECT_TRUE(values.insert(value).second) << name << " shares its field with another metric";
  }
  EXPECT_TRUE(r.converged);
}

TEST(MetricTable, Handles_NameTheirEntriesWithTheirUnits) {
  const std::tuple<MetricId, const char*, const char*> expected[] = {
      {metrics::kIterations, "iterations", "iterations"},
      {metrics::kConverged, "converged", ""},
      {metrics::kFinalIcn, "final_icn", ""},
      {metrics::kDistToIcn050M, "dist_to_icn050_m", "m"},
      {metrics::kDistToIcn095M, "dist_to_icn095_m", "m"},
      {metrics::kDistTotalM, "dist_total_m", "m"},
      {metrics::kProbeDistM, "probe_dist_m", "m"},
      {metrics::kSinrNvDb, "sinr_nv_db", "dB"},
      {metrics::kSinrZfDb, "sinr_zf_db", "dB"},
      {metrics::kSinrMfDb, "sinr_mf_db", "dB"},
      {metrics::kSumRateNvBpsHz, "sum_rate_nv_bps_hz", "bit/s/Hz"},
      {metrics::kSumRateZfBpsHz, "sum_rate_zf_bps_hz", "bit/s/Hz"},
      {metrics::kMeanSinrNvDb, "mean_sinr_nv_db", "dB"},
      {metrics::kMeanSinrZfDb, "mean_sinr_zf_db", "dB"},
      {metrics::kMeanSinrMfDb, "mean_sinr_mf_db", "dB"},
      {metrics::kDistPlacementM, "dist_placement_m", "m"}};
  ASSERT_EQ(std::size(expected), kMetrics.size());
  for (const auto& [id, name, unit] : expected) {
    const Metric* m = find_metric(id);
    ASSERT_NE(m, nullptr) << name;
    EXPECT_STREQ(m->name, name);
    EXPECT_STREQ(m->unit, unit) << name;
  }
  EXPECT_EQ(find_metric(MetricId{"sinr_nv"}), nullptr);
}

// An extension table's (name, unit) pairs in order.
std::vector<std::pair<std::string, std::string>> names_and_units(const ExtensionMetrics& table) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const ExtensionMetric& m : table) {
    out.emplace_back(m.name, m.unit);
    EXPECT_GT(std::string(m.doc).size(), 10u) << m.name << ": document it";
  }
  return out;
}

TEST(ExtensionMetricTable, ChannelSweepsAndMilestones_AreTheDocumentedColumns) {
  using Columns = std::vector<std::pair<std::string, std::string>>;
  EXPECT_EQ(names_and_units(channel_sweep_metrics()), (Columns{{"final_icn_los", ""},
                                                               {"final_icn_measured", ""},
                                                               {"sum_rate_nv_los_bps_hz", "bit/s/Hz"},
                                                               {"sum_rate_zf_los_bps_hz", "bit/s/Hz"}}));
  EXPECT_EQ(names_and_units(milestone_metrics()),
            (Columns{{"iterations_to_icn050", "iterations"}, {"iterations_to_icn095", "iterations"}}));
  // AND the extra columns of a run with a channel sweep and the milestones: the extension's, then the milestones
  common::IniConfig config;
  config.set_override("experiment.sweeps=sigma_loc_m, rician_k_db");
  config.set_override("experiment.milestone_columns=true");
  const ExperimentSettings s = load_experiment_settings(config, channel_sweep_extensions());
  EXPECT_EQ(extra_metric_names(s, channel_sweep_extensions()),
            (std::vector<std::string>{"final_icn_los", "final_icn_measured", "sum_rate_nv_los_bps_hz",
                                      "sum_rate_zf_los_bps_hz", "iterations_to_icn050", "iterations_to_icn095"}));
}

// A record of a channel sweep with every metric of channel_sweep_metrics() set but `skip`.
TrialRecord channel_record(const char* skip) {
  TrialRecord r;
  r.sweep = kSweepRicianK;
  r.algorithm = "gd";
  r.trial = 3;
  double v = 1.0;
  for (const ExtensionMetric& m : channel_sweep_metrics()) {
    if (std::string(m.name) != skip) r.extension.set(m, v++);
  }
  return r;
}

TEST(ExtensionMetricTable, RecordLeavingADeclaredMetricUnset_IsRefusedNamingIt) {
  // GIVEN a record that sets three of the four metrics
  TrialRecord r = channel_record("sum_rate_zf_los_bps_hz");
  try {
    extension_columns(r, channel_sweep_metrics());
    FAIL() << "accepted";
  } catch (const std::logic_error& e) {
    // THEN the refusal names the metric and the record
    EXPECT_NE(std::string(e.what()).find("leaves sum_rate_zf_los_bps_hz unset"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rician_k_db record of gd (trial 3)"), std::string::npos) << e.what();
  }
  // AND NaN is a value, not "unset": the columns in table order
  r.extension.set(kSumRateZfLosBpsHz, std::nan(""));
  const std::vector<double> columns = extension_columns(r, channel_sweep_metrics());
  ASSERT_EQ(columns.size(), 4u);
  EXPECT_EQ(columns[0], 1.0);
  EXPECT_EQ(columns[2], 3.0);
  EXPECT_TRUE(std::isnan(columns[3]));
  EXPECT_EQ(r.extension.at(kFinalIcnMeasured), 2.0);
  EXPECT_THROW(channel_record("final_icn_los").extension.at(kFinalIcnLos), std::out_of_range);
  // AND a metric the table does not declare is refused too
  r.extension.set(metrics::kIterationsToIcn050, 4.0);
  EXPECT_THROW(extension_columns(r, channel_sweep_metrics()), std::logic_error);
}

TEST(ExtensionMetricTable, EngineRefusesARecordLeavingADeclaredMetricUnset) {
  // GIVEN an extension declaring two metrics whose records set only the first
  static constexpr ExtensionMetric kSet{{"set_m"}, "m", "a metric every record sets"};
  static constexpr ExtensionMetric kForgotten{{"forgotten_m"}, "m", "a metric the records leave unset"};
  ExperimentExtension e;
  e.sweep = "forgetful";
  e.metrics = {kSet, kForgotten};
  e.load_values = [](const ExperimentSettings&) { return std::vector<double>{0.0}; };
  e.run = [](const ExperimentSettings&, int, int trial) {
    TrialRecord r;
    r.sweep = "forgetful";
    r.algorithm = "gd";
    r.trial = trial;
    r.extension.set(kSet, std::nan(""));
    return std::vector<TrialRecord>{r};
  };
  common::IniConfig config;
  config.set_override("experiment.sweeps=forgetful");
  config.set_override("experiment.trials=1");
  const ExperimentSettings s = load_experiment_settings(config, {e});
  // WHEN it runs THEN the engine refuses the record, naming the metric
  try {
    run_experiment(s, {e}, 1);
    FAIL() << "accepted";
  } catch (const std::logic_error& error) {
    EXPECT_NE(std::string(error.what()).find("leaves forgotten_m unset"), std::string::npos) << error.what();
  }
  // AND once every metric is set it runs, the columns in table order
  e.run = [](const ExperimentSettings&, int, int trial) {
    TrialRecord r;
    r.sweep = "forgetful";
    r.algorithm = "gd";
    r.trial = trial;
    r.extension.set(kForgotten, 2.0);
    r.extension.set(kSet, 1.0);
    return std::vector<TrialRecord>{r};
  };
  const ExperimentResults results = run_experiment(s, {e}, 1);
  ASSERT_EQ(results.records.size(), 1u);
  EXPECT_EQ(results.records[0].extra, (std::vector<double>{1.0, 2.0}));
}

TEST(MetricTable, ExactRecords_ReadBackEveryFieldBitForBit) {
  TrialRecord r;
  r.sweep = "sigma_act_m";
  r.value = 0.1;
  r.algorithm = "gd";
  r.trial = 7;
  r.seed = 18446744073709551557ULL;
  r.start_seed = 3;
  r.status = "iteration_cap";
  int k = 0;
  for (const Metric& m : kMetrics) m.set(r, m.real ? std::sqrt(2.0 + k++) / 3.0 : 5.0);
  r.dist_to_icn095_m = std::nan("");
  r.extra = {1.0 / 3.0, -0.0};
  r.start_m = Eigen::Matrix3Xd::Random(3, 4);
  r.final_m = Eigen::Matrix3Xd::Random(3, 4);
  std::stringstream text;
  RecordsWriter writer;
  text << writer.header({}) << writer.point(0, {}) << writer.point(1, {}) << writer.point(2, {r}) << writer.end();
  const RecordLines lines = read_records(text, "mem", RecordsMode::kComplete);
  ASSERT_EQ(lines.points.at(2).size(), 1u);
  const TrialRecord& back = lines.points.at(2).front();
  for (const Metric& m : kMetrics) {
    const double a = m.get(r), b = m.get(back);
    EXPECT_TRUE(a == b || (std::isnan(a) && std::isnan(b))) << m.name;
  }
  EXPECT_EQ(back.seed, r.seed);
  EXPECT_EQ(back.status, r.status);
  EXPECT_EQ(back.extra.size(), 2u);
  EXPECT_EQ(back.extra[0], r.extra[0]);
  EXPECT_TRUE(back.start_m == r.start_m && back.final_m == r.final_m);
  EXPECT_EQ(lines.points.size(), 3u);
}

TEST(MetricTable, RecordsOfAnotherVersion_AreRefusedNamingTheVersion) {
  std::istringstream v1("# losmimo-experiment records v1\nd,0\n");
  try {
    read_records(v1, "old/records.csv", RecordsMode::kComplete);
    FAIL() << "accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("old/records.csv:1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("records v1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace losmimo::experiment
