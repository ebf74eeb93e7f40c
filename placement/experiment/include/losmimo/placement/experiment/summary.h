#pragma once
// summary.csv: per (sweep, value, algorithm), the number of trials, the converged fraction and,
// for every metric, the mean of its finite values with a 95% confidence half-width (Student t).

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/placement/experiment/trial.h"

namespace losmimo::experiment {

// Mean and 95% confidence half-width (Student t) of the finite values of one metric.
struct Estimate {
  double mean = 0.0;
  double ci95 = 0.0;
  int n = 0;
};
Estimate estimate(const std::vector<double>& values);
// An estimate as report tables show it, `decimals` after the point: "mean ± ci95"; with one value
// (no CI) "mean (n = 1)", never a made-up "± 0"; "n/a" for none, a missing one or a non-finite mean.
std::string format_estimate(const Estimate* e, int decimals = 2);

struct SummaryRow {
  std::string sweep;
  double value = 0.0;
  std::string algorithm;
  int trials = 0;
  double converged_fraction = 0.0;
  std::vector<std::pair<std::string, Estimate>> metrics;  // summary_metric_names() (metrics.h) + extra
  // By handle (metrics::kSinrNvDb, an extension's ExtensionMetric); nullptr if absent.
  const Estimate* metric(MetricId id) const;
};
std::vector<SummaryRow> summarize(const std::vector<TrialRecord>& records, const std::vector<std::string>& extra = {});
void write_summary_csv(std::ostream& out, const std::vector<SummaryRow>& rows);

}  // namespace losmimo::experiment
