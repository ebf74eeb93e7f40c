// `losmimo-experiment merge`: finished shard folders -> one result folder.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>

#include "experiment_common.h"
#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/experiment_app.h"
#include "losmimo/placement/common/bounded_read.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/apps/lib/staged_output.h"
#include "losmimo/placement/experiment/records.h"
#include "losmimo/placement/experiment/run_folder.h"
#include "losmimo/placement/experiment/shards.h"
#include "messages.h"

namespace losmimo::apps {

using namespace experiment;
using common::InputError;

namespace {
namespace fs = std::filesystem;
constexpr const char* kApp = "losmimo-experiment merge";

// A shard folder's manifest, checked: a finished shard whose files are as it wrote them.
common::IniConfig shard_manifest(const std::string& dir) {
  if (!fs::exists(fs::path(dir) / kManifestName)) {
    const fs::path staging = StagedDir::staging_path_of(dir);
    if (fs::is_directory(staging)) {
      throw InputError(dir + ": an unfinished shard (its checkpoint is in " + staging.string() +
                       "): finish it with --resume " + dir);
    }
    throw InputError(dir + ": not a finished shard folder: no " + kManifestName + " (run with --shard i/N)");
  }
  const common::IniConfig m = read_manifest(dir);
  const std::string kind = m.get_string("run", "kind", "");
  if (kind != "shard") {
    throw InputError(dir + ": holds a finished " + kind +
                     ", not a shard (merge takes the folders of --shard i/N runs)");
  }
  verify_manifest_files(dir, m);
  if (!m.has("shard", "count") || !m.has("shard", "index")) {
    throw InputError(dir + "/" + kManifestName + ": needs [shard] index and count");
  }
  return m;
}
// The shard folders given to merge, checked: each a finished shard (its manifest), the same config,
// every shard of 0..count-1 exactly once (index -> folder), within the records size limit.
struct ShardFolders {
  ExperimentSettings settings;
  int count = -1;
  std::map<int, std::string> folders;
};

ShardFolders check_shard_folders(const MergeOptions& options, const ExperimentExtensions& extensions,
                                 RunTiming& timing) {
  ShardFolders f;
  std::string reference;
  std::uintmax_t record_bytes = 0;
  for (const std::string& d : options.shard_dirs) {
    const common::IniConfig m = shard_manifest(d);
    const int n = static_cast<int>(m.get_integer("shard", "count", 1, 1, 1'000'000'000));
    const int i = static_cast<int>(m.get_integer("shard", "index", 0, 0, n - 1));
    if (f.count != -1 && n != f.count) {
      throw InputError(d + ": shard " + std::to_string(i) + " of " + std::to_string(n) + ", but " +
                       f.folders.begin()->second + " is one of " + std::to_string(f.count));
    }
    f.count = n;
    if (f.folders.count(i))
      throw InputError(d + ": shard " + std::to_string(i) + " given twice (also " + f.folders[i] + ")");
    f.folders[i] = d;
    add_shard_timing(m, timing);
    const ExperimentSettings s = load_stored_settings((fs::path(d) / "config.ini").string(), extensions);
    const std::string config = results_config(s);
    if (reference.empty()) {
      reference = config;
      f.settings = s;
    } else if (const std::string diff = first_difference(reference, config); !diff.empty()) {
      throw InputError(d + "/config.ini differs from " + options.shard_dirs.front() + "/config.ini: " + diff);
    }
    std::error_code ec;
    record_bytes += fs::file_size(fs::path(d) / "records.csv", ec);
    if (ec) throw InputError(d + "/records.csv: missing");
  }
  std::string missing;
  for (int i = 0; i < f.count; ++i) {
    if (!f.folders.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i);
  }
  if (!missing.empty()) throw InputError("merge: missing shard(s) " + missing + " of " + std::to_string(f.count));
  if (record_bytes > common::kMaxRecordsBytes) {
    throw InputError("merge: the shards' records.csv files hold " + std::to_string(record_bytes) +
                     " bytes, more than the limit of " + common::format_bytes(common::kMaxRecordsBytes));
  }
  return f;
}

// Every shard's records.csv, verified against its folder's manifest and config, merged.
ExperimentResults merge_shard_folders(const ShardFolders& f) {
  std::vector<RecordLines> shards;
  std::vector<std::string> origins;
  for (const auto& [i, d] : f.folders) {
    const fs::path path = fs::path(d) / "records.csv";
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path.string() + ": missing");
    origins.push_back(path.string());
    shards.push_back(read_records(in, path.string(), RecordsMode::kComplete));
    const RecordsHeader& h = shards.back().header;
    if (h.kind != kRecordsKindShard || h.shard_index != i || h.shard_count != f.count) {
      throw InputError(path.string() + ": its h line says " + h.kind + " " + std::to_string(h.shard_index) + "/" +
                       std::to_string(h.shard_count) + ", the folder's manifest shard " + std::to_string(i) + "/" +
                       std::to_string(f.count) + ": the folder mixes two runs");
    }
    if (h.config_digest != config_digest(f.settings)) {
      throw InputError(path.string() + ": written for another config than its config.ini: the folder mixes two runs");
    }
  }
  return merge_shard_records(f.settings, shards, origins);
}

}  // namespace

int merge_experiment_app(const MergeOptions& options, const ExperimentExtensions& extensions, std::ostream& out,
                         std::ostream& err) {
  ExperimentSettings settings;
  ExperimentResults results;
  RunTiming timing;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    if (options.shard_dirs.empty()) throw InputError("merge: no shard folders given");
    if (options.out_dir.empty()) throw InputError("--out '': an output folder is required");
    StagedDir::check(options.out_dir, options.replace, StaleStaging::kDiscard);
    const ShardFolders folders = check_shard_folders(options, extensions, timing);
    settings = folders.settings;
    detail::check_scene_request(options.scene, static_cast<bool>(options.scene_writer), settings);
    results = merge_shard_folders(folders);
    if (const std::string note = mixed_isa_note(timing.shard_isas, "shard"); !note.empty()) {
      print_error(err, kApp, "note: " + note);
    }
  } catch (...) {
    return report_current_exception(err, kApp);
  }
  try {
    StagedDir staged = StagedDir::create(options.out_dir, options.replace, StaleStaging::kDiscard);
    results.traces = traced_runs(settings);
    timing.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timing.shards = static_cast<int>(options.shard_dirs.size());
    if (options.scene) options.scene_writer(settings, results, (staged.path() / "paths.3Dscene").string());
    detail::finish_and_publish(staged, "merged", settings, extensions, results, timing, false, out, err);
    return kExitOk;
  } catch (const OutputExistsError& e) {
    print_output_exists(err, kApp, e, "--out");
    return kExitBadInput;
  } catch (const std::exception& e) {
    print_error(err, kApp, std::string("error: ") + e.what());
    return kExitFailure;
  }
}

}  // namespace losmimo::apps
