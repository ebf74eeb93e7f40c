// losmimo-record: one closed-loop mission logged as an MRPT rawlog (rawlog/recorder.h).
// Exit codes: 0 ok, 1 runtime failure, 2 bad input, 3 the run was ended by a fault (an
// unresponsive UAV or a numerical fault; the reason is printed, the rawlog is kept).
#include <CLI/CLI.hpp>
#include <iostream>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/record_app.h"
#include "version_flag.h"

int main(int argc, char** argv) {
  losmimo::apps::RecordAppOptions options;
  CLI::App app{"Record one closed-loop losmimo mission as an MRPT rawlog"};
  losmimo::apps::add_version_flag(app);
  app.add_option("--config", options.config_path, "mission INI (default: built-in defaults)");
  app.add_option("--set", options.overrides, "override a key: section.key=value (repeatable)");
  app.add_option("--out", options.out_path, "output rawlog (gzip), written as <out>.partial until complete")
      ->required();
  app.add_option("--ro-export", options.ro_export_uavs,
                 "also write this UAV's stream for stock ro-localization beside the log: <out>.uavNN.ro.rawlog, "
                 ".ro.ini, .ro_truth.txt (repeatable)");
  app.add_flag("--replace", options.replace, "replace an existing --out file (default: refuse, exit 2)");
  app.add_flag("--scene", options.scene,
               "also write <out without .rawlog>.3Dscene, the mission as a 3-D scene for MRPT's SceneViewer3D");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? losmimo::apps::kExitOk : losmimo::apps::kExitBadInput;
  }
  return losmimo::apps::run_record_app(options, std::cout, std::cerr);
}
