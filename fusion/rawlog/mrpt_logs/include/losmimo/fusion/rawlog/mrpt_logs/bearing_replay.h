#pragma once
// Known-map localization on a bearing-range log (bearing_log.h) with a landmark pose filter
// (localization/pose/landmark_filter.h): what losmimo-replay does with MRPT's kf-slam logs given
// the landmark map. docs/bearing-range.md describes the model, the association and the outputs.
//
// Start: the map origin with a zero covariance, as stock kf-slam starts (MRPT's datasets start
// there: their robot path's row 0 is the origin). Frame 0 is a step with a zero increment that
// fuses its readings; frame k > 0 steps with its odometry, or without any (observation-format
// logs) with the no_odometry random walk (kf-slam's stdXY_no_odo, stdPhi_no_odo_deg) in x, y,
// yaw. The odometry's z sigma gets odometry_z_sigma_additional_m added (kf-slam's
// std_odo_z_additional).
// Landmark IDs the map does not hold: each is named once (ID and first frame) in `notes` and its
// readings are skipped; with `strict`, the first one is an error instead.
// Ground truth (MRPT's robot path, landmark_files.h): row k is frame k. Per frame with a row:
// e = |p - p_true| (3-D position), the heading error wrap(yaw - yaw_true), and the same position
// error for dead reckoning (the start composed with the odometry alone). Summary: RMSE over those
// frames (rmse_m; rmse_xy_m in the x-y plane), the heading RMSE, mean NIS of the fused readings
// (3 for a consistent filter: three components each).
// Refinement (options.refine, fusion/bearing_smoother.h): the batch smoother over the same frames,
// the filter's odometry noise and associations, seeded by the filter's track; the rows get the
// refined pose and, with truth, its error; the summary its RMSE beside the filter's.
// Errors (common::InputError): no CObservationBearingRange in the log, an empty map, no reading
// whose landmark ID is in the map (for a log with IDs), no reading fused at all, and with
// `strict` a landmark ID the map lacks.
// ignore_sensor_pose replaces every sensorLocationOnRobot by the robot origin: a negative
// control for the tests (the noncentered log then localizes clearly worse), no option.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/fusion/bearing_smoother.h"
#include "losmimo/localization/filter_config.h"
#include "losmimo/fusion/rawlog/mrpt_logs/bearing_log.h"

namespace losmimo::mrpt_logs {

struct BearingReplayOptions {
  localization::FilterKind estimator = localization::FilterKind::kEkf;
  localization::LandmarkFilterConfig config;                                      // `planar` is set from the log
  std::uint64_t seed = 1;                                                         // the particle filter's
  Eigen::Vector2d no_odometry_sigma = Eigen::Vector2d(0.1, 0.03490658503988659);  // (xy_m, yaw_rad) per frame
  double odometry_z_sigma_additional_m = 0.0;
  std::vector<localization::Pose6> ground_truth;  // robot path rows; empty: none
  bool strict = false;
  bool refine = false;
  bool ignore_sensor_pose = false;
};

struct BearingTrackRow {
  std::int64_t step = 0;
  double timestamp_s = 0.0;
  localization::LandmarkBelief belief;
  localization::Pose6 dead_reckoning = localization::Pose6::Zero();
  int readings = 0, fused = 0;
  double nis_sum = 0.0;
  bool has_truth = false;
  localization::Pose6 truth = localization::Pose6::Zero();
  double error_m = 0.0, error_xy_m = 0.0, yaw_error_rad = 0.0, dr_error_m = 0.0;
  std::optional<localization::Pose6> refined;
  double refined_error_m = 0.0;
};

struct BearingReplayResult {
  std::string estimator;  // "ekf" or "pf"
  bool planar = false;
  int particles = 0;  // pf only
  std::vector<BearingTrackRow> track;
  localization::LandmarkCounters counters;
  std::map<std::int32_t, std::pair<std::int64_t, std::int64_t>> unknown_ids;  // ID -> (first step, readings)
  std::vector<std::string> notes;
  std::int64_t truth_frames = 0;
  double rmse_m = 0.0, rmse_xy_m = 0.0, yaw_rmse_rad = 0.0, dr_rmse_m = 0.0, mean_nis = 0.0;  // nan without truth
  bool refined = false;
  fusion::BearingSmootherResult smoother;                // its track is in the rows' `refined`
  double refined_rmse_m = 0.0, refined_rmse_xy_m = 0.0;  // 3-D and horizontal position
  double refine_wall_s = 0.0;                            // process-dependent: not in the summary rows
};

BearingReplayResult replay_bearings(const BearingLog& log, const localization::BeaconMap& landmarks,
                                    const BearingReplayOptions& options);

// track.csv (one row per frame), the summary rows (key, value) and track.png (gnuplot; writes
// track.gp, ellipses.dat and landmarks.dat into `dir`; returns gnuplot's warnings).
void write_bearing_track_csv(const BearingReplayResult& result, const std::string& path);
std::vector<std::pair<std::string, std::string>> bearing_summary_rows(const BearingLog& log,
                                                                      const BearingReplayResult& result);
std::vector<std::string> write_bearing_plot(const BearingReplayResult& result, const localization::BeaconMap& landmarks,
                                            const std::string& dir);

}  // namespace losmimo::mrpt_logs
