#pragma once
// One UAV's stream of a losmimo mission log as stock MRPT ro-localization reads it (Debian
// mrpt-apps): a sensory-frame rawlog, its ground-truth file and a config that runs it
// (docs/rawlog-format.md, "Logs for stock MRPT apps").
//
// Frames: one per epoch the UAV reported (log.h), in epoch order; frame j is the log's j-th
// (CActionCollection, CSensoryFrame) pair, which ro-localization processes as its step j:
//   action  CActionRobotMovement2D whose poseChange is a CPosePDFGaussian: the measured
//           displacement's (x, y) as a robot-frame increment. The odometry's axes are the BS
//           frame's (heading 0 throughout), so the robot-frame increment (composed as a CPose2D)
//           equals the BS-frame displacement. Covariance diag(s^2, s^2, kRoHeadingSigma_rad^2),
//           s = the DR stream's sigma (format.h; floored at kRoMinIncrementSigma_m). A frame
//           without a displacement (the first) is a zero motion. Its estimationMethod is
//           emScan2DMatching, the one MRPT stores with its PDF (an emOdometry action is stored
//           as the raw increment and a motion model's parameters, and read back with the
//           model's covariance instead of the log's).
//   frame   a CSensoryFrame with the epoch's BS_RANGES reading (format.h: beacon kBsBeaconId at
//           the BS array centre, float range, stdError = the beacon's range sigma), or empty at
//           an epoch without a beacon (an outage), so that frames stay aligned with epochs.
// Start: the UAV's logged filter belief after its first frame (x, y; heading 0), what the
// losmimo filter knew there (the first beacon's fix, or the start-cube prior's centre in an
// outage): [OdometryEstimation] odometry_X / odometry_Y / odometry_PHI. ro-localization draws
// its particles uniformly within +-0.5 m of it, with any heading.
// Ground truth: row j = "j x y phi": the true (x, y) at frame j minus the start, phi = 0;
// ro-localization composes start (+) row j and prints it as "GT robot pose" at step j.
// The stock app is 2-D: it places the UAV in the BS's horizontal plane, so an altitude z shows
// as an error of about z^2 / (2 R) along the line of sight (R the range).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "losmimo/fusion/rawlog/mission/log.h"

namespace losmimo::rawlog {

// The heading 1-sigma per frame [rad]: the UAV's heading is not part of losmimo's state (its
// displacements are measured in the BS frame), but MRPT's pose sampler needs a positive-definite
// covariance, and a little heading spread keeps the stock PF's heading hypotheses diverse.
inline constexpr double kRoHeadingSigma_rad = 1e-3;
inline constexpr double kRoMinIncrementSigma_m = 1e-4;
// The stock PF's particle count and seed written into the config (fixed: reproducible runs).
inline constexpr int kRoParticles = 5000;
inline constexpr int kRoRandomSeed = 1;

struct RoFrame {
  int epoch = 0;
  Eigen::Vector2d increment_m = Eigen::Vector2d::Zero();  // robot frame = BS frame (heading 0)
  double increment_sigma_m = 0.0;                         // per axis
  std::optional<double> range_m;                          // to the BS beacon (kBsBeaconId)
  Eigen::Vector2d truth_m = Eigen::Vector2d::Zero();      // true (x, y), BS frame
};

struct RoExport {
  int uav = 0;
  Eigen::Vector2d start_m = Eigen::Vector2d::Zero();  // [OdometryEstimation] (x, y), heading 0
  double range_sigma_m = 0.0;                         // the readings' stdError (the beacon's sigma)
  double beacon_ranges_std_m = 0.0;                   // the config's beaconRangesStd
  double epoch_period_s = 1.0;
  std::vector<RoFrame> frames;
};

// Throws common::InputError naming the value: a log not written by losmimo-record (no mission
// config), a UAV index outside 0 .. num_uavs - 1, a UAV that reported no epoch, or a reported
// epoch without its truth or filter belief.
RoExport build_ro_export(const MissionLog& log, int uav);

// The sensory-frame rawlog (gzip, as MRPT's CFileGZOutputStream writes). Throws
// std::runtime_error if it cannot be written.
void write_ro_rawlog(const RoExport& ro, const std::string& path);
// ro-localization's groundTruthFile (rows "j x y phi", full precision).
std::string ro_ground_truth_text(const RoExport& ro);

// ro-localization's config: the beacon map (beacons_ini_text of the BS_RANGES beacon, with
// beaconRangesStd), [ro-localization] rawlog_file, groundTruthFile, logOutput_dir (as given:
// names relative to the folder ro-localization runs in), random_seed = kRoRandomSeed, no 3-D
// scene files after the first, [OdometryEstimation] = the start, [PF_options] (standard proposal,
// kRoParticles, fixed sample size: the app has no adaptive one) and [RO_MODEL] with no bias jumps
// (losmimo's ranges have none). losmimo-replay --mrpt-config reads it too.
struct RoIniPaths {
  std::string rawlog, ground_truth, log_output_dir;
};
std::string ro_localization_ini_text(const RoExport& ro, const RoIniPaths& paths);

// Where losmimo-record writes UAV u's export beside LOG (run.rawlog, u = 3):
// run.uav03.ro.rawlog, run.uav03.ro.ini, run.uav03.ro_truth.txt; the config's logOutput_dir is
// run.uav03.ro_out (ro-localization appends "_Pc_<p>/REP_000").
struct RoExportPaths {
  std::string rawlog, ini, ground_truth, log_output_dir;
};
RoExportPaths ro_export_paths(const std::string& log_path, int uav);

}  // namespace losmimo::rawlog
