#pragma once
// `losmimo-experiment`: runs the experiment engine into an output folder, as one process, one
// shard of several, MPI ranks or the continuation of an interrupted run, and merges shard
// folders. Messages go to `err` prefixed "losmimo-experiment:", the last line to `out`.
// Returns the exit code (exit_codes.h).

#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/extension.h"

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
  std::optional<std::string> out_dir;  // not given: "results"
  int trials = 0;                      // > 0 overrides [experiment] trials
  int threads = -1;                    // >= 0 overrides [experiment] threads
  // "i/N": run shard i of N into out_dir (config.ini, records.csv and a manifest saying so) for
  // `losmimo-experiment merge`; not given: everything.
  std::optional<std::string> shard;
  // Continue the interrupted run of this output folder (its checkpoint in `<dir>.partial/`,
  // a whole run's or a shard's); the config must give the same results as its config.ini
  // (threads and plots may differ). `--out` may only name the same folder.
  std::optional<std::string> resume_dir;
  // A finished run already in the output folder (or an interrupted one in `<dir>.partial/`)
  // is replaced whole; without it the run refuses (kExitBadInput) before any work.
  bool replace = false;
  const ExperimentCollective* collective = nullptr;  // MPI: ranks split the jobs, rank 0 writes
  // --scene: paths.3Dscene beside paths.png, written by `scene_writer` (given the settings, the
  // results and the file; apps/experiment_scene.h) into the output folder with the rest. Refused
  // (exit 2, before any work) without a writer, with --shard, or when the run records no path
  // (experiment::records_paths).
  bool scene = false;
  std::function<void(const experiment::ExperimentSettings&, const experiment::ExperimentResults&, const std::string&)>
      scene_writer{};
};
// The output folder holds one run or nothing: everything is written into `<dir>.partial/` and
// renamed into place when complete (staged_output.h), with losmimo-run.ini last.
int run_experiment_app(const ExperimentOptions& options, const experiment::ExperimentExtensions& extensions,
                       std::ostream& out, std::ostream& err);

struct MergeOptions {
  std::vector<std::string> shard_dirs;
  std::string out_dir = "results";
  bool replace = false;  // as ExperimentOptions::replace
  // --scene: as ExperimentOptions::scene, for the merged run.
  bool scene = false;
  std::function<void(const experiment::ExperimentSettings&, const experiment::ExperimentResults&, const std::string&)>
      scene_writer{};
};
// `losmimo-experiment merge DIR...`: merges finished shard folders (their manifests say kind =
// shard, their files and records verify, same config, every shard of 0..N-1 exactly once) into
// out_dir, byte-identical trials.csv, positions.csv, traces.csv and summary.csv to a
// single-process run. Bad or missing shards: a message naming the folder (and record) and
// kExitBadInput.
int merge_experiment_app(const MergeOptions& options, const experiment::ExperimentExtensions& extensions,
                         std::ostream& out, std::ostream& err);

}  // namespace losmimo::apps
