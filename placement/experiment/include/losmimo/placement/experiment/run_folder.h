#pragma once
// What a run folder holds, and reading back an interrupted one. The apps write a run into the
// staging folder `<out>.partial/` and rename it into place when it is complete
// (apps/staged_output.h); losmimo-run.ini, the manifest, is written last.
//   config.ini       the full configuration (to_ini)
//   trials.csv, positions.csv, traces.csv, summary.csv   (csv.h, summary.h)
//   fig*.png/.gp/.dat, report.md                         (report.h)
//   records.csv      a shard's records (records.h), closed by their e line
//   records.partial  the checkpoint while a run is under way (records.h): every finished
//                    point's exact records followed by its `d` line; only in `<out>.partial/`

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/records.h"
#include "losmimo/placement/experiment/report.h"

namespace losmimo::experiment {

// The configuration as far as results depend on it (threads and plots do not matter), as INI,
// and its FNV-1a digest (the records' h line).
std::string results_config(ExperimentSettings settings);
std::uint64_t config_digest(const ExperimentSettings& settings);
// The first line where two configs differ ("'a' vs 'b'"), or "" if they are equal.
std::string first_difference(const std::string& a, const std::string& b);
// Loads the config.ini of a run or shard folder; common::InputError if missing or invalid.
ExperimentSettings load_stored_settings(const std::string& config_ini, const ExperimentExtensions& extensions);

// Writes everything after the runs, each file atomically: trials.csv and positions.csv (from
// the records, unless the run already renamed them from its partial files), traces.csv,
// summary.csv, the figures and report.md. Returns the figures' warnings.
std::vector<std::string> finish_outputs(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                                        const ExperimentResults& results, const std::string& out_dir,
                                        const RunTiming& timing, bool trial_files_written);

// The checkpoint of an interrupted run: its header (run or shard, config digest) and the records
// of the finished points (a prefix), verified (records.h).
struct Checkpoint {
  RecordsHeader header;
  std::map<int, std::vector<TrialRecord>> finished;
};
// Reads `dir`/records.partial; common::InputError if missing or damaged, naming the record.
Checkpoint read_checkpoint(const std::string& dir);

}  // namespace losmimo::experiment
