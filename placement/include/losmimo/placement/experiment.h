#pragma once
// The `losmimo-experiment` engine: Monte Carlo sweeps of sigma_loc and sigma_act over every
// algorithm (the paper's Figs 1-3), run in parallel with results independent of the thread
// count, written to an output directory:
//   trials.csv     one row per (sweep, value, algorithm, trial)      (experiment_trial.h)
//   positions.csv  start and final UAV positions of every trial row
//   traces.csv     per-iteration ICN / SINR of the Fig 1 runs
//   summary.csv    mean and 95% confidence half-width per (sweep, value, algorithm)
//   config.ini     the full configuration used
//   fig*.png/.gp/.dat, report.md                                     (experiment_report.h)
// trials.csv and positions.csv grow point by point as `*.partial` files (flushed), so an
// interrupted run keeps every finished point; every final file is written atomically.

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "losmimo/placement/experiment_extension.h"
#include "losmimo/placement/experiment_trial.h"

namespace losmimo::placement {

struct TracedRun {
  Algorithm algorithm;
  int trial;
  RunResult result;
};

struct ExperimentResults {
  std::vector<TrialRecord> records;  // ordered by sweep, point, trial, algorithm
  std::vector<TracedRun> traces;
};

// Called after each finished sweep point with (points done, points total, label).
using ProgressFn = std::function<void(int, int, const std::string&)>;

// Runs everything; `row_sink` (optional) receives each finished point's records in order.
// Sweeps not built in are run by the extension of the same name.
ExperimentResults run_experiment(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                                 int threads, const ProgressFn& progress = {},
                                 const std::function<void(const std::vector<TrialRecord>&)>& row_sink = {});

// CSV writers (column layout documented in README and experiment_trial.h); `extra` names the
// extension columns appended after the built-in ones (empty cells as nan).
void write_trials_header(std::ostream& out, const std::vector<std::string>& extra = {});
void write_trials_rows(std::ostream& out, const std::vector<TrialRecord>& records, std::size_t num_extra = 0);
void write_positions_header(std::ostream& out);
void write_positions_rows(std::ostream& out, const std::vector<TrialRecord>& records);
void write_traces_csv(std::ostream& out, const std::vector<TracedRun>& traces);

// Mean and 95% confidence half-width (Student t) of the finite values of one metric.
struct Estimate {
  double mean = 0.0;
  double ci95 = 0.0;
  int n = 0;
};
Estimate estimate(const std::vector<double>& values);

struct SummaryRow {
  std::string sweep;
  double value = 0.0;
  std::string algorithm;
  int trials = 0;
  double converged_fraction = 0.0;
  std::vector<std::pair<std::string, Estimate>> metrics;  // summary_metric_names() + extra
  const Estimate* metric(const std::string& name) const;  // nullptr if absent
};
std::vector<std::string> summary_metric_names();
std::vector<SummaryRow> summarize(const std::vector<TrialRecord>& records, const std::vector<std::string>& extra = {});
void write_summary_csv(std::ostream& out, const std::vector<SummaryRow>& rows);

// Writes `content` to path atomically (temp file + rename).
void write_file_atomically(const std::string& path, const std::string& content);

// The app: returns the exit code (0 ok, 2 bad input, 1 runtime failure).
struct ExperimentOptions {
  std::string config_path;
  std::vector<std::string> overrides;
  std::string out_dir = "results";
  int trials = 0;    // > 0 overrides [experiment] trials
  int threads = -1;  // >= 0 overrides [experiment] threads
};
int run_experiment_app(const ExperimentOptions& options, const ExperimentExtensions& extensions,
                       std::ostream& out, std::ostream& err);

}  // namespace losmimo::placement
