#include "losmimo/apps/lib/replay_app.h"

#include <optional>
#include <ostream>
#include <stdexcept>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/apps/lib/staged_output.h"
#include "losmimo/placement/common/test_hook.h"
#include "losmimo/localization/position/filter.h"
#include "losmimo/fusion/rawlog/mission/replay.h"
#include "kernel_isa.h"
#include "messages.h"
#include "rawlog_scenes.h"
#include "replay_outputs.h"

namespace losmimo::apps {

using namespace rawlog;
using namespace rawlog_io;

namespace {
constexpr const char* kApp = "losmimo-replay";

// Read to a clean end, and (ours) every mark verified up to END_OF_LOG: the only logs whose
// replay exits kExitOk or kExitFault, and whose summary.csv says complete.
bool read_completely(const MissionLog& log) {
  const bool clean_end = log.read_status.stop == RawlogStop::kEnd;
  return log.ours ? log.complete && log.integrity_error.empty() && clean_end : clean_end;
}

// A foreign log the mission replay can use holds a BS beacon (CObservationBearingRange); else
// the reason, naming what the log holds instead.
std::string unusable_foreign_log(const MissionLog& log) {
  for (const auto& [key, n] : log.used) {
    if (key.find("CObservationBearingRange") != std::string::npos && n > 0) return "";
  }
  std::int64_t ranges = 0;
  for (const auto& [key, n] : log.skipped) {
    if (key.find("CObservationBeaconRanges") != std::string::npos) ranges += n;
  }
  if (ranges > 0) {
    return "no usable measurement: " + std::to_string(ranges) +
           " CObservationBeaconRanges but no beacon map (give --beacons FILE, one 'ID x y z' per line)";
  }
  std::string classes;
  for (const auto& [key, n] : log.skipped) classes += (classes.empty() ? "" : ", ") + key + " x " + std::to_string(n);
  return "no usable measurement: no beacon observation (CObservationBearingRange or CObservationBeaconRanges); "
         "skipped: " +
         (classes.empty() ? std::string("nothing") : classes);
}
}  // namespace

int run_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err) {
  try {
    if (uses_bearing_replay(options)) return run_bearing_replay_app(options, out, err);
  } catch (...) {
    return report_current_exception(err, kApp);
  }
  if (!options.beacons_path.empty() || !options.mrpt_config.empty()) return run_range_replay_app(options, out, err);
  ReplayOptions ro;
  try {
    if (options.estimator == "ekf" || options.estimator == "pf") {
      ro.estimator = localization::filter_kind_from_string(options.estimator);
    } else if (!options.estimator.empty()) {
      throw common::InputError("--estimator '" + options.estimator + "': must be ekf or pf");
    }
    if (options.refine && options.no_refine) throw common::InputError("--refine and --no-refine together");
    kernel_isa_name();  // a bad LOSMIMO_ISA stops here: kExitBadInput
    check_out_options(options);
  } catch (...) {
    return report_current_exception(err, kApp);
  }
  if (options.refine) ro.refine = true;
  if (options.no_refine) ro.refine = false;
  RawlogReaderOptions reader_options;
  reader_options.foreign = options.strict ? ForeignObjects::kStop : ForeignObjects::kSandbox;
  MissionLog log;
  ReplayResult result;
  try {
    RawlogReader reader = RawlogReader::open_file(options.rawlog_path, reader_options);
    log = load_mission_log(reader);
    // (An incomplete log goes on: its prefix is replayed, kExitFailure with where reading stopped.)
    if (!log.ours && read_completely(log)) {
      if (const std::string why = unusable_foreign_log(log); !why.empty()) throw common::InputError(why);
      if (const std::string why = landmark_log_needs_map(options.rawlog_path); !why.empty())
        throw common::InputError(why);
    }
    try {
      result = replay_mission(log, ro);
    } catch (const common::InputError& e) {
      // Nothing to replay: say why reading stopped, if it did not reach a clean end.
      if (read_completely(log)) throw;
      throw common::InputError(std::string(e.what()) + "; " + log.stop_description());
    }
  } catch (...) {
    return report_replay_error(err, kApp, options.rawlog_path);
  }
  const bool complete = read_completely(log);
  // summary.csv and stdout say `complete` as the exit code means it (a log whose END_OF_LOG
  // verified but whose gzip trailer is missing, or with bytes after its end, is not complete).
  log.complete = complete && log.ours;
  const int code = !complete ? kExitFailure : log.run_faulted() ? kExitFault : kExitOk;
  const int published = publish_replay_outputs(
      options.out_dir, options.replace, complete, code,
      [&](const std::filesystem::path& dir) {
        write_replay_csv(log, result, dir.string());
        if (options.scene) scene::write_scene_file(mission_scene(log, &result), (dir / "scene.3Dscene").string());
      },
      err, kApp);
  if (published != kExitOk) return published;
  for (const auto& [k, v] : rawlog::replay_summary_rows(log, result, false)) out << k << " = " << v << "\n";
  if (!complete) {
    print_error(err, kApp, options.rawlog_path + ": " + log.stop_description());
    return kExitFailure;
  }
  out << "read: " << log.read_status.describe() << "\n";
  if (log.run_faulted()) {
    err << "losmimo-replay: " << options.rawlog_path << ": the recorded run was ended by a fault ("
        << log.run_end.status << "): " << (log.run_end.fault.empty() ? "reason not in the log" : log.run_end.fault)
        << "; its " << log.epochs.size() << " epochs up to the fault were replayed\n";
  }
  return code;
}

}  // namespace losmimo::apps
