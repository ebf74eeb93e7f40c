#pragma once
// `losmimo-replay`: a rawlog's sensor stream through an estimator, offline (rawlog/replay.h).
// Messages go to `err` prefixed "losmimo-replay:", the summary to `out`.
//
// Exit code (exit_codes.h): kExitOk for a complete log replayed; kExitBadInput for a missing
// file, not a rawlog, a bad option or CONFIG; kExitFailure for a runtime error or a
// truncated/corrupt log (its readable prefix replayed and written, the report says where and why
// reading stopped); kExitFault for a complete log of a run that losmimo-record ended by a fault:
// every epoch up to the fault replayed and written, the status and the reason from END_OF_LOG
// go to `err`.
// Outputs (--out DIR) are written into DIR.partial/ and renamed into place with their manifest
// (staged_output.h); summary.csv's `complete` agrees with the exit code. A DIR that holds
// an earlier replay (or anything else) is refused (kExitBadInput) before reading, unless
// `replace`.
#include <iosfwd>
#include <string>

namespace losmimo::apps {

struct ReplayAppOptions {
  std::string rawlog_path;
  std::string estimator;  // "", "ekf" or "pf"
  bool refine = false;
  bool no_refine = false;
  std::string out_dir;     // empty: summary to stdout only (unless out_given: then an error)
  bool strict = false;     // stop at classes the reader cannot bound, no sandbox (RawlogReaderOptions)
  bool replace = false;    // replace an earlier replay in out_dir
  bool out_given = false;  // --out was given (so an empty out_dir is a mistake, not "none")
  // Range-only logs (rawlog/range_replay.h): a beacon list file (`ID x y z` per line) selects
  // that replay; the start pose "x,y,yaw_deg" with its 1-sigma "xy_m,yaw_deg" (default: uniform
  // over the beacons, any heading); the range 1-sigma (default: each observation's stdError).
  std::string beacons_path{};
  std::string initial_pose{};
  std::string initial_sigma = "0.1,2";
  double range_sigma_m = 0.0;  // 0: the log's stdError
  int particles = 0;           // 0: [PF_options] sampleSize of --mrpt-config, else 1000
  int settle_steps = 10;
  // --refine on a range-only log: 0 smooths the whole log in one Ceres problem, W >= 2 refines
  // each frame in the window of the last W frames (fusion/range_smoother.h).
  int refine_window = 0;
  bool refine_window_given = false;
  // A stock ro-localization / pf-localization APP.ini (rawlog/mrpt_app_config.h): beacon map,
  // prior, range noise, particles, ground truth. Explicit options win over it.
  std::string mrpt_config{};
  std::string ground_truth{};  // ro-localization's groundTruthFile format ("k x y phi" rows); bearing-range:
                               // MRPT's robot path ("x y z yaw pitch roll" rows)
  // Bearing-range logs (mrpt_logs/bearing_replay.h): MRPT's ground-truth landmark file selects that
  // replay, as does a kf-slam INI given as mrpt_config.
  std::string landmarks_path{};
  // --scene: scene.3Dscene in the --out folder (required: without it, exit 2), the replay as an
  // MRPT 3-D scene (docs/scenes.md): truth, beliefs and covariances, BS array and beacons.
  bool scene = false;
};
int run_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err);
// The range-only replay (options.beacons_path or options.mrpt_config set), same exit codes; kExitBadInput also for a
// log with no usable measurement (no CObservationBeaconRanges, no beacon ID in the map, nothing fused).
int run_range_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err);
// The bearing-range replay (landmarks_path set, or mrpt_config a kf-slam INI), same exit codes: 2 also for a
// log with nothing usable, and with `strict` for a landmark ID the map lacks.
int run_bearing_replay_app(const ReplayAppOptions& options, std::ostream& out, std::ostream& err);
bool uses_bearing_replay(const ReplayAppOptions& options);
// For a foreign log without a map: the reason to refuse it when its CObservationBearingRange hold several
// readings (mapped landmarks, not the one BS beacon the mission replay takes), else empty.
std::string landmark_log_needs_map(const std::string& rawlog_path);

}  // namespace losmimo::apps
