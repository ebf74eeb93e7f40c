#pragma once
// Range-only localization of a RangeLog (range_log.h) against a beacon map, with a pose filter
// (localization/pose_filter.h): what losmimo-replay does with MRPT's range-only logs.
//
// Frame 0: initial_pose(frame 0's scans, map, config, prior) (a range fix when the scans allow
// one, localization/initial_pose.h); the filter starts from it. If no fix was taken, frame 0's
// scans go to the filter's first step() with a zero increment.
// Frame k > 0: step(odometry_k, scans_k). A frame without odometry (observation-format logs
// with ranges only) predicts with a zero increment and no_odometry_sigma_m /
// no_odometry_sigma_yaw_rad per frame (a random walk, as pf-localization's DummyOdometryParams).
// Dead reckoning: the start mean composed with the odometry increments alone.
//
// Figures:
//   innovation RMS  sqrt(sum y_j^2 / n) over the fused readings, y_j against the prediction
//   mean NIS        mean of y_j^2 / S_j over the fused readings (1 for a consistent filter)
//   residual RMS    post-fit: r_j - h_j(updated mean) over the readings the filter fused
//                   (RangeInnovations::readings; the start fix's frame: every reading that
//                   passes the range screen), all frames, and from frame settle_steps on
//                   ("after convergence"). Gated outliers are not in it: they are counted in
//                   counters.rejected_range_gate.
// Ground truth (ro-localization's alignment, mrpt_app_config.h): row k of the relative rows
// belongs to the k-th frame that has odometry (the k-th (action, sensory frame) pair); the truth
// is origin (+) row (2-D). Per frame with truth: e = estimate - truth in (x, y), NEES
// e^T P_xy^-1 e (2 dof), and the same error for dead reckoning. Summary: RMSE over those frames,
// mean NEES (2 for a consistent filter), dead reckoning's RMSE.
// Refinement (options.refine, fusion/range_smoother.h): after the filter, a Ceres smoother over
// the same frames (the filter's odometry increments, including the no-odometry random walk, and
// its range readings and screen), seeded by the filter's track. Each row then also has the
// refined pose and covariance, its post-fit residuals over the same readings as the filter's
// (so the two residual RMS compare like with like), and with truth its error and NEES; the
// summary the same figures beside the filter's and dead reckoning's.
// Errors (common::InputError, the reason a user can act on): no CObservationBeaconRanges in the
// log, an empty map, ranges of several UAVs (labels "UAVnn_...", a losmimo log: the message
// names the rawlog-edit command that keeps one), no reading whose beacon ID is in the map, no
// range fused at all.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "losmimo/fusion/range_smoother.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/filter.h"
#include "losmimo/fusion/rawlog/mrpt_logs/range_log.h"

namespace losmimo::mrpt_logs {

struct RangeReplayOptions {
  localization::FilterKind estimator = localization::FilterKind::kEkf;
  localization::PoseFilterConfig config;
  // none: uniform over the beacons' bounding box (x, y; z within 1 m of it), any heading.
  std::optional<localization::PosePrior> prior;
  std::uint64_t seed = 1;  // the particle filter's
  int settle_steps = 10;
  double no_odometry_sigma_m = 0.1;
  double no_odometry_sigma_yaw_rad = 0.1;
  std::vector<Eigen::Vector3d> ground_truth;  // relative rows (x_m, y_m, phi_rad); empty: none
  Eigen::Vector3d ground_truth_origin = Eigen::Vector3d::Zero();
  std::optional<fusion::RangeSmootherConfig> refine;  // none: the filter only
};

struct RangeTrackRow {
  std::int64_t step = 0;
  double timestamp_s = 0.0;
  localization::PoseBelief belief;
  Eigen::Vector4d dead_reckoning = Eigen::Vector4d::Zero();
  int ranges = 0;  // readings in the frame
  localization::RangeInnovations innovations;
  double residual_sum_sq_m2 = 0.0;  // post-fit, fused readings
  int residuals = 0;
  bool has_truth = false;
  Eigen::Vector3d truth = Eigen::Vector3d::Zero();  // (x_m, y_m, phi_rad), map frame
  double error_m = 0.0, nees = 0.0, dr_error_m = 0.0;
  // With refinement: the smoother's pose, its post-fit residuals (the same readings as above),
  // and with truth its error and NEES.
  std::optional<localization::PoseBelief> refined;
  double refined_residual_sum_sq_m2 = 0.0;
  double refined_error_m = 0.0, refined_nees = 0.0;
};

struct RangeReplayResult {
  std::string estimator;  // "ekf" or "pf"
  std::string prior_description;
  std::vector<RangeTrackRow> track;
  localization::FilterCounters counters;  // frame 0's fix and the filter's, every reading once
  std::int64_t fused_in_fix = 0;
  double innovation_rms_m = 0.0, mean_nis = 0.0;
  double residual_rms_m = 0.0, residual_rms_settled_m = 0.0;
  std::int64_t residuals = 0, residuals_settled = 0;
  int settle_steps = 0;
  std::int64_t truth_frames = 0;
  double rmse_m = 0.0, mean_nees = 0.0, dr_rmse_m = 0.0;  // nan without truth
  // With refinement (else `refined` false and the figures unset):
  bool refined = false;
  std::string refine_mode;               // "batch" or "window <W>"
  fusion::RangeSmootherResult smoother;  // its track is in the rows' `refined`
  double refined_residual_rms_m = 0.0, refined_residual_rms_settled_m = 0.0;
  double refined_rmse_m = 0.0, refined_mean_nees = 0.0;  // nan without truth
  double refine_wall_s = 0.0;                            // process-dependent: not in the summary rows
};

RangeReplayResult replay_ranges(const RangeLog& log, const localization::BeaconMap& beacons,
                                const RangeReplayOptions& options);

// track.png through gnuplot (common/gnuplot.h): the estimate, dead reckoning, the truth, the
// beacons and 2-sigma ellipses every ~1/20 of the track; writes track.gp, ellipses.dat and
// beacons.dat (id,x,y,z) into `dir`. Returns the gnuplot warnings.
std::vector<std::string> write_range_plot(const RangeReplayResult& result, const localization::BeaconMap& beacons,
                                          const std::string& dir);

// ranges.csv: every reading of the log, "step,beacon_id,range_m,sensor_x_m,sensor_y_m,sensor_z_m,
// std_error_m" (to score another estimator's track on the same readings, scripts/compare-stock).
void write_range_readings_csv(const RangeLog& log, const std::string& path);

// track.csv (one row per frame) and the summary rows (key, value).
void write_range_track_csv(const RangeReplayResult& result, const std::string& path);
std::vector<std::pair<std::string, std::string>> range_summary_rows(const RangeLog& log,
                                                                    const RangeReplayResult& result);

}  // namespace losmimo::mrpt_logs
