#include "losmimo/placement/experiment/metrics.h"

#include <algorithm>
#include <stdexcept>

namespace losmimo::experiment {

namespace {
constexpr Metric real(MetricId id, const char* unit, double TrialRecord::*field,
                      int summary_column = Metric::kNotSummarised) {
  return Metric{id.name, unit, field, nullptr, nullptr, summary_column};
}
}  // namespace

// dist_placement_m is not summarised: summary.csv has never had it (dist_total_m - probe_dist_m
// gives it), and adding columns would change every summary file.
const std::array<Metric, kNumMetrics> kMetrics = {{
    Metric{metrics::kIterations.name, "iterations", nullptr, &TrialRecord::iterations, nullptr, 5},
    Metric{metrics::kConverged.name, "", nullptr, nullptr, &TrialRecord::converged, Metric::kNotSummarised},
    real(metrics::kFinalIcn, "", &TrialRecord::final_icn, 0),
    real(metrics::kDistToIcn050M, "m", &TrialRecord::dist_to_icn050_m, 1),
    real(metrics::kDistToIcn095M, "m", &TrialRecord::dist_to_icn095_m, 2),
    real(metrics::kDistTotalM, "m", &TrialRecord::dist_total_m, 3),
    real(metrics::kProbeDistM, "m", &TrialRecord::probe_dist_m, 4),
    real(metrics::kSinrNvDb, "dB", &TrialRecord::sinr_nv_db, 6),
    real(metrics::kSinrZfDb, "dB", &TrialRecord::sinr_zf_db, 7),
    real(metrics::kSinrMfDb, "dB", &TrialRecord::sinr_mf_db, 8),
    real(metrics::kSumRateNvBpsHz, "bit/s/Hz", &TrialRecord::sum_rate_nv_bps_hz, 12),
    real(metrics::kSumRateZfBpsHz, "bit/s/Hz", &TrialRecord::sum_rate_zf_bps_hz, 13),
    real(metrics::kMeanSinrNvDb, "dB", &TrialRecord::mean_sinr_nv_db, 9),
    real(metrics::kMeanSinrZfDb, "dB", &TrialRecord::mean_sinr_zf_db, 10),
    real(metrics::kMeanSinrMfDb, "dB", &TrialRecord::mean_sinr_mf_db, 11),
    real(metrics::kDistPlacementM, "m", &TrialRecord::dist_placement_m),
}};

double Metric::get(const TrialRecord& r) const {
  if (real) return r.*real;
  if (integer) return static_cast<double>(r.*integer);
  return (r.*flag) ? 1.0 : 0.0;
}

void Metric::set(TrialRecord& r, double value) const {
  if (real) {
    r.*real = value;
  } else if (integer) {
    r.*integer = static_cast<int>(value);
  } else {
    r.*flag = value != 0.0;
  }
}

const Metric* find_metric(MetricId id) {
  for (const Metric& m : kMetrics) {
    if (m.id() == id) return &m;
  }
  return nullptr;
}

std::vector<const Metric*> summary_metrics() {
  std::vector<const Metric*> summarised;
  for (const Metric& m : kMetrics) {
    if (m.summary_column != Metric::kNotSummarised) summarised.push_back(&m);
  }
  std::sort(summarised.begin(), summarised.end(),
            [](const Metric* a, const Metric* b) { return a->summary_column < b->summary_column; });
  return summarised;
}

std::vector<std::string> summary_metric_names() {
  std::vector<std::string> names;
  for (const Metric* m : summary_metrics()) names.emplace_back(m->name);
  return names;
}

const ExtensionMetrics& milestone_metrics() {
  static const ExtensionMetrics kTable = {metrics::kIterationsToIcn050, metrics::kIterationsToIcn095};
  return kTable;
}

std::vector<double> extension_columns(const TrialRecord& r, const ExtensionMetrics& table) {
  const auto refuse = [&](const std::string& what) {
    throw std::logic_error("extension_columns: the " + r.sweep + " record of " + r.algorithm + " (trial " +
                           std::to_string(r.trial) + ") " + what);
  };
  std::vector<double> columns;
  for (const ExtensionMetric& m : table) {
    const std::optional<double> v = r.extension.find(m);
    if (!v) refuse("leaves " + std::string(m.name) + " unset");
    columns.push_back(*v);
  }
  for (const auto& entry : r.extension.entries()) {
    const auto& id = entry.first;  // a named variable: C++17 lambdas cannot capture a structured binding
    if (std::none_of(table.begin(), table.end(), [&id](const ExtensionMetric& m) { return id == m; })) {
      refuse("sets " + std::string(id.name) + ", which its extension does not declare");
    }
  }
  return columns;
}

void MetricValues::set(MetricId id, double value) {
  for (auto& [k, v] : values_) {
    if (k == id) {
      v = value;
      return;
    }
  }
  values_.emplace_back(id, value);
}

std::optional<double> MetricValues::find(MetricId id) const {
  for (const auto& [k, v] : values_) {
    if (k == id) return v;
  }
  return std::nullopt;
}

double MetricValues::at(MetricId id) const {
  const std::optional<double> v = find(id);
  if (!v) throw std::out_of_range(std::string("MetricValues: ") + id.name + " is unset");
  return *v;
}

}  // namespace losmimo::experiment
