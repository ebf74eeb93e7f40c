// losmimo-replay: a rawlog's sensor stream through an estimator, offline (rawlog/replay.h).
// Exit codes: 0 complete log replayed, 1 runtime failure or truncated/corrupt log (its readable
// prefix replayed), 2 bad input, 3 complete log of a run that was ended by a fault (the status
// and the reason from the log are printed; everything up to the fault is replayed).
// Foreign rawlogs are parsed in a bounded child process (rawlog/sandbox.h).
#include <CLI/CLI.hpp>
#include <iostream>

#include "losmimo/apps/lib/exit_codes.h"
#include "losmimo/apps/lib/replay_app.h"
#include "version_flag.h"

int main(int argc, char** argv) {
  losmimo::apps::ReplayAppOptions options;
  CLI::App app{"Replay a rawlog through an estimator and evaluate the placement along it"};
  losmimo::apps::add_version_flag(app);
  app.add_option("rawlog", options.rawlog_path, "input rawlog (gzip or plain)")->required();
  app.add_option("--estimator", options.estimator, "ekf or pf (default: as recorded)");
  app.add_flag("--refine", options.refine,
               "Ceres sliding-window refinement (default: as recorded); range-only: a Ceres smoother after the filter");
  app.add_flag("--no-refine", options.no_refine, "no refinement");
  CLI::Option* out_option =
      app.add_option("--out", options.out_dir, "write estimates.csv, epochs.csv, summary.csv into this new folder");
  app.add_flag("--replace", options.replace, "replace an earlier replay in the --out folder (default: refuse, exit 2)");
  app.add_flag("--scene", options.scene,
               "also write scene.3Dscene into the --out folder: the replay as a 3-D scene for MRPT's SceneViewer3D");
  app.add_flag("--strict", options.strict,
               "stop at object classes the reader cannot bound, instead of parsing them in the sandbox; bearing-range "
               "replay: stop (exit 2) at a landmark ID the map lacks (the sandbox still parses the log)");
  app.add_option("--beacons", options.beacons_path,
                 "range-only replay: beacon list file, one 'ID x y z' per line (MRPT's ground-truth beacon files)");
  app.add_option("--landmarks", options.landmarks_path,
                 "bearing-range replay (CObservationBearingRange logs, e.g. MRPT's kf-slam demos): landmark map in "
                 "MRPT's ground-truth format, one 'x y z ... ID' per line");
  app.add_option("--initial-pose", options.initial_pose,
                 "range-only: start pose 'x,y,yaw_deg' (default: uniform over the beacons)");
  app.add_option("--initial-sigma", options.initial_sigma, "range-only: start 1-sigma 'xy_m,yaw_deg' (default 0.1,2)");
  app.add_option("--range-sigma", options.range_sigma_m, "range-only: range 1-sigma [m] (default: the log's stdError)");
  app.add_option("--particles", options.particles,
                 "range-only, --estimator pf: particles (default: the config's sampleSize, else 1000)");
  app.add_option("--mrpt-config", options.mrpt_config,
                 "range-only: a stock ro-localization / pf-localization APP.ini (beacon map, prior, beaconRangesStd, "
                 "groundTruthFile); bearing-range: a stock kf-slam INI (landmarks, robot path, std_sensor_*)");
  app.add_option("--ground-truth", options.ground_truth,
                 "range-only: robot path as ro-localization's groundTruthFile ('k x y phi' relative to the start); "
                 "bearing-range: MRPT's robot path file ('x y z yaw pitch roll' per sensory frame)");
  app.add_option("--settle-steps", options.settle_steps,
                 "range-only: frames before the settled residual RMS (default 10)");
  CLI::Option* refine_window_option = app.add_option(
      "--refine-window", options.refine_window,
      "range-only, with --refine: 0 smooths the whole log (default), W >= 2 refines each frame over its last W frames");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? losmimo::apps::kExitOk : losmimo::apps::kExitBadInput;
  }
  options.out_given = out_option->count() > 0;
  options.refine_window_given = refine_window_option->count() > 0;
  return losmimo::apps::run_replay_app(options, std::cout, std::cerr);
}
