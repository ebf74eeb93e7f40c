#pragma once
// What the replays (mission, range-only and bearing-range logs) do alike: check --out and
// --scene, name the stock configuration's keys they do not use, report an error while reading
// the log, and write their outputs into --out as one staged folder (it appears whole or not at
// all, with a manifest saying whether the log was read completely and the exit code).
#include <chrono>
#include <filesystem>
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/common/text.h"
#include "losmimo/apps/lib/staged_output.h"
#include "losmimo/placement/common/test_hook.h"
#include "losmimo/fusion/rawlog/io/reader.h"
#include "messages.h"

namespace losmimo::apps {

// --out and --scene before any work: an empty --out, --scene without --out (it writes into
// that folder), and an --out that holds results without --replace are refused (InputError or
// OutputExistsError).
inline void check_out_options(const ReplayAppOptions& options) {
  if (options.out_given && options.out_dir.empty()) throw common::InputError("--out '': an output folder is required");
  if (options.scene && options.out_dir.empty())
    throw common::InputError("--scene: writes scene.3Dscene into the --out folder: give --out DIR");
  if (!options.out_dir.empty()) StagedDir::check(options.out_dir, options.replace, StaleStaging::kDiscard);
}

// "not used from CONFIG: k1, k2" on out, nothing when every key is used.
inline void print_unused_keys(std::ostream& out, const std::string& config_path, const std::vector<std::string>& keys) {
  if (keys.empty()) return;
  out << "not used from " << config_path << ": " << common::join(keys) << "\n";
}

// Called inside a catch (...) around reading and replaying `rawlog_path`: bad input and a file
// that cannot be opened are kExitBadInput, anything else is a failed replay (kExitFailure).
// Runs replay() on a log read into `log` and returns its wall time [s]. Bad input found by a
// replay of a log whose reading stopped early also says where and why reading stopped.
template <typename Log, typename Replay>
double timed_replay(const Log& log, Replay replay) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    replay();
  } catch (const common::InputError& e) {
    if (log.read_status.stop == rawlog_io::RawlogStop::kEnd) throw;
    throw common::InputError(std::string(e.what()) + "; reading stopped: " + log.read_status.describe());
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

inline int report_replay_error(std::ostream& err, const std::string& app, const std::string& rawlog_path) {
  try {
    throw;
  } catch (const common::InputError& e) {
    print_error(err, app, rawlog_path + ": " + e.what());
    return kExitBadInput;
  } catch (const std::runtime_error& e) {  // cannot open the file
    print_error(err, app, e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    print_error(err, app, rawlog_path + ": replay failed: " + e.what());
    return kExitFailure;
  }
}

// Writes the outputs with `write` (given the staging folder) and publishes them as `out_dir`;
// nothing when out_dir is empty. Returns kExitOk, or the exit code after printing why not.
inline int publish_replay_outputs(const std::string& out_dir, bool replace, bool complete, int exit_code,
                                  const std::function<void(const std::filesystem::path&)>& write, std::ostream& err,
                                  const std::string& app) {
  if (out_dir.empty()) return kExitOk;
  try {
    StagedDir staged = StagedDir::create(out_dir, replace, StaleStaging::kDiscard);
    write(staged.path());
    common::test_pause_point("replay.outputs_written");
    Manifest m;
    m.kind = "replay";
    m.run_keys = {{"app", app}, {"complete", complete ? "true" : "false"}, {"exit_code", std::to_string(exit_code)}};
    staged.publish(m);
    return kExitOk;
  } catch (const OutputExistsError& e) {
    print_output_exists(err, app, e, "--out");
    return kExitBadInput;
  } catch (const std::exception& e) {
    print_error(err, app, e.what());
    return kExitFailure;
  }
}

}  // namespace losmimo::apps
