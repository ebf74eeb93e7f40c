#include "losmimo/apps/record_app.h"

#include <ostream>

#include "losmimo/apps/exit_codes.h"
#include "losmimo/coevaluation/extensions.h"
#include "losmimo/common/ini_config.h"
#include "losmimo/experiment/extension.h"
#include "losmimo/rawlog/recorder.h"

namespace losmimo::apps {

using namespace rawlog;

int run_record_app(const RecordAppOptions& options, std::ostream& out, std::ostream& err) {
  MissionConfig config;
  try {
    common::IniConfig ini = options.config_path.empty()
                                   ? common::IniConfig()
                                   : common::IniConfig::from_file(options.config_path);
    for (const std::string& o : options.overrides) ini.set_override(o);
    // An experiment config (e.g. datasets/configs/paper.ini) is a valid mission source too.
    config = load_mission_config(ini, experiment::experiment_config_keys(coevaluation::experiment_extensions()));
    if (options.out_path.empty()) throw common::InputError("--out: an output file is required");
  } catch (const common::InputError& e) {
    err << "losmimo-record: " << e.what() << "\n";
    return kExitBadInput;
  }
  try {
    const RecordResult r = record_mission(config, {options.out_path, 6, {}});
    out << "losmimo-record: " << options.out_path << ": " << r.objects << " objects ("
        << r.uncompressed_bytes << " bytes uncompressed), " << r.epochs << " epochs, "
        << r.run.run.iterations << " iterations, " << placement::to_string(r.run.run.status)
        << ", final ICN " << (r.run.run.trace.empty() ? 0.0 : r.run.run.trace.back().icn) << "\n";
    if (r.run.run.faulted()) {  // the log is complete up to the fault (END_OF_LOG has the status)
      err << "losmimo-record: run ended by a fault: " << r.run.run.fault << "\n";
      return kExitFault;
    }
    return kExitOk;
  } catch (const std::exception& e) {
    err << "losmimo-record: " << e.what() << "\n";
    return kExitFailure;
  }
}

}  // namespace losmimo::apps
