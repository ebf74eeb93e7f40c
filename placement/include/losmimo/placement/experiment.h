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
#include <map>
#include <utility>
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

// Which jobs a process runs. The jobs are the (sweep point, trial) pairs, numbered
// j = point * trials + trial with the points of every sweep in order; shard i of N runs the
// jobs with j % N == i (round robin, so every shard gets a share of every point).
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

// Parses "i/N" (0 <= i < N, decimal); throws InputError naming the text otherwise.
std::pair<int, int> parse_shard(const std::string& text);

// Records at full precision (every double as %.17g, positions included), one line each,
// `r,<point>,...`, and `d,<point>` once a point is complete: the checkpoint of a run
// (records.partial), a shard's output (records.csv) and what MPI ranks send to rank 0.
void write_record_lines(std::ostream& out, int point, const std::vector<TrialRecord>& records);
void write_point_done(std::ostream& out, int point);
struct RecordLines {
  std::map<int, std::vector<TrialRecord>> points;  // point -> records in file order
  std::vector<int> done;                           // `d` markers, in order
};
// Throws InputError naming `origin` and the line on a malformed line; a truncated last line
// (an interrupted write) is ignored when `allow_truncated_tail`.
RecordLines parse_record_lines(std::istream& in, const std::string& origin, bool allow_truncated_tail);

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

// Processes that run one experiment together (MPI ranks): `gather` is collective, each rank
// passes its serialized records and rank 0 receives every rank's, in rank order (the others
// an empty list).
struct ExperimentCollective {
  int rank = 0;
  int size = 1;
  std::function<std::vector<std::string>(const std::string&)> gather;
};

// The app: returns the exit code (0 ok, 2 bad input, 1 runtime failure).
struct ExperimentOptions {
  std::string config_path;
  std::vector<std::string> overrides;
  std::string out_dir = "results";
  int trials = 0;    // > 0 overrides [experiment] trials
  int threads = -1;  // >= 0 overrides [experiment] threads
  // "i/N": run shard i of N into out_dir (config.ini, shard.ini, records.csv) for
  // `losmimo-experiment merge`; empty: everything.
  std::string shard;
  // Continue the interrupted run in this folder (its records.partial checkpoint); the config
  // must give the same results as its config.ini (threads and plots may differ).
  std::string resume_dir;
  const ExperimentCollective* collective = nullptr;  // MPI: ranks split the jobs, rank 0 writes
};
int run_experiment_app(const ExperimentOptions& options, const ExperimentExtensions& extensions,
                       std::ostream& out, std::ostream& err);

// `losmimo-experiment merge DIR...`: merges complete shard folders (same config, every shard
// of 0..N-1 exactly once) into out_dir, byte-identical trials.csv, positions.csv, traces.csv
// and summary.csv to a single-process run. Bad or missing shards: a message and exit code 2.
int merge_experiment_app(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                         const ExperimentExtensions& extensions, std::ostream& out, std::ostream& err);

}  // namespace losmimo::placement
