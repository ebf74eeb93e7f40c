#pragma once
// losmimo-record --ro-export UAV: the stock ro-localization files of one UAV's stream
// (rawlog/ro_export.h), written beside the log once it is complete.
#include <iosfwd>
#include <string>
#include <vector>

#include "losmimo/apps/lib/staged_output.h"

namespace losmimo::apps {

class RoExportOutputs {
 public:
  // Refuses (common::InputError naming --ro-export and the value) a UAV outside
  // 0 .. num_uavs - 1 or one given twice; then stages each UAV's three files beside log_path
  // (rawlog::ro_export_paths), refusing existing ones unless `replace` (OutputExistsError).
  // What it staged before a refusal is removed.
  static RoExportOutputs create(const std::string& log_path, const std::vector<int>& uavs, int num_uavs, bool replace);
  // Reads the complete log at log_path back, writes and publishes every UAV's files, and says
  // where they are on `out`. Throws common::InputError (a UAV that reported nothing) or
  // std::runtime_error.
  void write(const std::string& log_path, std::ostream& out);
  // Removes the staged files (a run refused before any work).
  void discard();

 private:
  struct Uav {
    int uav = 0;
    std::vector<StagedFile> files;  // rawlog, ini, ground truth
    std::string log_output_dir;
  };
  std::vector<Uav> uavs_;
};

}  // namespace losmimo::apps
