#include "losmimo/apps/replay_app.h"

#include <ostream>
#include <stdexcept>

#include "losmimo/apps/exit_codes.h"
#include "losmimo/common/input_error.h"
#include "losmimo/localization/filter.h"
#include "losmimo/rawlog/replay.h"

namespace losmimo::apps {

using namespace rawlog;

int run_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err) {
  ReplayOptions ro;
  if (options.estimator == "ekf" || options.estimator == "pf") {
    ro.estimator = localization::filter_kind_from_string(options.estimator);
  } else if (!options.estimator.empty()) {
    err << "losmimo-replay: --estimator '" << options.estimator << "': must be ekf or pf\n";
    return kExitBadInput;
  }
  if (options.refine && options.no_refine) {
    err << "losmimo-replay: --refine and --no-refine together\n";
    return kExitBadInput;
  }
  if (options.refine) ro.refine = true;
  if (options.no_refine) ro.refine = false;
  RawlogReaderOptions reader_options;
  reader_options.parse_unscanned_classes = !options.strict;
  MissionLog log;
  ReplayResult result;
  try {
    RawlogReader reader = RawlogReader::open_file(options.rawlog_path, reader_options);
    log = load_mission_log(reader);
    result = replay_mission(log, ro);
  } catch (const common::InputError& e) {
    err << "losmimo-replay: " << options.rawlog_path << ": " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::runtime_error& e) {  // cannot open the file
    err << "losmimo-replay: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    err << "losmimo-replay: " << options.rawlog_path << ": replay failed: " << e.what() << "\n";
    return kExitFailure;
  }
  try {
    if (!options.out_dir.empty()) write_replay_csv(log, result, options.out_dir);
  } catch (const std::exception& e) {
    err << "losmimo-replay: " << e.what() << "\n";
    return kExitFailure;
  }
  for (const auto& [k, v] : rawlog::replay_summary_rows(log, result, false)) out << k << " = " << v << "\n";
  const bool complete = log.ours ? log.complete && log.integrity_error.empty() &&
                                       log.read_status.stop == RawlogStop::kEnd
                                 : log.read_status.stop == RawlogStop::kEnd;
  if (!complete) {
    err << "losmimo-replay: " << options.rawlog_path << ": " << log.stop_description() << "\n";
    return kExitFailure;
  }
  out << "read: " << log.read_status.describe() << "\n";
  if (log.run_faulted()) {
    err << "losmimo-replay: " << options.rawlog_path << ": the recorded run was ended by a fault ("
        << log.run_end.status << "): " << (log.run_end.fault.empty() ? "reason not in the log" : log.run_end.fault)
        << "; its " << log.epochs.size() << " epochs up to the fault were replayed\n";
    return kExitFault;
  }
  return kExitOk;
}

}  // namespace losmimo::apps
