#include "losmimo/placement/experiment/summary.h"

#include <algorithm>
#include <cmath>
#include <ostream>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/experiment/metrics.h"

namespace losmimo::experiment {

namespace {}  // namespace

std::string format_estimate(const Estimate* e, int decimals) {
  if (!e || e->n == 0 || !std::isfinite(e->mean)) return "n/a";
  const std::string mean = common::format_fixed(e->mean, decimals);
  if (e->n < 2 || !std::isfinite(e->ci95)) return mean + " (n = " + std::to_string(e->n) + ")";
  return mean + " ± " + common::format_fixed(e->ci95, decimals);
}

Estimate estimate(const std::vector<double>& values) {
  Estimate e;
  double sum = 0.0;
  for (const double v : values) {
    if (std::isfinite(v)) {
      sum += v;
      ++e.n;
    }
  }
  if (e.n == 0) return {std::nan(""), std::nan(""), 0};
  e.mean = sum / e.n;
  if (e.n < 2) {
    e.ci95 = std::nan("");
    return e;
  }
  double ss = 0.0;
  for (const double v : values) {
    if (std::isfinite(v)) ss += (v - e.mean) * (v - e.mean);
  }
  const double sd = std::sqrt(ss / (e.n - 1));
  // Student t quantile 0.975: exact for 1 and 2 degrees of freedom, Cornish-Fisher beyond
  // (within 0.3% from 3 degrees of freedom on).
  const int dof = e.n - 1;
  const double z = 1.959963984540054;
  double t = z + (z * z * z + z) / (4.0 * dof) + (5 * std::pow(z, 5) + 16 * z * z * z + 3 * z) / (96.0 * dof * dof);
  if (dof == 1) t = 12.706204736;
  if (dof == 2) t = 4.302652730;
  e.ci95 = t * sd / std::sqrt(static_cast<double>(e.n));
  return e;
}

const Estimate* SummaryRow::metric(MetricId id) const {
  for (const auto& [n, e] : metrics) {
    if (n == id.name) return &e;
  }
  return nullptr;
}

std::vector<SummaryRow> summarize(const std::vector<TrialRecord>& records, const std::vector<std::string>& extra) {
  // The summarised metrics in summary.csv order, then the extensions'.
  const std::vector<const Metric*> summarised = summary_metrics();
  std::vector<std::string> names = summary_metric_names();
  names.insert(names.end(), extra.begin(), extra.end());
  std::vector<SummaryRow> rows;
  std::size_t i = 0;
  while (i < records.size()) {
    // Records of one point are contiguous; group each algorithm's trials.
    std::size_t j = i;
    while (j < records.size() && records[j].sweep == records[i].sweep && records[j].value == records[i].value) ++j;
    std::vector<std::string> order;
    for (std::size_t k = i; k < j; ++k) {
      if (std::find(order.begin(), order.end(), records[k].algorithm) == order.end())
        order.push_back(records[k].algorithm);
    }
    for (const std::string& a : order) {
      SummaryRow row{records[i].sweep, records[i].value, a, 0, 0.0, {}};
      std::vector<std::vector<double>> columns(names.size());
      int converged = 0;
      for (std::size_t k = i; k < j; ++k) {
        const TrialRecord& r = records[k];
        if (r.algorithm != a) continue;
        ++row.trials;
        converged += r.converged;
        for (std::size_t c = 0; c < summarised.size(); ++c) columns[c].push_back(summarised[c]->get(r));
        for (std::size_t c = 0; c < extra.size(); ++c) {
          columns[summarised.size() + c].push_back(c < r.extra.size() ? r.extra[c] : std::nan(""));
        }
      }
      row.converged_fraction = row.trials ? static_cast<double>(converged) / row.trials : 0.0;
      for (std::size_t c = 0; c < columns.size(); ++c) row.metrics.emplace_back(names[c], estimate(columns[c]));
      rows.push_back(std::move(row));
    }
    i = j;
  }
  return rows;
}

void write_summary_csv(std::ostream& out, const std::vector<SummaryRow>& rows) {
  out << "sweep,value,algorithm,trials,converged_fraction";
  const std::vector<std::pair<std::string, Estimate>> no_metrics;
  for (const auto& [m, e] : rows.empty() ? no_metrics : rows.front().metrics) {
    out << "," << m << "_mean," << m << "_ci95," << m << "_n";
  }
  out << "\n";
  for (const SummaryRow& r : rows) {
    out << r.sweep << "," << common::format_csv(r.value) << "," << r.algorithm << "," << r.trials << ","
        << common::format_csv(r.converged_fraction);
    for (const auto& [name, e] : r.metrics)
      out << "," << common::format_csv(e.mean) << "," << common::format_csv(e.ci95) << "," << e.n;
    out << "\n";
  }
}

}  // namespace losmimo::experiment
