#pragma once
// What losmimo-experiment's run (experiment_app.cpp) and merge (merge_app.cpp) share: the
// progress line, the final outputs and the manifest of a finished folder.
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include <unistd.h>

#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/apps/lib/staged_output.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/report.h"
#include "losmimo/placement/experiment/run_folder.h"

namespace losmimo::apps::detail {

class Progress {
 public:
  explicit Progress(std::ostream& err) : err_(err), tty_(isatty(STDERR_FILENO) != 0), t0_(clock::now()) {}
  void operator()(int done, int total, const std::string& label) {
    const double elapsed = std::chrono::duration<double>(clock::now() - t0_).count();
    const double eta = done > 0 ? elapsed * (total - done) / done : 0.0;
    if (tty_) {
      constexpr int kWidth = 30;
      const int filled = kWidth * done / total;
      err_ << "\r[" << std::string(filled, '#') << std::string(kWidth - filled, '.') << "] " << done << "/" << total
           << "  " << std::fixed << std::setprecision(0) << elapsed << " s, ETA " << eta << " s   "
           << (done == total ? "\n" : "") << std::flush;
    } else {
      err_ << "point " << done << "/" << total << " done (" << label << "), " << std::fixed << std::setprecision(1)
           << elapsed << " s elapsed, ETA " << eta << " s\n";
    }
  }

 private:
  using clock = std::chrono::steady_clock;
  std::ostream& err_;
  bool tty_;
  clock::time_point t0_;
};

// The manifest of a finished experiment folder: its kind ("experiment", "shard", "merged"),
// the config digest and the record count; `extra` adds sections (a shard's [shard]).
inline Manifest experiment_manifest(const std::string& kind, const experiment::ExperimentSettings& settings,
                                    std::size_t records, const std::string& extra = "") {
  Manifest m;
  m.kind = kind;
  m.run_keys = {{"app", "losmimo-experiment"},
                {"config_digest", common::format_hex64(experiment::config_digest(settings))},
                {"points", std::to_string(experiment::num_sweep_points(settings))},
                {"records", std::to_string(records)}};
  m.extra_sections = extra;
  return m;
}

// --scene (run and merge) is refused before any work without a writer or when the run records
// no path (experiment::records_paths).
inline void check_scene_request(bool scene, bool has_writer, const experiment::ExperimentSettings& settings) {
  if (!scene) return;
  if (!has_writer) throw common::InputError("--scene: this program has no scene writer");
  if (!experiment::records_paths(settings)) {
    throw common::InputError(
        "--scene: this run records no path (it needs [experiment] paths = true, fig1_trials > 0, the sigma_loc or "
        "sigma_act sweep and GD or BF among the algorithms)");
  }
}

// Writes config.ini and every output into the staging folder, publishes it, prints the
// warnings and the last line.
inline void finish_and_publish(StagedDir& staged, const std::string& kind,
                               const experiment::ExperimentSettings& settings,
                               const experiment::ExperimentExtensions& extensions,
                               const experiment::ExperimentResults& results, const experiment::RunTiming& timing,
                               bool trial_files_written, std::ostream& out, std::ostream& err) {
  namespace fs = std::filesystem;
  common::write_file_atomically((staged.path() / "config.ini").string(), experiment::to_ini(settings));
  const std::vector<std::string> warnings =
      experiment::finish_outputs(settings, extensions, results, staged.path().string(), timing, trial_files_written);
  // The checkpoint goes last: until the outputs are complete, --resume can finish them.
  fs::remove(staged.path() / "records.partial");
  staged.publish(experiment_manifest(kind, settings, results.records.size()));
  for (const std::string& w : warnings) err << "losmimo-experiment: warning: " << w << "\n";
  out << "losmimo-experiment: " << results.records.size() << " trial rows, " << settings.trials << " trials per point, "
      << experiment::describe(timing) << "; results in " << staged.final_path().string()
      << "/ (report.md, summary.csv, trials.csv, fig*.png)\n";
}

}  // namespace losmimo::apps::detail
