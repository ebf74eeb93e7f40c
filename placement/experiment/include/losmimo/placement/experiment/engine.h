#pragma once
// The experiment engine: Monte Carlo sweeps of sigma_loc and sigma_act over every algorithm
// (the paper's Figs 1-3), plus the sweeps of extensions, run in parallel with results that do
// not depend on the thread count or on how the jobs are split between processes.
//
// Jobs are the (sweep point, trial) pairs, numbered j = point * trials + trial with the points of
// every sweep in order. Each job's records come from seeds derived from (seed, sweep, point,
// trial) only (trial.h), and land in the slot its number names, whatever thread ran it.

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/trial.h"

namespace losmimo::experiment {

struct TracedRun {
  Algorithm algorithm;
  int trial;
  placement::RunResult result;
  // 0: a Fig 1 run (no errors, traces.csv); > 0: a path-figure run under this actuation error.
  double sigma_act_m = 0.0;
  bool fig1() const { return sigma_act_m == 0.0; }
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

// Which jobs a process runs: shard i of N runs the jobs with j % N == i (round robin, so every
// shard gets a share of every point).
struct ExperimentSlice {
  int shard_index = 0;
  int shard_count = 1;
  // Resume: points already finished, with their records (not run again, not sent to the sink).
  std::map<int, std::vector<TrialRecord>> finished_points;
  bool traces = true;  // the Fig 1 traced runs (a merge recomputes them)
};
// Receives each point's records (this slice's jobs only) once they are all done, in order.
using PointSink = std::function<void(int point, const std::vector<TrialRecord>&)>;
ExperimentResults run_experiment(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                                 int threads, const ExperimentSlice& slice, const ProgressFn& progress,
                                 const PointSink& sink);
int num_sweep_points(const ExperimentSettings& settings);

// The Fig 1 runs: GD and BF (those of them in the settings' algorithms) without errors, traced,
// fig1_trials each, when a built-in sweep runs; with [experiment] paths, trial 0's positions are
// recorded and GD and BF run again from trial 0's start under the largest sigma_act of the
// sweep (run_path).
std::vector<TracedRun> traced_runs(const ExperimentSettings& settings);
// Whether traced_runs records at least one path (trial 0's Fig 1 runs of GD or BF with
// [experiment] paths): what the path figure and the app's --scene need, known before any run.
bool records_paths(const ExperimentSettings& settings);

}  // namespace losmimo::experiment
