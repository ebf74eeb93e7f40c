#pragma once
// Readings: which open modelling choice moves which of the paper's values, measured.
//
// A reading ([experiment] readings, settings.h) is a set of placement keys set on top of the
// run's configuration, e.g. "gd-noescape: gd.escape=false". For every paper value (report.h)
// whose sweep point and algorithm the run has, the base configuration and every reading run
// trials 0 .. reading_trials - 1 at that point with the run's own seeds (trial.h): the same
// starts and error draws, so the difference reading - base is paired per trial.
//
//   value  the reading's mean over its trials where the quantity is defined (n)
//   base   the same for the base configuration (the run's first reading_trials trials)
//   delta  the mean of reading - base over the trials where both are defined (n), with its 95%
//          confidence half-width: the effect of the reading's keys, free of the start-to-start
//          spread that dominates each mean's CI
// A reading whose keys are all in [gd], [bf] or [ura] runs that algorithm only: a planner's
// options and stop rule reach no other planner, so the others' values are the base's. Every job
// depends on (settings, reading, point, trial) only: the numbers do not depend on the thread
// count. The Fig 1 values (iterations to ICN 0.95) are read from the first iteration
// at which each run reached 0.95, so that readings that run a fixed number of iterations still
// give them.

#include <iosfwd>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/report.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::experiment {

struct ReadingMeasure {
  Estimate value;
  Estimate base;
  Estimate delta;
};

struct ReadingResults {
  int trials = 0;                  // per reading and point
  std::vector<PaperValue> values;  // the paper values measured, in paper_values() order
  std::vector<int> value_numbers;  // their numbers 1..27 in paper_values()
  std::vector<ReadingSpec> readings;
  std::vector<std::vector<ReadingMeasure>> measures;  // [reading][value]
  bool empty() const { return readings.empty(); }
  // The measure of paper value number `number` (1-based) under reading r, or nullptr.
  const ReadingMeasure* find(std::size_t r, int number) const;
};

// Runs the base and every reading of `settings` (none: an empty result) on `threads` threads.
ReadingResults measure_readings(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                                int threads);

// The per-trial value of a paper value's metric in a record: a built-in metric (kMetrics), or
// metrics::kIterationsToIcn050 / kIterationsToIcn095 from the record's milestones (NaN if never reached).
double record_metric(const TrialRecord& record, MetricId metric);

// readings.csv: one row per reading and paper value:
// reading,number,figure,quantity,sweep,value,algorithm,metric,paper,trials,
// mean,ci95,n,base_mean,base_ci95,base_n,delta_mean,delta_ci95,delta_n,agrees,settings
void write_readings_csv(std::ostream& out, const ReadingResults& results);

// Whether an estimate agrees with a paper value: |mean - paper| <= CI + resolution (n > 0).
bool agrees(const Estimate& e, const PaperValue& p);

// report.md's "Why" for paper value number `number` (1-based, paper_values() order): the
// readings that move it toward the paper beyond the CI of their paired difference, closest
// first (at most three), each with its keys, the move and where it lands; else "cause unknown"
// with what was tried.
std::string explain_difference(const PaperValue& value, int number, const ReadingResults& readings);
// report.md's "Readings" section: per reading, how many values agree at reading_trials trials,
// and which values it gains or loses against the base.
std::string readings_section(const ReadingResults& readings);

}  // namespace losmimo::experiment
