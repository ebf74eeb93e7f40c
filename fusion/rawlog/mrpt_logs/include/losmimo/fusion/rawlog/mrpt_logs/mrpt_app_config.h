#pragma once
// The range-only settings of a stock MRPT app configuration (ro-localization's or
// pf-localization's APP.ini), read from the same sections and keys those apps read, through
// mrpt::config::CConfigFile (section and key names case-insensitive, "// ..." tails stripped):
//   [MetricMap_landmarksMap_00_creationOpts]  nBeacons, beacon_NNN_ID / _X / _Y / _Z, NNN = 001..
//   [MetricMap_landmarksMap_00_likelihoodOpts] beaconRangesStd [m],
//                                              beaconRangesUseObservationStd (0 / 1)
//   [OdometryEstimation] odometry_X, odometry_Y [m], odometry_PHI [deg] (ro-localization): the
//       start pose in the map frame, the ground truth's origin, and the prior ro-localization
//       uses: uniform x +- 0.5 m, y +- 0.5 m, any heading
//   [LocalizationExperiment] init_PDF_mode = 1 with init_PDF_min/max_x, _y [m] and optional
//       init_PDF_min/max_yaw_deg (pf-localization): a uniform box (any heading without the yaw
//       keys); it wins over [OdometryEstimation]'s box when both are present
//   [PF_options] sampleSize: the particle count
//   [ro-localization] groundTruthFile, rawlog_file: resolved against the config's folder (the
//       stock configs name ../../datasets/..., relative to where they are installed)
// Every other key is listed once in `unused_keys` ("[section] key"), not an error.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/range_model.h"

namespace losmimo::mrpt_logs {

struct MrptAppConfig {
  localization::BeaconMap beacons;  // empty without nBeacons
  std::optional<localization::PosePrior> prior;
  std::optional<double> range_sigma_m;
  std::optional<bool> use_observation_std;
  std::optional<int> particles;
  std::optional<Eigen::Vector3d> start_pose;  // (x_m, y_m, phi_rad), [OdometryEstimation]
  std::string ground_truth_file, rawlog_file;
  std::vector<std::string> unused_keys;
};

// Throws common::InputError naming "<path>: [section] key" and the value for a bad or missing
// value (a beacon's coordinate, a non-numeric nBeacons, ...), or for a file that does not exist.
MrptAppConfig read_mrpt_app_config(const std::string& path);

// `beacons` as the beacon-map sections stock ro-localization and pf-localization read:
// [MetricMap] landmarksMap_count = 1; [MetricMap_landmarksMap_00_creationOpts] nBeacons,
// beacon_NNN_ID / _X / _Y / _Z in ID order, positions in metres with 17 significant digits (so
// read_mrpt_app_config gives back the same map); [..._insertOpts]
// insert_Landmarks_from_range_scans = 0; with a range sigma, [..._likelihoodOpts]
// beaconRangesStd. Throws common::InputError for an empty map (the stock apps would localize
// against nothing) or a sigma that is not > 0.
std::string beacons_ini_text(const localization::BeaconMap& beacons,
                             std::optional<double> range_sigma_m = std::nullopt);
// Writes beacons_ini_text to `path` (std::runtime_error if it cannot be written).
void write_beacons_ini(const localization::BeaconMap& beacons, const std::string& path,
                       std::optional<double> range_sigma_m = std::nullopt);

// The settings of a stock kf-slam configuration (config_files/kf-slam/EKF-SLAM_*.ini) that the
// bearing-range replay acts on (bearing_replay.h), read the same way:
//   [MappingApplication] rawlog_file, ground_truth_file (the landmarks: MRPT's ground-truth
//       landmark file, landmark_files.h), ground_truth_file_robot (the robot path), resolved
//       against the config's folder
//   [RangeBearingKFSLAM] std_sensor_range [m], std_sensor_yaw_deg, std_sensor_pitch_deg [deg]
//       (the reading noise; a key left out takes the replay's default: 0.01 m, 0.1 deg),
//       std_odo_z_additional [m] (added to the odometry's z sigma), stdXY_no_odo [m],
//       stdPhi_no_odo_deg (the random walk of a frame without odometry)
// Every other key is listed in `unused_keys`.
struct KfSlamConfig {
  std::string rawlog_file, landmarks_file, robot_path_file;
  std::optional<Eigen::Vector3d> sensor_sigma;  // (range_m, yaw_rad, pitch_rad)
  double odometry_z_sigma_additional_m = 0.0;
  std::optional<Eigen::Vector2d> no_odometry_sigma;  // (xy_m, phi_rad)
  std::vector<std::string> unused_keys;
};

// Whether `path` is a kf-slam configuration (it has [RangeBearingKFSLAM] or [MappingApplication]).
bool is_kf_slam_config(const std::string& path);
// Throws common::InputError naming "<path>: [section] key" and the value for a bad value, or for
// a file that does not exist.
KfSlamConfig read_kf_slam_config(const std::string& path);

// ro-localization's groundTruthFile: rows "k x y phi" (column 0 ignored; x, y [m] and phi [rad]
// relative to the start pose); row k belongs to the k-th (action, sensory frame) pair.
// Throws common::InputError naming the line and column.
std::vector<Eigen::Vector3d> read_relative_ground_truth(const std::string& path);

}  // namespace losmimo::mrpt_logs
