#pragma once
// `losmimo-record`: one closed-loop mission logged as an MRPT rawlog (rawlog/recorder.h).
// Messages go to `err` prefixed "losmimo-record:", the summary line to `out`.
//
// Config file (optional) + overrides -> rawlog. Returns the exit code (exit_codes.h):
// kExitBadInput names the file, line, key and value; kExitFault when the run was ended by a
// fault (placement::RunResult::faulted(): an unresponsive UAV or a numerical fault; the reason
// goes to `err`, the rawlog is written and closed up to the fault).
// The log is written as `<out>.partial` and renamed to out_path when closed (fsynced): an
// interrupted recording never leaves a partial log under the final name nor destroys an older
// one; `<out>.partial` keeps its readable prefix. An existing out_path is refused before any
// work unless `replace`.
#include <iosfwd>
#include <string>
#include <vector>

namespace losmimo::apps {

struct RecordAppOptions {
  std::string config_path;             // empty: built-in defaults
  std::vector<std::string> overrides;  // "section.key=value"
  std::string out_path;
  bool replace = false;  // replace an existing out_path (default: refuse, kExitBadInput)
  // UAVs whose stream is also written for stock ro-localization (rawlog/ro_export.h): a UAV
  // outside the mission or given twice is refused (kExitBadInput) before any work.
  std::vector<int> ro_export_uavs{};
  // --scene: also "<out without .rawlog>.3Dscene", the recorded mission read back from the log
  // as an MRPT 3-D scene (docs/scenes.md), staged and checked like the log (an existing one is
  // refused unless `replace`); it is written after the log is complete.
  bool scene = false;
};
int run_record_app(const RecordAppOptions& options, std::ostream& out, std::ostream& err);

}  // namespace losmimo::apps
