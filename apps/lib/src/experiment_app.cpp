#include "losmimo/apps/experiment_app.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <thread>
#include <tuple>
#include <unistd.h>

#include "losmimo/apps/exit_codes.h"
#include "losmimo/common/atomic_file.h"
#include "losmimo/common/format.h"
#include "losmimo/common/ini_config.h"
#include "losmimo/common/input_error.h"
#include "losmimo/experiment/csv.h"
#include "losmimo/experiment/records.h"
#include "losmimo/experiment/report.h"
#include "losmimo/experiment/run_folder.h"
#include "losmimo/experiment/shards.h"

namespace losmimo::apps {

using namespace experiment;  // the app is a thin layer over the engine's vocabulary
using common::InputError;
using common::IniConfig;
using common::write_file_atomically;

namespace {
namespace fs = std::filesystem;

ExperimentSettings load_settings(const ExperimentOptions& options, const ExperimentExtensions& extensions) {
  common::IniConfig config = options.config_path.empty() ? common::IniConfig() : common::IniConfig::from_file(options.config_path);
  for (const std::string& o : options.overrides) config.set_override(o);
  if (options.trials > 0) config.set("experiment", "trials", std::to_string(options.trials));
  if (options.threads >= 0) config.set("experiment", "threads", std::to_string(options.threads));
  return load_experiment_settings(config, extensions);
}

int threads_of(const ExperimentSettings& settings) {
  return settings.threads > 0 ? settings.threads
                              : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

class Progress {
 public:
  explicit Progress(std::ostream& err) : err_(err), tty_(isatty(STDERR_FILENO) != 0), t0_(clock::now()) {}
  void operator()(int done, int total, const std::string& label) {
    const double elapsed = std::chrono::duration<double>(clock::now() - t0_).count();
    const double eta = done > 0 ? elapsed * (total - done) / done : 0.0;
    if (tty_) {
      constexpr int kWidth = 30;
      const int filled = kWidth * done / total;
      err_ << "\r[" << std::string(filled, '#') << std::string(kWidth - filled, '.') << "] " << done << "/"
           << total << "  " << std::fixed << std::setprecision(0) << elapsed << " s, ETA " << eta << " s   "
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
// Writes the outputs after the runs, prints their warnings and the last line.
void report_finished(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                     const ExperimentResults& results, const fs::path& dir, const RunTiming& timing,
                     bool trial_files_written, std::ostream& out, std::ostream& err) {
  for (const std::string& w :
       finish_outputs(settings, extensions, results, dir.string(), timing, trial_files_written)) {
    err << "losmimo-experiment: warning: " << w << "\n";
  }
  out << "losmimo-experiment: " << results.records.size() << " trial rows, " << settings.trials
      << " trials per point, " << describe(timing) << "; results in " << dir.string()
      << "/ (report.md, summary.csv, trials.csv, fig*.png)\n";
}
}  // namespace

int run_experiment_app(const ExperimentOptions& options, const ExperimentExtensions& extensions,
                       std::ostream& out, std::ostream& err) {
  ExperimentSettings settings;
  ExperimentSlice slice;
  const bool resume = !options.resume_dir.empty();
  const ExperimentCollective* collective = options.collective && options.collective->size > 1 ? options.collective : nullptr;
  const bool root = !collective || collective->rank == 0;
  const fs::path dir(resume ? options.resume_dir : options.out_dir);
  try {
    settings = load_settings(options, extensions);
    if (!options.shard.empty()) std::tie(slice.shard_index, slice.shard_count) = parse_shard(options.shard);
    if (resume && (!options.shard.empty() || collective)) {
      throw common::InputError("--resume runs a whole experiment: not with --shard or MPI");
    }
    if (!options.shard.empty() && collective) throw common::InputError("--shard and MPI (mpirun) cannot be combined");
    if (collective) {
      slice.shard_index = collective->rank;
      slice.shard_count = collective->size;
    }
    if (resume) {
      const ExperimentSettings stored = load_stored_settings((dir / "config.ini").string(), extensions);
      const std::string diff = first_difference(results_config(stored), results_config(settings));
      if (!diff.empty()) {
        throw common::InputError("--resume " + dir.string() + ": the config differs from its config.ini: " + diff);
      }
    }
  } catch (const common::InputError& e) {
    err << "losmimo-experiment: " << e.what() << "\n";
    return kExitBadInput;
  }
  const bool sharded = slice.shard_count > 1 || !options.shard.empty();
  const int threads = threads_of(settings);
  try {
    if (collective) {
      // Every rank runs its slice in memory; rank 0 gathers, merges and writes.
      std::string mine;
      ExperimentResults part;
      const auto t0 = std::chrono::steady_clock::now();
      try {
        slice.traces = false;
        Progress progress(err);
        std::ostringstream text;
        part = run_experiment(settings, extensions, threads, slice, root ? ProgressFn(std::ref(progress)) : ProgressFn(),
                              [&](int point, const std::vector<TrialRecord>& rows) { write_record_lines(text, point, rows); });
        mine = text.str();
      } catch (const std::exception& e) {
        mine = std::string("!") + e.what();  // reported by rank 0; the gather must still happen
      }
      const std::vector<std::string> all = collective->gather(mine);
      if (!root) return mine.rfind('!', 0) == 0 ? 1 : 0;
      std::vector<RecordLines> shards;
      std::vector<std::string> origins;
      for (std::size_t r = 0; r < all.size(); ++r) {
        origins.push_back("rank " + std::to_string(r));
        if (all[r].rfind('!', 0) == 0) throw std::runtime_error(origins.back() + ": " + all[r].substr(1));
        std::istringstream in(all[r]);
        shards.push_back(parse_record_lines(in, origins.back(), false));
      }
      ExperimentResults results = merge_shard_records(settings, shards, origins);
      results.traces = traced_runs(settings);
      const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      fs::create_directories(dir);
      write_file_atomically((dir / "config.ini").string(), to_ini(settings));
      report_finished(settings, extensions, results, dir, {wall_s, threads * collective->size}, false, out, err);
      return kExitOk;
    }

    fs::create_directories(dir);
    const std::vector<std::string> extra = extra_metric_names(settings, extensions);
    if (resume) {
      Checkpoint c = read_checkpoint(dir.string());
      slice.finished_points = std::move(c.finished);
      // Cut the user-facing partial files back to the last finished point, rewrite the checkpoint.
      const int kept = static_cast<int>(slice.finished_points.size());
      std::ostringstream records;
      records << kRecordsHeader << "\n";
      for (const auto& [p, rows] : slice.finished_points) {
        write_record_lines(records, p, rows);
        write_point_done(records, p);
      }
      std::vector<TrialRecord> kept_rows;
      for (const auto& [p, rows] : slice.finished_points) kept_rows.insert(kept_rows.end(), rows.begin(), rows.end());
      common::write_stream_atomically((dir / "trials.csv.partial").string(), [&](std::ostream& o) {
        write_trials_header(o, extra);
        write_trials_rows(o, kept_rows, extra.size());
      });
      common::write_stream_atomically((dir / "positions.csv.partial").string(), [&](std::ostream& o) {
        write_positions_header(o);
        write_positions_rows(o, kept_rows);
      });
      write_file_atomically((dir / "records.partial").string(), records.str());
      err << "losmimo-experiment: resuming " << dir.string() << ": " << kept << " of " << num_sweep_points(settings)
          << " points already finished\n";
    }
    write_file_atomically((dir / "config.ini").string(), to_ini(settings));

    const auto mode = resume ? std::ios::app : std::ios::trunc;
    std::ofstream records_part(dir / "records.partial", std::ios::binary | mode);
    std::ofstream trials_part, positions_part;
    if (!resume) records_part << kRecordsHeader << "\n";
    if (!sharded) {
      trials_part.open(dir / "trials.csv.partial", std::ios::binary | mode);
      positions_part.open(dir / "positions.csv.partial", std::ios::binary | mode);
      if (!resume) {
        write_trials_header(trials_part, extra);
        write_positions_header(positions_part);
      }
    }
    const auto sink = [&](int point, const std::vector<TrialRecord>& rows) {
      if (!sharded) {
        write_trials_rows(trials_part, rows, extra.size());
        write_positions_rows(positions_part, rows);
        trials_part.flush();
        positions_part.flush();
      }
      // The checkpoint last: a `d` line promises the point is complete everywhere.
      write_record_lines(records_part, point, rows);
      write_point_done(records_part, point);
      records_part.flush();
    };
    Progress progress(err);
    const auto t0 = std::chrono::steady_clock::now();
    if (sharded) slice.traces = false;
    const ExperimentResults results = run_experiment(settings, extensions, threads, slice, std::ref(progress), sink);
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    records_part.close();
    if (!records_part) throw std::runtime_error("writing records.partial failed");
    if (sharded) {
      fs::rename(dir / "records.partial", dir / "records.csv");
      std::ostringstream shard;
      shard << "# losmimo-experiment shard: merge the folders of shards 0.." << slice.shard_count - 1
            << " with `losmimo-experiment merge`\n[shard]\nindex = " << slice.shard_index
            << "\ncount = " << slice.shard_count << "\n"
            << "# this shard's run, reported by the merge\nthreads = " << threads << "\nwall_s = "
            << common::format_g(wall_s, common::kExactDigits) << "\n";
      write_file_atomically((dir / "shard.ini").string(), shard.str());
      out << "losmimo-experiment: shard " << slice.shard_index << "/" << slice.shard_count << ": "
          << results.records.size() << " trial rows, " << describe({wall_s, threads}) << "; records in "
          << dir.string() << "/records.csv\n";
      return kExitOk;
    }
    trials_part.close();
    positions_part.close();
    if (!trials_part || !positions_part) throw std::runtime_error("writing trials/positions failed");
    fs::rename(dir / "trials.csv.partial", dir / "trials.csv");
    fs::rename(dir / "positions.csv.partial", dir / "positions.csv");
    report_finished(settings, extensions, results, dir, {wall_s, threads}, true, out, err);
    fs::remove(dir / "records.partial");
    return kExitOk;
  } catch (const common::InputError& e) {
    err << "losmimo-experiment: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    err << "losmimo-experiment: error: " << e.what() << "\n";
    return kExitFailure;
  }
}

int merge_experiment_app(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                         const ExperimentExtensions& extensions, std::ostream& out, std::ostream& err) {
  ExperimentSettings settings;
  ExperimentResults results;
  RunTiming timing;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (shard_dirs.empty()) throw common::InputError("merge: no shard folders given");
    std::string reference;
    int count = -1;
    std::map<int, std::string> seen;  // shard index -> folder
    std::vector<RecordLines> shards;
    for (const std::string& d : shard_dirs) {
      const fs::path shard_ini = fs::path(d) / "shard.ini";
      if (!fs::exists(shard_ini)) {
        throw common::InputError(shard_ini.string() + ": missing: not a finished shard folder (run with --shard i/N)");
      }
      const common::IniConfig ini = common::IniConfig::from_file(shard_ini.string());
      ini.require_known({{"shard", {"index", "count", "threads", "wall_s"}}});
      if (!ini.has("shard", "count") || !ini.has("shard", "index")) {
        throw common::InputError(shard_ini.string() + ": needs [shard] index and count");
      }
      const int n = static_cast<int>(ini.get_integer("shard", "count", 1, 1, 1'000'000'000));
      const int i = static_cast<int>(ini.get_integer("shard", "index", 0, 0, n - 1));
      if (count != -1 && n != count) {
        throw common::InputError(d + ": shard " + std::to_string(i) + " of " + std::to_string(n) + ", but " +
                         seen.begin()->second + " is one of " + std::to_string(count));
      }
      count = n;
      if (seen.count(i)) throw common::InputError(d + ": shard " + std::to_string(i) + " given twice (also " + seen[i] + ")");
      seen[i] = d;
      add_shard_timing(ini, timing);
      const ExperimentSettings s = load_stored_settings((fs::path(d) / "config.ini").string(), extensions);
      const std::string config = results_config(s);
      if (reference.empty()) {
        reference = config;
        settings = s;
      } else if (const std::string diff = first_difference(reference, config); !diff.empty()) {
        throw common::InputError(d + "/config.ini differs from " + shard_dirs.front() + "/config.ini: " + diff);
      }
    }
    std::string missing;
    for (int i = 0; i < count; ++i) {
      if (!seen.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
    }
    if (!missing.empty()) throw common::InputError("merge: missing shard(s) " + missing + " of " + std::to_string(count));
    std::vector<std::string> origins;
    for (const auto& [i, d] : seen) {
      const fs::path path = fs::path(d) / "records.csv";
      std::ifstream in(path, std::ios::binary);
      if (!in) throw common::InputError(path.string() + ": missing");
      origins.push_back(path.string());
      shards.push_back(parse_record_lines(in, path.string(), false));
    }
    results = merge_shard_records(settings, shards, origins);
  } catch (const common::InputError& e) {
    err << "losmimo-experiment merge: " << e.what() << "\n";
    return kExitBadInput;
  }
  try {
    results.traces = traced_runs(settings);
    const fs::path dir(out_dir);
    fs::create_directories(dir);
    write_file_atomically((dir / "config.ini").string(), to_ini(settings));
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timing.wall_s = wall_s;
    timing.shards = static_cast<int>(shard_dirs.size());
    report_finished(settings, extensions, results, dir, timing, false, out, err);
    return kExitOk;
  } catch (const std::exception& e) {
    err << "losmimo-experiment merge: error: " << e.what() << "\n";
    return kExitFailure;
  }
}

}  // namespace losmimo::apps