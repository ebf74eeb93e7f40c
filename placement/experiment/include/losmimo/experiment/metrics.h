#pragma once
// The metrics of a trial record, declared once. trials.csv, summary.csv, the exact records and
// their parser all iterate kMetrics, so a new metric is its TrialRecord field plus one line here.
//
//   name            the column in trials.csv, and <name>_mean / _ci95 / _n in summary.csv
//   field           the TrialRecord member: a real, an integer (iterations) or a flag (converged)
//   summary_column  its place among summary.csv's metrics (they keep the order the file has
//                   always had), or kNotSummarised
// trials.csv and the exact records list every metric in table order; summary.csv lists the
// summarised ones by summary_column. Extensions' metrics (TrialRecord::extra) follow in each.

#include <array>
#include <string>
#include <vector>

#include "losmimo/experiment/trial.h"

namespace losmimo::experiment {

struct Metric {
  static constexpr int kNotSummarised = -1;
  const char* name;
  double TrialRecord::*real = nullptr;
  int TrialRecord::*integer = nullptr;
  bool TrialRecord::*flag = nullptr;
  int summary_column = kNotSummarised;

  // The value as a double (integers and flags exactly).
  double get(const TrialRecord& r) const;
  void set(TrialRecord& r, double value) const;
  bool is_real() const { return real != nullptr; }
};

inline constexpr int kNumMetrics = 16;
extern const std::array<Metric, kNumMetrics> kMetrics;

// The summarised metrics, and their names, in summary.csv order.
std::vector<const Metric*> summary_metrics();
std::vector<std::string> summary_metric_names();

}  // namespace losmimo::experiment
