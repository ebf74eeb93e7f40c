#pragma once
// How a higher library adds sweep kinds to `losmimo-experiment` without placement depending on
// it: the app passes a list of extensions (e.g. fusion's co-evaluation). Each one owns a sweep
// name, its INI sections, the algorithms it runs at every point, and any extra trials.csv
// columns; the engine schedules, seeds, writes, summarises and reports its rows like the
// built-in sweeps'.

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/metrics.h"
#include "losmimo/placement/experiment/trial.h"

namespace losmimo::experiment {

struct SummaryRow;

struct ExperimentExtension {
  std::string sweep;  // its name in [experiment] sweeps and in the `sweep` column
  std::map<std::string, std::set<std::string>> config_keys;  // the INI keys it reads
  ExtensionMetrics metrics;  // its metric table (metrics.h): the extra trials.csv / summary.csv columns
  // Validates its configuration (throwing common::InputError naming key and value) and returns the
  // sweep points. Called before any work.
  std::function<std::vector<double>(const ExperimentSettings&)> load_values;
  // Runs its algorithms on trial `trial` at sweep point `point`; each record sets every metric of
  // `metrics` in its `extension` values (the engine refuses one left unset). Must be
  // deterministic in (settings, point, trial) and thread-safe.
  std::function<std::vector<TrialRecord>(const ExperimentSettings&, int point, int trial)> run;
  // Optional, preferred over run: called once per run, before any trial, with the run's settings
  // (which outlive the returned function); returns the trial function with the extension's own
  // settings already parsed, under the same rules as run.
  using TrialFn = std::function<std::vector<TrialRecord>(int point, int trial)>;
  std::function<TrialFn(const ExperimentSettings&)> bind;
  // Optional: figures (write files into the folder, return warnings) and a report.md section.
  std::function<std::vector<std::string>(const ExperimentSettings&, const std::vector<SummaryRow>&,
                                         const std::string& out_dir)>
      figures;
  std::function<std::string(const ExperimentSettings&, const std::vector<SummaryRow>&)> report_section;
  // Optional: the conditions of this run under which parts of the sweep do not run (e.g. "no
  // gd_pf in [coevaluation] algorithms"), named as the apps' table of unused keys names them
  // (apps/unused_keys.h), which refuses a --set key that only those parts read.
  std::function<std::vector<std::string>(const ExperimentSettings&)> unused_conditions;
};
using ExperimentExtensions = std::vector<ExperimentExtension>;

// All INI keys: placement's, [experiment], and the extensions'.
std::map<std::string, std::set<std::string>> experiment_config_keys(const ExperimentExtensions& extensions = {});

// Validates every key (unknown ones included) before any work; common::InputError names key and value.
ExperimentSettings load_experiment_settings(const common::IniConfig& config,
                                            const ExperimentExtensions& extensions = {});
std::string to_ini(const ExperimentSettings& settings);

// The settings of a reading: `base`'s configuration with the reading's keys set (placement keys
// only), validated like any config, without readings of its own. common::InputError names the
// reading and the key.
ExperimentSettings apply_reading(const ExperimentSettings& base, const ReadingSpec& reading,
                                 const ExperimentExtensions& extensions);

// The extra metric columns: the extensions' metrics of the sweeps enabled in `settings`, in
// sweep order (each name once), then with [experiment] milestone_columns milestone_metrics().
std::vector<std::string> extra_metric_names(const ExperimentSettings& settings, const ExperimentExtensions& extensions);
// The extensions' part of it.
std::vector<std::string> extension_metric_names(const ExperimentSettings& settings,
                                                const ExperimentExtensions& extensions);

}  // namespace losmimo::experiment
