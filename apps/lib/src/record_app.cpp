#include "losmimo/apps/lib/record_app.h"

#include <filesystem>
#include <fstream>
#include <optional>
#include <ostream>
#include <set>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/unused_keys.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/apps/lib/staged_output.h"
#include "losmimo/placement/common/test_hook.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "losmimo/fusion/rawlog/io/reader.h"
#include "kernel_isa.h"
#include "rawlog_scenes.h"
#include "messages.h"
#include "record_ro_export.h"

namespace losmimo::apps {

using namespace rawlog;

namespace {
constexpr const char* kApp = "losmimo-record";

// The scene of the log just published, read back as losmimo-replay reads it.
void write_record_scene(const std::string& log_path, StagedFile& staged_scene) {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(log_path, {});
  const MissionLog log = load_mission_log(reader);
  const std::string bytes = scene::scene_file_bytes(mission_scene(log, nullptr));
  std::ofstream f(staged_scene.path(), std::ios::binary);
  if (!f.write(bytes.data(), static_cast<std::streamsize>(bytes.size())) || !f.flush())
    throw std::runtime_error(staged_scene.path() + ": cannot write");
  staged_scene.publish();
}

// The mission of --config and --set, every override acting or refused (kExitBadInput).
MissionConfig load_record_config(const RecordAppOptions& options) {
  MissionConfig config;
  common::IniConfig ini =
      options.config_path.empty() ? common::IniConfig() : common::IniConfig::from_file(options.config_path);
  for (const std::string& o : options.overrides) ini.set_override(o);
  // An experiment config (e.g. datasets/configs/paper.ini) is a valid mission source too; its
  // [experiment] keys are not used here, but checked like everything else.
  const experiment::ExperimentExtensions extensions = coevaluation::experiment_extensions();
  config = load_mission_config(ini, experiment::experiment_config_keys(extensions));
  std::set<std::string> experiment_sections;
  for (const auto& [section, keys] : experiment::experiment_config_keys(extensions))
    experiment_sections.insert(section);
  if (ini.has_section("experiment")) experiment::load_experiment_settings(ini.subset(experiment_sections), extensions);
  KeyUser record{"losmimo-record", {}};
  if (config.closed_loop.filter_kind == localization::FilterKind::kEkf) record.conditions.push_back(kEkfFilter);
  if (!config.closed_loop.refine) record.conditions.push_back(kNoRefinement);
  refuse_unused_overrides(ini, options.overrides, {record});
  return config;
}
}  // namespace

int run_record_app(const RecordAppOptions& options, std::ostream& out, std::ostream& err) {
  MissionConfig config;
  std::optional<StagedFile> staged, staged_beacons, staged_scene;
  std::optional<RoExportOutputs> ro_exports;
  try {
    config = load_record_config(options);
    if (options.out_path.empty()) throw common::InputError("--out: an output file is required");
    kernel_isa_name();  // a bad LOSMIMO_ISA stops here: kExitBadInput
    staged.emplace(StagedFile::create(options.out_path, options.replace));
    try {
      staged_beacons.emplace(StagedFile::create(beacons_ini_path(options.out_path), options.replace));
      ro_exports.emplace(RoExportOutputs::create(options.out_path, options.ro_export_uavs,
                                                 config.placement.scenario.num_uavs, options.replace));
      if (options.scene) staged_scene.emplace(StagedFile::create(scene_path_beside(options.out_path), options.replace));
    } catch (...) {
      std::error_code ignored;  // the staged files were just created, empty: no litter from a refused run
      std::filesystem::remove(staged->path(), ignored);
      if (staged_beacons) std::filesystem::remove(staged_beacons->path(), ignored);
      if (ro_exports) ro_exports->discard();
      throw;
    }
  } catch (...) {
    return report_current_exception(err, kApp);
  }
  try {
    RecordOptions ro;
    ro.out_path = staged->path();
    ro.after_epoch_mark = [](int) { common::test_pause_point("record.epoch_mark"); };
    const RecordResult r = record_mission(config, ro);
    staged->publish();
    // The beacon map of the BS_RANGES streams, for stock MRPT apps (docs/replay.md).
    {
      std::ofstream f(staged_beacons->path());
      if (!(f << mission_beacons_ini_text(config)) || !f.flush())
        throw std::runtime_error(staged_beacons->path() + ": cannot write");
    }
    staged_beacons->publish();
    out << "losmimo-record: " << options.out_path << ": " << r.objects << " objects (" << r.uncompressed_bytes
        << " bytes uncompressed), " << r.epochs << " epochs, " << r.run.run.iterations << " iterations, "
        << placement::to_string(r.run.run.status) << ", final ICN "
        << (r.run.run.trace.empty() ? 0.0 : r.run.run.trace.back().icn) << "\n"
        << "losmimo-record: the beliefs placement used: lateral RMSE " << r.run.stats.lateral_rmse_m
        << " m, of it a common offset of " << r.run.stats.common_lateral_rms_m << " m (RMS) and a shape error of "
        << r.run.stats.shape_lateral_rmse_m << " m (RMSE); shape NEES " << r.run.stats.shape_nees_per_dof
        << " per degree of freedom (1 = consistent)\n"
        << "losmimo-record: beacon map for stock MRPT apps: " << staged_beacons->final_path() << "\n";
    try {  // one UAV's stream for stock ro-localization (--ro-export), from the published log
      ro_exports->write(options.out_path, out);
    } catch (const std::exception& e) {
      ro_exports->discard();
      std::error_code ignored;  // the scene is written after the export: nothing of it yet
      if (staged_scene) std::filesystem::remove(staged_scene->path(), ignored);
      print_error(err, kApp,
                  std::string("--ro-export: ") + e.what() + " (the log is complete: " + options.out_path + ")");
      return kExitFailure;
    }
    if (staged_scene) {
      try {
        write_record_scene(staged->final_path(), *staged_scene);
      } catch (const std::exception& e) {
        std::error_code ignored;  // no half-written scene
        std::filesystem::remove(staged_scene->path(), ignored);
        print_error(err, kApp, std::string("--scene: ") + e.what() + " (the log is complete)");
        return kExitFailure;
      }
      out << "losmimo-record: 3-D scene for MRPT's SceneViewer3D: " << staged_scene->final_path() << "\n";
    }
    if (r.run.run.faulted()) {  // the log is complete up to the fault (END_OF_LOG has the status)
      err << "losmimo-record: run ended by a fault: " << r.run.run.fault << "\n";
      return kExitFault;
    }
    return kExitOk;
  } catch (const OutputExistsError& e) {
    print_output_exists(err, kApp, e, "--out");
    return kExitBadInput;
  } catch (const std::exception& e) {
    print_error(err, kApp, std::string(e.what()) + " (what was written is in " + staged->path() + ")");
    return kExitFailure;
  }
}

}  // namespace losmimo::apps
