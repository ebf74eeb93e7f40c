#include "losmimo/experiment/metrics.h"

#include <algorithm>

namespace losmimo::experiment {

namespace {
constexpr Metric real(const char* name, double TrialRecord::*field, int summary_column = Metric::kNotSummarised) {
  return Metric{name, field, nullptr, nullptr, summary_column};
}
}  // namespace

// dist_placement_m is not summarised: summary.csv has never had it (dist_total_m - probe_dist_m
// gives it), and adding columns would change every summary file.
const std::array<Metric, kNumMetrics> kMetrics = {{
    Metric{"iterations", nullptr, &TrialRecord::iterations, nullptr, 5},
    Metric{"converged", nullptr, nullptr, &TrialRecord::converged, Metric::kNotSummarised},
    real("final_icn", &TrialRecord::final_icn, 0),
    real("dist_to_icn050_m", &TrialRecord::dist_to_icn050_m, 1),
    real("dist_to_icn095_m", &TrialRecord::dist_to_icn095_m, 2),
    real("dist_total_m", &TrialRecord::dist_total_m, 3),
    real("probe_dist_m", &TrialRecord::probe_dist_m, 4),
    real("sinr_nv_db", &TrialRecord::sinr_nv_db, 6),
    real("sinr_zf_db", &TrialRecord::sinr_zf_db, 7),
    real("sinr_mf_db", &TrialRecord::sinr_mf_db, 8),
    real("sum_rate_nv_bps_hz", &TrialRecord::sum_rate_nv_bps_hz, 12),
    real("sum_rate_zf_bps_hz", &TrialRecord::sum_rate_zf_bps_hz, 13),
    real("mean_sinr_nv_db", &TrialRecord::mean_sinr_nv_db, 9),
    real("mean_sinr_zf_db", &TrialRecord::mean_sinr_zf_db, 10),
    real("mean_sinr_mf_db", &TrialRecord::mean_sinr_mf_db, 11),
    real("dist_placement_m", &TrialRecord::dist_placement_m),
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

}  // namespace losmimo::experiment
