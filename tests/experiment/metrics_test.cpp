// The metric table drives trials.csv, summary.csv and the exact records: these tests hold it to
// the documented columns and to TrialRecord's fields, written out here independently.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include "losmimo/experiment/csv.h"
#include "losmimo/experiment/metrics.h"
#include "losmimo/experiment/records.h"
#include "losmimo/experiment/summary.h"

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
  EXPECT_EQ(summary_metric_names(),
            (std::vector<std::string>{"final_icn", "dist_to_icn050_m", "dist_to_icn095_m", "dist_total_m",
                                      "probe_dist_m", "iterations", "sinr_nv_db", "sinr_zf_db", "sinr_mf_db",
                                      "mean_sinr_nv_db", "mean_sinr_zf_db", "mean_sinr_mf_db",
                                      "sum_rate_nv_bps_hz", "sum_rate_zf_bps_hz"}));
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
  const std::pair<const char*, double> expected[] = {
      {"iterations", r.iterations},       {"final_icn", r.final_icn},
      {"dist_to_icn050_m", r.dist_to_icn050_m}, {"dist_to_icn095_m", r.dist_to_icn095_m},
      {"dist_total_m", r.dist_total_m},   {"probe_dist_m", r.probe_dist_m},
      {"sinr_nv_db", r.sinr_nv_db},       {"sinr_zf_db", r.sinr_zf_db},
      {"sinr_mf_db", r.sinr_mf_db},       {"sum_rate_nv_bps_hz", r.sum_rate_nv_bps_hz},
      {"sum_rate_zf_bps_hz", r.sum_rate_zf_bps_hz}, {"mean_sinr_nv_db", r.mean_sinr_nv_db},
      {"mean_sinr_zf_db", r.mean_sinr_zf_db}, {"mean_sinr_mf_db", r.mean_sinr_mf_db},
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
