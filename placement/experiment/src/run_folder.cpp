#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/run_folder.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/hash.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/csv.h"
#include "losmimo/placement/experiment/records.h"
#include "losmimo/placement/experiment/report.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::experiment {

namespace fs = std::filesystem;
using common::InputError;

std::string results_config(ExperimentSettings s) {
  s.threads = 0;
  s.plots = true;
  s.config.set("experiment", "threads", "0");
  s.config.set("experiment", "plots", "true");
  return to_ini(s);
}

std::uint64_t config_digest(const ExperimentSettings& settings) { return common::fnv1a64(results_config(settings)); }

std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream ia(a), ib(b);
  std::string la, lb;
  while (true) {
    const bool ga = static_cast<bool>(std::getline(ia, la));
    const bool gb = static_cast<bool>(std::getline(ib, lb));
    if (!ga && !gb) return "";
    if (!ga) la = "(nothing)";
    if (!gb) lb = "(nothing)";
    if (la != lb) return "'" + la + "' vs '" + lb + "'";
  }
}

ExperimentSettings load_stored_settings(const std::string& config_ini, const ExperimentExtensions& extensions) {
  if (!fs::exists(config_ini)) throw common::InputError(config_ini + ": missing");
  return load_experiment_settings(common::IniConfig::from_file(config_ini), extensions);
}

std::vector<std::string> finish_outputs(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                                        const ExperimentResults& results, const std::string& out_dir,
                                        const RunTiming& timing, bool trial_files_written) {
  const fs::path dir(out_dir);
  const std::vector<std::string> extra = extra_metric_names(settings, extensions);
  if (!trial_files_written) {
    common::write_stream_atomically((dir / "trials.csv").string(), [&](std::ostream& o) {
      write_trials_header(o, extra);
      write_trials_rows(o, results.records, extra.size());
    });
    common::write_stream_atomically((dir / "positions.csv").string(), [&](std::ostream& o) {
      write_positions_header(o);
      write_positions_rows(o, results.records);
    });
  }
  std::ostringstream traces, summary;
  write_traces_csv(traces, results.traces);
  common::write_file_atomically((dir / "traces.csv").string(), traces.str());
  const std::vector<SummaryRow> rows = summarize(results.records, extra);
  write_summary_csv(summary, rows);
  common::write_file_atomically((dir / "summary.csv").string(), summary.str());
  return write_figures_and_report(settings, extensions, results, rows, dir.string(), timing).warnings;
}

Checkpoint read_checkpoint(const std::string& dir) {
  const fs::path path = fs::path(dir) / "records.partial";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw common::InputError(path.string() + ": missing: nothing to resume");
  RecordLines lines = read_records(in, path.string(), RecordsMode::kCheckpoint);
  Checkpoint c;
  c.header = lines.header;
  c.finished = std::move(lines.points);
  return c;
}

}  // namespace losmimo::experiment
