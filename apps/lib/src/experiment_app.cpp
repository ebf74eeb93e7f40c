#include "losmimo/apps/lib/experiment_app.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

#include "experiment_common.h"
#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/unused_keys.h"
#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/apps/lib/staged_output.h"
#include "losmimo/placement/common/test_hook.h"
#include "losmimo/placement/experiment/csv.h"
#include "losmimo/placement/experiment/records.h"
#include "losmimo/placement/experiment/report.h"
#include "losmimo/placement/experiment/run_folder.h"
#include "losmimo/placement/experiment/shards.h"
#include "kernel_isa.h"
#include "messages.h"

namespace losmimo::apps {

using namespace experiment;  // the app is a thin layer over the engine's vocabulary
using common::InputError;
using common::write_file_atomically;

namespace {
namespace fs = std::filesystem;
constexpr const char* kApp = "losmimo-experiment";

ExperimentSettings load_settings(const ExperimentOptions& options, const ExperimentExtensions& extensions) {
  common::IniConfig config =
      options.config_path.empty() ? common::IniConfig() : common::IniConfig::from_file(options.config_path);
  for (const std::string& o : options.overrides) config.set_override(o);
  // Named after their option in messages, not "--set".
  if (options.trials > 0) config.set("experiment", "trials", std::to_string(options.trials), "--trials");
  if (options.threads >= 0) config.set("experiment", "threads", std::to_string(options.threads), "--threads");
  ExperimentSettings settings = load_experiment_settings(config, extensions);
  // A --set key that none of the run's sweeps uses is refused (unused_keys.h).
  ExperimentUse use;
  for (const SweepPoints& s : settings.sweeps) use.sweeps.push_back(s.name);
  for (const Algorithm& a : settings.algorithms) use.algorithms.push_back(to_string(a));
  use.fading = settings.placement.channel.fading();
  use.readings = !settings.readings.empty();
  for (const ExperimentExtension& e : extensions) {
    if (e.unused_conditions && settings.sweep(e.sweep)) use.sweep_conditions[e.sweep] = e.unused_conditions(settings);
  }
  refuse_unused_overrides(config, options.overrides, experiment_users(use));
  return settings;
}

int threads_of(const ExperimentSettings& settings) {
  return settings.threads > 0 ? settings.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// The trials of `point` that are the slice's jobs.
std::set<int> slice_trials(const ExperimentSlice& slice, int point, int trials) {
  std::set<int> mine;
  for (int t = 0; t < trials; ++t) {
    if ((static_cast<long long>(point) * trials + t) % slice.shard_count == slice.shard_index) mine.insert(t);
  }
  return mine;
}

bool same_folder(const std::string& a, const std::string& b) {
  const auto norm = [](const std::string& p) {
    fs::path n = fs::absolute(p).lexically_normal();
    return n.has_filename() ? n : n.parent_path();
  };
  return norm(a) == norm(b);
}

// --resume DIR (or DIR.partial, the staging folder itself): the run's final folder.
std::string resume_target(const std::string& given) {
  const std::string suffix = kStagingSuffix;
  std::string dir = given;
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  if (dir.size() > suffix.size() && dir.compare(dir.size() - suffix.size(), suffix.size(), suffix) == 0 &&
      fs::exists(fs::path(dir) / "records.partial")) {
    return dir.substr(0, dir.size() - suffix.size());
  }
  return given;
}

// Locks the interrupted run's staging folder; "nothing to resume" if there is none.
StagedDir open_for_resume(const std::string& dir, bool replace) {
  const fs::path staging = StagedDir::staging_path_of(dir);
  if (!fs::is_directory(staging)) {
    if (fs::exists(fs::path(dir) / kManifestName)) {
      const common::IniConfig m = read_manifest(dir);
      throw InputError("--resume " + dir + ": holds a finished " + m.get_string("run", "kind", "run") +
                       ": nothing to resume");
    }
    throw InputError("--resume " + dir + ": nothing to resume (no interrupted run in " + staging.string() + ")");
  }
  return StagedDir::resume(dir, replace);
}

// Checks an interrupted run's checkpoint against the config and fills the slice from it.
// Returns whether it is a shard's.
bool load_checkpoint(const StagedDir& staged, const ExperimentOptions& options, const ExperimentSettings& settings,
                     const ExperimentExtensions& extensions, ExperimentSlice& slice) {
  const fs::path dir = staged.path();
  const ExperimentSettings stored = load_stored_settings((dir / "config.ini").string(), extensions);
  const std::string diff = first_difference(results_config(stored), results_config(settings));
  if (!diff.empty()) throw InputError("--resume " + dir.string() + ": the config differs from its config.ini: " + diff);
  Checkpoint c = read_checkpoint(dir.string());
  const std::string records = (dir / "records.partial").string();
  if (c.header.config_digest != config_digest(stored)) {
    throw InputError(records + ": written for another config than " + (dir / "config.ini").string() +
                     " (its config digest differs): the folder mixes two runs");
  }
  const bool shard = c.header.kind == kRecordsKindShard;
  if (options.shard) {
    const auto [i, n] = parse_shard(*options.shard);
    if (!shard || i != c.header.shard_index || n != c.header.shard_count) {
      throw InputError(
          "--shard " + *options.shard + ": the interrupted run in " + dir.string() + " is " +
          (shard ? "shard " + std::to_string(c.header.shard_index) + "/" + std::to_string(c.header.shard_count)
                 : std::string("a whole run")));
    }
  }
  slice.shard_index = c.header.shard_index;
  slice.shard_count = c.header.shard_count;
  for (const auto& [point, rows] : c.finished) {
    check_point_jobs(records, point, rows, slice_trials(slice, point, settings.trials));
  }
  slice.finished_points = std::move(c.finished);
  return shard;
}

// --scene's refusals, before any work.
void check_scene_option(const ExperimentOptions& options, const ExperimentSettings& settings) {
  if (options.scene && options.shard) throw InputError("--scene: not with --shard (a shard records no path)");
  detail::check_scene_request(options.scene, static_cast<bool>(options.scene_writer), settings);
}

// paths.3Dscene into the staging folder, beside paths.png.
void write_scene(const ExperimentOptions& options, const ExperimentSettings& settings, const ExperimentResults& results,
                 const fs::path& stage) {
  if (options.scene) options.scene_writer(settings, results, (stage / "paths.3Dscene").string());
}

// MPI: every rank runs its slice in memory; rank 0 gathers, verifies, merges and writes. Each
// rank's part starts with the line "isa <name>" (its kernels' instruction set).
int run_collective(const ExperimentOptions& options, const ExperimentExtensions& extensions,
                   const ExperimentSettings& settings, ExperimentSlice slice, const std::string& dir,
                   const ExperimentCollective& collective, const std::string& isa, std::ostream& out,
                   std::ostream& err) {
  const bool root = collective.rank == 0;
  const int threads = threads_of(settings);
  std::string mine;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    slice.traces = false;
    detail::Progress progress(err);
    RecordsWriter writer;
    mine = "isa " + isa + "\n" +
           writer.header({kRecordsKindShard, collective.rank, collective.size, config_digest(settings)});
    run_experiment(settings, extensions, threads, slice, root ? ProgressFn(std::ref(progress)) : ProgressFn(),
                   [&](int point, const std::vector<TrialRecord>& rows) { mine += writer.point(point, rows); });
    mine += writer.end();
  } catch (const std::exception& e) {
    mine = std::string("!") + e.what();  // reported by rank 0; the gather must still happen
  }
  const std::vector<std::string> all = collective.gather(mine);
  if (!root) return mine.rfind('!', 0) == 0 ? kExitFailure : kExitOk;
  std::vector<RecordLines> shards;
  std::vector<std::string> origins;
  std::map<std::string, int> ranks_per_isa;
  for (std::size_t r = 0; r < all.size(); ++r) {
    origins.push_back("rank " + std::to_string(r));
    if (all[r].rfind('!', 0) == 0) throw std::runtime_error(origins.back() + ": " + all[r].substr(1));
    const std::size_t eol = all[r].find('\n');
    if (all[r].rfind("isa ", 0) != 0 || eol == std::string::npos) {
      throw std::runtime_error(origins.back() + ": its part does not start with its instruction set");
    }
    ++ranks_per_isa[all[r].substr(4, eol - 4)];
    std::istringstream in(all[r].substr(eol + 1));
    shards.push_back(read_records(in, origins.back(), RecordsMode::kComplete));
    const RecordsHeader& h = shards.back().header;
    if (h.shard_index != static_cast<int>(r) || h.shard_count != collective.size ||
        h.config_digest != config_digest(settings)) {
      throw std::runtime_error(origins.back() + ": its records are not this run's rank " + std::to_string(r));
    }
  }
  ExperimentResults results = merge_shard_records(settings, shards, origins);
  results.traces = traced_runs(settings);
  if (const std::string note = mixed_isa_note(ranks_per_isa, "rank"); !note.empty()) {
    print_error(err, kApp, "note: " + note);
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  StagedDir staged = StagedDir::create(dir, options.replace, StaleStaging::kRefuse);
  write_scene(options, settings, results, staged.path());
  RunTiming timing{wall_s, threads * collective.size};
  for (const auto& [name, ranks] : ranks_per_isa) timing.isa += (timing.isa.empty() ? "" : "+") + name;
  detail::finish_and_publish(staged, "experiment", settings, extensions, results, timing, false, out, err);
  return kExitOk;
}

// A run once its input is checked: settings, slice, output folder (staged, except under MPI,
// where rank 0 stages it at the end) and the kernels' instruction set.
struct RunPlan {
  ExperimentSettings settings;
  ExperimentSlice slice;
  std::string dir;
  std::optional<StagedDir> staged;
  std::string isa;
  bool resume = false;
  bool shard_run = false;
  const ExperimentCollective* collective = nullptr;
};

// Everything that can be wrong with the input is found here, before any work or any file.
void plan_run(const ExperimentOptions& options, const ExperimentExtensions& extensions, RunPlan& plan) {
  plan.resume = options.resume_dir.has_value();
  plan.collective = options.collective && options.collective->size > 1 ? options.collective : nullptr;
  plan.shard_run = options.shard.has_value();
  const bool resume = plan.resume;
  const ExperimentCollective* collective = plan.collective;
  if (options.out_dir && options.out_dir->empty()) throw InputError("--out '': an output folder is required");
  if (resume && options.resume_dir->empty())
    throw InputError("--resume '': the folder of an interrupted run is required");
  plan.dir = resume ? resume_target(*options.resume_dir) : options.out_dir.value_or("results");
  if (resume && options.out_dir && !same_folder(*options.out_dir, plan.dir)) {
    throw InputError("--out " + *options.out_dir + ": --resume " + plan.dir + " finishes the run in " + plan.dir +
                     " itself; leave out --out, or give the same folder");
  }
  if (resume && collective) throw InputError("--resume runs in one process: not under MPI (mpirun)");
  if (options.shard && collective) throw InputError("--shard and MPI (mpirun) cannot be combined");
  plan.settings = load_settings(options, extensions);
  check_scene_option(options, plan.settings);
  plan.isa = kernel_isa_name();
  if (options.shard) std::tie(plan.slice.shard_index, plan.slice.shard_count) = parse_shard(*options.shard);
  if (collective) {
    plan.slice.shard_index = collective->rank;
    plan.slice.shard_count = collective->size;
    StagedDir::check(plan.dir, options.replace, StaleStaging::kRefuse);  // every rank: the same answer
  } else if (resume) {
    plan.staged.emplace(open_for_resume(plan.dir, options.replace));
    plan.shard_run = load_checkpoint(*plan.staged, options, plan.settings, extensions, plan.slice);
  } else {
    plan.staged.emplace(StagedDir::create(plan.dir, options.replace, StaleStaging::kRefuse));
  }
}

// Writes config.ini and the partial files into the staging folder: records.partial (the
// checkpoint) starts as its verified prefix (a fresh run: the header alone), and a whole run's
// trials.csv.partial and positions.csv.partial hold the rows of the points already finished.
void start_partial_files(const RunPlan& plan, const std::vector<std::string>& extra, RecordsWriter& writer) {
  const fs::path stage = plan.staged->path();
  write_file_atomically((stage / "config.ini").string(), to_ini(plan.settings));
  std::string prefix = writer.header({plan.shard_run ? kRecordsKindShard : kRecordsKindRun, plan.slice.shard_index,
                                      plan.slice.shard_count, config_digest(plan.settings)});
  std::vector<TrialRecord> kept_rows;
  for (const auto& [p, rows] : plan.slice.finished_points) {
    prefix += writer.point(p, rows);
    kept_rows.insert(kept_rows.end(), rows.begin(), rows.end());
  }
  if (!plan.shard_run) {
    common::write_stream_atomically((stage / "trials.csv.partial").string(), [&](std::ostream& o) {
      write_trials_header(o, extra);
      write_trials_rows(o, kept_rows, extra.size());
    });
    common::write_stream_atomically((stage / "positions.csv.partial").string(), [&](std::ostream& o) {
      write_positions_header(o);
      write_positions_rows(o, kept_rows);
    });
  }
  write_file_atomically((stage / "records.partial").string(), prefix);
}

// A shard's end: records.partial, closed by its `e` line, becomes records.csv, and the folder is
// published with the shard's [shard] section (index, count and its run's threads, time, kernels).
int publish_shard(RunPlan& plan, RecordsWriter& writer, std::ofstream& records_part, const ExperimentResults& results,
                  const RunTiming& timing, int threads, std::ostream& out) {
  const fs::path stage = plan.staged->path();
  records_part << writer.end();
  records_part.close();
  if (!records_part) throw std::runtime_error("writing records.partial failed");
  fs::rename(stage / "records.partial", stage / "records.csv");
  std::ostringstream shard;
  shard << "\n[shard]\nindex = " << plan.slice.shard_index << "\ncount = " << plan.slice.shard_count
        << "\n# this shard's run, reported by the merge\nthreads = " << threads
        << "\nwall_s = " << common::format_g(timing.wall_s, common::kExactDigits) << "\nisa = " << plan.isa << "\n";
  plan.staged->publish(detail::experiment_manifest("shard", plan.settings, results.records.size(), shard.str()));
  out << "losmimo-experiment: shard " << plan.slice.shard_index << "/" << plan.slice.shard_count << ": "
      << results.records.size() << " trial rows, " << describe(timing) << "; records in "
      << plan.staged->final_path().string() << "/records.csv\n";
  return kExitOk;
}

// One process: runs the slice, appending every finished point to the partial files (the
// checkpoint last), then publishes the shard or the whole run's outputs.
int run_in_process(const ExperimentOptions& options, RunPlan& plan, const ExperimentExtensions& extensions,
                   std::ostream& out, std::ostream& err) {
  const ExperimentSettings& settings = plan.settings;
  const bool shard_run = plan.shard_run;
  const int threads = threads_of(settings);
  const fs::path stage = plan.staged->path();
  const std::vector<std::string> extra = extra_metric_names(settings, extensions);
  RecordsWriter writer;
  start_partial_files(plan, extra, writer);
  if (plan.resume) {
    err << "losmimo-experiment: resuming " << plan.dir << ": " << plan.slice.finished_points.size() << " of "
        << num_sweep_points(settings) << " points already finished\n";
  }

  std::ofstream records_part(stage / "records.partial", std::ios::binary | std::ios::app);
  std::ofstream trials_part, positions_part;
  if (!shard_run) {
    trials_part.open(stage / "trials.csv.partial", std::ios::binary | std::ios::app);
    positions_part.open(stage / "positions.csv.partial", std::ios::binary | std::ios::app);
  }
  const auto sink = [&](int point, const std::vector<TrialRecord>& rows) {
    if (!shard_run) {
      write_trials_rows(trials_part, rows, extra.size());
      write_positions_rows(positions_part, rows);
      trials_part.flush();
      positions_part.flush();
    }
    // The checkpoint last: a `d` line promises the point is complete everywhere.
    records_part << writer.point(point, rows);
    records_part.flush();
    if (!records_part || (!shard_run && (!trials_part || !positions_part))) {
      throw std::runtime_error("writing the checkpoint in " + stage.string() + " failed");
    }
    common::test_pause_point("experiment.point_done");
  };
  detail::Progress progress(err);
  const auto t0 = std::chrono::steady_clock::now();
  if (shard_run) plan.slice.traces = false;
  const ExperimentResults results = run_experiment(settings, extensions, threads, plan.slice, std::ref(progress), sink);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RunTiming timing{wall_s, threads};
  timing.isa = plan.isa;
  if (shard_run) return publish_shard(plan, writer, records_part, results, timing, threads, out);
  records_part.close();
  trials_part.close();
  positions_part.close();
  if (!records_part || !trials_part || !positions_part) throw std::runtime_error("writing the partial files failed");
  fs::rename(stage / "trials.csv.partial", stage / "trials.csv");
  fs::rename(stage / "positions.csv.partial", stage / "positions.csv");
  write_scene(options, settings, results, stage);
  detail::finish_and_publish(*plan.staged, "experiment", settings, extensions, results, timing, true, out, err);
  return kExitOk;
}

}  // namespace

int run_experiment_app(const ExperimentOptions& options, const ExperimentExtensions& extensions, std::ostream& out,
                       std::ostream& err) {
  RunPlan plan;
  try {
    plan_run(options, extensions, plan);
  } catch (...) {
    return report_current_exception(err, kApp, options.resume_dir.has_value() ? "--resume" : "--out");
  }
  try {
    if (plan.collective) {
      return run_collective(options, extensions, plan.settings, plan.slice, plan.dir, *plan.collective, plan.isa, out,
                            err);
    }
    return run_in_process(options, plan, extensions, out, err);
  } catch (...) {
    return report_current_exception(err, kApp);
  }
}

}  // namespace losmimo::apps
