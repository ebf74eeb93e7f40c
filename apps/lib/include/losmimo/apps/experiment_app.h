#pragma once
// `losmimo-experiment`: runs the experiment engine into an output folder, as one process, one
// shard of several, MPI ranks or the continuation of an interrupted run, and merges shard
// folders. Messages go to `err` prefixed "losmimo-experiment:", the last line to `out`.
// Returns the exit code (exit_codes.h).

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "losmimo/experiment/extension.h"

namespace losmimo::apps {

// Processes that run one experiment together (MPI ranks): `gather` is collective, each rank
// passes its serialized records and rank 0 receives every rank's, in rank order (the others
// an empty list).
struct ExperimentCollective {
  int rank = 0;
  int size = 1;
  std::function<std::vector<std::string>(const std::string&)> gather;
};

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
int run_experiment_app(const ExperimentOptions& options, const experiment::ExperimentExtensions& extensions,
                       std::ostream& out, std::ostream& err);

// `losmimo-experiment merge DIR...`: merges complete shard folders (same config, every shard
// of 0..N-1 exactly once) into out_dir, byte-identical trials.csv, positions.csv, traces.csv
// and summary.csv to a single-process run. Bad or missing shards: a message and exit code 2.
int merge_experiment_app(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                         const experiment::ExperimentExtensions& extensions, std::ostream& out,
                         std::ostream& err);

}  // namespace losmimo::apps
