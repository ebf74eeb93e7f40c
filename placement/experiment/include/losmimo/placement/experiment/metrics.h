#pragma once
// The metrics of a trial record, declared once, in tables. trials.csv, summary.csv, the exact
// records, their parser and the reports all go through them: a new metric is one handle and one
// table entry (for a built-in one, also its TrialRecord field).
//
// Built-in metrics, kMetrics (a TrialRecord field each):
//   name            the column in trials.csv, and <name>_mean / _ci95 / _n in summary.csv
//   unit            "m", "dB", "bit/s/Hz", "iterations", or "" (a ratio or a flag)
//   field           the TrialRecord member: a real, an integer (iterations) or a flag (converged)
//   summary_column  its place among summary.csv's metrics (a fixed order that readers of the
//                   file rely on, independent of the table's), or kNotSummarised
// Extension metrics, ExtensionMetric (an extension's table, ExperimentExtension::metrics; the
// milestone columns, milestone_metrics()):
//   name, unit      as above
//   doc             what the column holds
//   summarised      always: after the built-in ones in summary.csv, in table order
//   accessor        the record's MetricValues (TrialRecord::extension), set by the metric's handle;
//                   every declared metric must be set (NaN where it does not apply)
// trials.csv and the exact records list the built-in metrics in table order, summary.csv the
// summarised ones by summary_column; the extension metrics follow in each
// (extra_metric_names, extension.h).
// Handles: metrics::kSinrNvDb etc. below, an extension's ExtensionMetric constants.

#include <array>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/metric_values.h"
#include "losmimo/placement/experiment/trial.h"

namespace losmimo::experiment {

struct Metric {
  static constexpr int kNotSummarised = -1;
  const char* name;
  const char* unit;
  double TrialRecord::*real = nullptr;
  int TrialRecord::*integer = nullptr;
  bool TrialRecord::*flag = nullptr;
  int summary_column = kNotSummarised;

  MetricId id() const { return {name}; }
  // The value as a double (integers and flags exactly).
  double get(const TrialRecord& r) const;
  void set(TrialRecord& r, double value) const;
  bool is_real() const { return real != nullptr; }
};

struct ExtensionMetric : MetricId {
  const char* unit;
  const char* doc;
};
using ExtensionMetrics = std::vector<ExtensionMetric>;

// The built-in metrics' handles (kMetrics holds their fields and summary columns).
namespace metrics {
inline constexpr MetricId kIterations{"iterations"};
inline constexpr MetricId kConverged{"converged"};
inline constexpr MetricId kFinalIcn{"final_icn"};
inline constexpr MetricId kDistToIcn050M{"dist_to_icn050_m"};
inline constexpr MetricId kDistToIcn095M{"dist_to_icn095_m"};
inline constexpr MetricId kDistTotalM{"dist_total_m"};
inline constexpr MetricId kProbeDistM{"probe_dist_m"};
inline constexpr MetricId kSinrNvDb{"sinr_nv_db"};
inline constexpr MetricId kSinrZfDb{"sinr_zf_db"};
inline constexpr MetricId kSinrMfDb{"sinr_mf_db"};
inline constexpr MetricId kSumRateNvBpsHz{"sum_rate_nv_bps_hz"};
inline constexpr MetricId kSumRateZfBpsHz{"sum_rate_zf_bps_hz"};
inline constexpr MetricId kMeanSinrNvDb{"mean_sinr_nv_db"};
inline constexpr MetricId kMeanSinrZfDb{"mean_sinr_zf_db"};
inline constexpr MetricId kMeanSinrMfDb{"mean_sinr_mf_db"};
inline constexpr MetricId kDistPlacementM{"dist_placement_m"};

// The milestone columns ([experiment] milestone_columns), filled by the engine from
// TrialRecord::icn050_iteration / icn095_iteration.
inline constexpr ExtensionMetric kIterationsToIcn050{
    {"iterations_to_icn050"}, "iterations", "the iteration at which the ICN first reached 0.5 (NaN: never)"};
inline constexpr ExtensionMetric kIterationsToIcn095{
    {"iterations_to_icn095"}, "iterations", "the iteration at which the ICN first reached 0.95 (NaN: never)"};
}  // namespace metrics

inline constexpr int kNumMetrics = 16;
extern const std::array<Metric, kNumMetrics> kMetrics;

// The built-in metric of a handle, nullptr if `id` is not one.
const Metric* find_metric(MetricId id);

// The summarised metrics, and their names, in summary.csv order.
std::vector<const Metric*> summary_metrics();
std::vector<std::string> summary_metric_names();

// The milestone columns' table: kIterationsToIcn050, kIterationsToIcn095.
const ExtensionMetrics& milestone_metrics();

// Record r's values of `table`'s metrics, in table order. std::logic_error naming the record and
// the metric when r leaves a declared metric unset or sets one the table does not declare.
std::vector<double> extension_columns(const TrialRecord& r, const ExtensionMetrics& table);

}  // namespace losmimo::experiment
