// losmimo-replay on range-only logs (mrpt_logs/range_replay.h): options, messages, exit codes.
#include <cmath>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/apps/lib/staged_output.h"
#include "losmimo/fusion/rawlog/mrpt_logs/beacon_list.h"
#include "losmimo/fusion/rawlog/mrpt_logs/mrpt_app_config.h"
#include "losmimo/fusion/rawlog/mrpt_logs/range_replay.h"
#include "messages.h"
#include "rawlog_scenes.h"
#include "replay_outputs.h"

namespace losmimo::apps {

using namespace mrpt_logs;
using namespace rawlog_io;

namespace {
constexpr const char* kApp = "losmimo-replay";
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

std::vector<double> numbers(const std::string& text, std::size_t count, const std::string& option) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) v.push_back(common::parse_double(item, option, option));
  if (v.size() != count) {
    throw common::InputError(option + " '" + text + "': expected " + std::to_string(count) + " comma-separated numbers",
                             option);
  }
  return v;
}

// The options, the config's values under the explicit ones.
RangeReplayOptions range_options(const ReplayAppOptions& o, const MrptAppConfig* cfg) {
  RangeReplayOptions ro;
  if (cfg) {
    ro.prior = cfg->prior;
    if (cfg->range_sigma_m) ro.config.filter.noise.sigma_range_m = *cfg->range_sigma_m;
    // The stock apps take beaconRangesStd unless told to use the observation's stdError.
    ro.config.use_observation_std = cfg->use_observation_std.value_or(!cfg->range_sigma_m.has_value());
    if (cfg->start_pose) ro.ground_truth_origin = *cfg->start_pose;
  } else {
    ro.config.use_observation_std = true;
  }
  if (o.estimator == "ekf" || o.estimator == "pf" || o.estimator.empty()) {
    ro.estimator = localization::filter_kind_from_string(o.estimator.empty() ? "ekf" : o.estimator);
  } else {
    throw common::InputError("--estimator '" + o.estimator + "': must be ekf or pf");
  }
  if (o.refine_window_given && !o.refine) throw common::InputError("--refine-window: needs --refine");
  if (o.refine) {
    fusion::RangeSmootherConfig refine;
    refine.window_frames = o.refine_window;
    try {
      fusion::validate(refine);
    } catch (const common::FieldError&) {  // the one field the option sets
      throw common::InputError("--refine-window " + std::to_string(o.refine_window) +
                                   ": must be 0 (smooth the whole log) or a window of 2 to 100000 frames",
                               "--refine-window");
    }
    ro.refine = refine;
  }
  if (o.range_sigma_m < 0.0 || !std::isfinite(o.range_sigma_m)) {
    throw common::InputError("--range-sigma " + common::format_double(o.range_sigma_m) + ": must be >= 0");
  }
  if (o.range_sigma_m > 0.0) {
    ro.config.use_observation_std = false;
    ro.config.filter.noise.sigma_range_m = o.range_sigma_m;
  }
  const int particles = o.particles != 0 ? o.particles : (cfg && cfg->particles ? *cfg->particles : 1000);
  if (particles < 10) throw common::InputError("--particles " + std::to_string(particles) + ": must be >= 10");
  ro.config.filter.num_particles = particles;
  if (o.settle_steps < 0)
    throw common::InputError("--settle-steps " + std::to_string(o.settle_steps) + ": must be >= 0");
  ro.settle_steps = o.settle_steps;
  if (!o.initial_pose.empty()) {
    const std::vector<double> p = numbers(o.initial_pose, 3, "--initial-pose");
    const std::vector<double> s = numbers(o.initial_sigma, 2, "--initial-sigma");
    if (!(s[0] > 0.0) || !(s[1] > 0.0)) {
      throw common::InputError("--initial-sigma '" + o.initial_sigma + "': both sigmas must be > 0");
    }
    localization::PoseBelief g;
    g.mean = Eigen::Vector4d(p[0], p[1], 0.0, p[2] * kDegToRad);
    g.cov = Eigen::Vector4d(s[0] * s[0], s[0] * s[0], 1e-6, std::pow(s[1] * kDegToRad, 2)).asDiagonal();
    ro.prior = g;
    ro.ground_truth_origin = Eigen::Vector3d(p[0], p[1], p[2] * kDegToRad);
  }
  return ro;
}
// The beacon map: --beacons FILE, else the --mrpt-config's (InputError if it has none).
localization::BeaconMap beacon_map_of(const ReplayAppOptions& options, const MrptAppConfig* cfg) {
  if (!options.beacons_path.empty()) return read_beacon_list(options.beacons_path);
  if (cfg->beacons.empty()) {
    throw common::InputError(
        options.mrpt_config +
        ": no beacon map ([MetricMap_landmarksMap_00_creationOpts] nBeacons); give --beacons FILE");
  }
  return cfg->beacons;
}

}  // namespace

int run_range_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err) {
  RangeReplayOptions ro;
  localization::BeaconMap beacons;
  std::optional<MrptAppConfig> cfg;
  try {
    if (!options.mrpt_config.empty()) cfg = read_mrpt_app_config(options.mrpt_config);
    ro = range_options(options, cfg ? &*cfg : nullptr);
    check_out_options(options);
    beacons = beacon_map_of(options, cfg ? &*cfg : nullptr);
    const std::string gt = !options.ground_truth.empty() ? options.ground_truth : cfg ? cfg->ground_truth_file : "";
    if (!gt.empty()) ro.ground_truth = read_relative_ground_truth(gt);
    if (cfg) print_unused_keys(out, options.mrpt_config, cfg->unused_keys);
  } catch (const OutputExistsError& e) {
    print_output_exists(err, kApp, e, "--out");
    return kExitBadInput;
  } catch (const std::exception& e) {  // InputError, or the beacon list cannot be opened
    print_error(err, kApp, e.what());
    return kExitBadInput;
  }
  RangeLog log;
  RangeReplayResult result;
  double filter_wall_s = 0.0;
  try {
    RawlogReaderOptions reader_options;
    reader_options.foreign = options.strict ? ForeignObjects::kStop : ForeignObjects::kSandbox;
    RawlogReader reader = RawlogReader::open_file(options.rawlog_path, reader_options);
    log = load_range_log(reader);
    filter_wall_s = timed_replay(log, [&] { result = replay_ranges(log, beacons, ro); });
  } catch (...) {
    return report_replay_error(err, kApp, options.rawlog_path);
  }
  const bool complete = log.read_status.stop == RawlogStop::kEnd;
  const int code = complete ? kExitOk : kExitFailure;
  auto rows = range_summary_rows(log, result);
  rows.push_back({"complete", complete ? "true" : "false"});
  const int published = publish_replay_outputs(
      options.out_dir, options.replace, complete, code,
      [&](const std::filesystem::path& dir) {
        write_range_track_csv(result, (dir / "track.csv").string());
        write_range_readings_csv(log, (dir / "ranges.csv").string());
        for (const std::string& w : write_range_plot(result, beacons, dir.string())) err << kApp << ": " << w << "\n";
        std::ostringstream summary;
        summary << "key,value\n";
        for (const auto& [k, v] : rows) summary << k << ",\"" << v << "\"\n";
        common::write_file_atomically((dir / "summary.csv").string(), summary.str());
        if (options.scene) scene::write_scene_file(range_scene(result, beacons), (dir / "scene.3Dscene").string());
      },
      err, kApp);
  if (published != kExitOk) return published;
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

}  // namespace losmimo::apps
