// losmimo-replay on bearing-range logs with a landmark map (mrpt_logs/bearing_replay.h):
// options, messages, exit codes.
#include <filesystem>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/apps/lib/staged_output.h"
#include "losmimo/fusion/rawlog/mrpt_logs/bearing_replay.h"
#include "losmimo/fusion/rawlog/mrpt_logs/landmark_files.h"
#include "losmimo/fusion/rawlog/mrpt_logs/mrpt_app_config.h"
#include "messages.h"
#include "rawlog_scenes.h"
#include "replay_outputs.h"

namespace losmimo::apps {

using namespace mrpt_logs;
using namespace rawlog_io;

namespace {
constexpr const char* kApp = "losmimo-replay";
constexpr int kDefaultParticles = 100;  // the optimal proposal keeps few particles diverse (docs/bearing-range.md)

// The range-only options that have no meaning here are refused, not ignored.
void refuse_range_only_options(const ReplayAppOptions& o) {
  const auto refuse = [](const std::string& option, const std::string& why) {
    throw common::InputError(option + ": " + why, option);
  };
  if (!o.beacons_path.empty()) refuse("--beacons", "give one map: --landmarks for a bearing-range log");
  if (!o.initial_pose.empty())
    refuse("--initial-pose", "not used by the bearing-range replay (it starts at the map origin, as kf-slam)");
  if (o.range_sigma_m != 0.0)
    refuse("--range-sigma",
           "not used by the bearing-range replay (the noise comes from the log's sensor_std_* "
           "fields or --mrpt-config's std_sensor_*)");
  if (o.refine_window_given) refuse("--refine-window", "the bearing-range replay refines the whole log (no window)");
}

BearingReplayOptions bearing_options(const ReplayAppOptions& o, const KfSlamConfig* cfg) {
  refuse_range_only_options(o);
  BearingReplayOptions bo;
  if (o.estimator == "ekf" || o.estimator == "pf" || o.estimator.empty()) {
    bo.estimator = localization::filter_kind_from_string(o.estimator.empty() ? "ekf" : o.estimator);
  } else {
    throw common::InputError("--estimator '" + o.estimator + "': must be ekf or pf");
  }
  if (o.refine && o.no_refine) throw common::InputError("--refine and --no-refine together");
  bo.refine = o.refine;
  bo.strict = o.strict;
  const int particles = o.particles != 0 ? o.particles : kDefaultParticles;
  if (particles < 10) throw common::InputError("--particles " + std::to_string(particles) + ": must be >= 10");
  bo.config.num_particles = particles;
  if (cfg) {
    if (cfg->sensor_sigma) {  // kf-slam's noise keys win over the observations' fields, as in kf-slam
      bo.config.sigma = *cfg->sensor_sigma;
      bo.config.use_scan_sigma = false;
    }
    bo.odometry_z_sigma_additional_m = cfg->odometry_z_sigma_additional_m;
    if (cfg->no_odometry_sigma) bo.no_odometry_sigma = *cfg->no_odometry_sigma;
  }
  return bo;
}

int publish(const ReplayAppOptions& options, const BearingLog& log, const BearingReplayResult& result,
            const localization::BeaconMap& landmarks, double filter_wall_s, std::ostream& out, std::ostream& err) {
  const bool complete = log.read_status.stop == RawlogStop::kEnd;
  const int code = complete ? kExitOk : kExitFailure;
  auto rows = bearing_summary_rows(log, result);
  rows.push_back({"complete", complete ? "true" : "false"});
  const int published = publish_replay_outputs(
      options.out_dir, options.replace, complete, code,
      [&](const std::filesystem::path& dir) {
        write_bearing_track_csv(result, (dir / "track.csv").string());
        for (const std::string& w : write_bearing_plot(result, landmarks, dir.string()))
          err << kApp << ": " << w << "\n";
        std::ostringstream summary;
        summary << "key,value\n";
        for (const auto& [k, v] : rows) summary << k << ",\"" << v << "\"\n";
        common::write_file_atomically((dir / "summary.csv").string(), summary.str());
        if (options.scene) scene::write_scene_file(bearing_scene(result, landmarks), (dir / "scene.3Dscene").string());
      },
      err, kApp);
  if (published != kExitOk) return published;
  for (const std::string& note : result.notes) err << kApp << ": " << options.rawlog_path << ": " << note << "\n";
  for (const auto& [k, v] : rows) out << k << " = " << v << "\n";
  // Process-dependent: stdout only.
  out << "filter_wall_s = " << common::format_g(filter_wall_s - result.refine_wall_s, 4) << "\n";
  if (result.refined) out << "refine_wall_s = " << common::format_g(result.refine_wall_s, 4) << "\n";
  if (!complete) {
    print_error(err, kApp, options.rawlog_path + ": " + log.read_status.describe());
    return kExitFailure;
  }
  out << "read: " << log.read_status.describe() << "\n";
  return code;
}

}  // namespace

bool uses_bearing_replay(const ReplayAppOptions& options) {
  return !options.landmarks_path.empty() || (!options.mrpt_config.empty() && is_kf_slam_config(options.mrpt_config));
}

std::string landmark_log_needs_map(const std::string& rawlog_path) {
  RawlogReaderOptions reader_options;
  reader_options.foreign = ForeignObjects::kSandbox;
  RawlogReader reader = RawlogReader::open_file(rawlog_path, reader_options);
  const BearingLog log = load_bearing_log(reader);
  if (log.max_readings_per_observation <= 1) return "";
  return "a bearing-range log of mapped landmarks (" + std::to_string(log.bearing_observations) +
         " CObservationBearingRange with up to " + std::to_string(log.max_readings_per_observation) +
         " readings each) needs the landmark map: give --landmarks FILE (MRPT's ground-truth landmark file) or "
         "--mrpt-config INI (a kf-slam configuration)";
}

int run_bearing_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err) {
  BearingReplayOptions bo;
  localization::BeaconMap landmarks;
  std::optional<KfSlamConfig> cfg;
  try {
    if (!options.mrpt_config.empty()) cfg = read_kf_slam_config(options.mrpt_config);
    bo = bearing_options(options, cfg ? &*cfg : nullptr);
    check_out_options(options);
    const std::string map_file = !options.landmarks_path.empty() ? options.landmarks_path : cfg->landmarks_file;
    if (map_file.empty()) {
      throw common::InputError(options.mrpt_config +
                               ": no landmark map ([MappingApplication] ground_truth_file); give --landmarks FILE");
    }
    landmarks = read_landmark_file(map_file);
    const std::string gt = !options.ground_truth.empty() ? options.ground_truth : cfg ? cfg->robot_path_file : "";
    if (!gt.empty()) bo.ground_truth = read_robot_path(gt);
    if (cfg) {
      print_unused_keys(out, options.mrpt_config, cfg->unused_keys);
      if (!cfg->rawlog_file.empty() &&
          std::filesystem::weakly_canonical(cfg->rawlog_file) != std::filesystem::weakly_canonical(options.rawlog_path))
        out << "note: replaying " << options.rawlog_path << ", not the config's rawlog_file " << cfg->rawlog_file
            << "\n";
    }
  } catch (const OutputExistsError& e) {
    print_output_exists(err, kApp, e, "--out");
    return kExitBadInput;
  } catch (const std::exception& e) {  // InputError, or a file that cannot be opened
    print_error(err, kApp, e.what());
    return kExitBadInput;
  }
  BearingLog log;
  BearingReplayResult result;
  double filter_wall_s = 0.0;
  try {
    // --strict here stops at a landmark ID the map lacks; the classes the reader cannot bound
    // (CSensoryFrame: every kf-slam log) are still parsed in the sandbox, else nothing would load.
    RawlogReaderOptions reader_options;
    reader_options.foreign = ForeignObjects::kSandbox;
    RawlogReader reader = RawlogReader::open_file(options.rawlog_path, reader_options);
    log = load_bearing_log(reader);
    filter_wall_s = timed_replay(log, [&] { result = replay_bearings(log, landmarks, bo); });
  } catch (...) {
    return report_replay_error(err, kApp, options.rawlog_path);
  }
  return publish(options, log, result, landmarks, filter_wall_s, out, err);
}

}  // namespace losmimo::apps
