#pragma once
// losmimo-replay: the sensor stream of a rawlog (log.h) through an estimator, offline,
// and the placement evaluation along the logged trajectory.
//
// Per UAV m, exactly as the closed loop consumed the data (closed_loop.cpp):
//   epoch 0: initial belief = beacon_fix(z_0) with the filter's noise, or the start-cube prior
//            (mean at the cube centre, 1-sigma cube_side_m / sqrt(12), degraded) without beacon;
//            filter = make_filter(kind, filter config, initial, logged filter seed);
//   epoch k: filter.step(d_k, z_k) (d_k missing -> NaN: the filter's missing-displacement rule);
//   refine:  fusion::SlidingWindowRefiner.add_epoch({filter belief, d_k, z_k, {csi_k}}), refine().
//   silent (ours, no record of the UAV at epoch k: an unresponsive UAV, or a run a fault stopped
//   part-way through the epoch): neither is stepped, the belief stays as it was, as in the loop.
// So replaying with the recorded estimator reproduces the logged beliefs bit for bit; another
// estimator is a co-evaluation on the same measurements.
// Evaluation, per epoch with every UAV's truth: the channel H at the true positions (ICN, and
// stream-1 SINR NV/ZF/MF, ZF sum rate, scenario's noise), the ICN at the estimated positions,
// and per UAV the error e = mean - truth (3-D, lateral = y and z), NEES e^T P^-1 e, and the
// swarm's split of those errors into its common lateral offset and its shape (swarm_shape.h),
// with the shape's NEES. A UAV-epoch
// is a fallback when the belief placement would use is degraded (and the config's fallback is on),
// unless the log says the UAV was not commanded in that iteration (mode '-'). An epoch without
// every UAV's truth (a silent UAV's is not logged) has no ICN or SINR (nan); mean_icn averages
// the others.
//
// Outputs (--out DIR): estimates.csv (epoch, uav, truth, estimate, sigmas, errors, NEES,
// degraded, beacon), epochs.csv (per-epoch metrics), summary.csv (key,value, RFC 4180 quoting;
// the rows that depend on the process, refined covariances' last bits, go to stdout only). A
// log of a run ended by a fault adds status, fault_uav and fault (END_OF_LOG) to summary.csv;
// stdout has the status of every complete log of ours.

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/localization/position/filter.h"

namespace losmimo::rawlog {

struct ReplayOptions {
  std::optional<localization::FilterKind> estimator;  // default: the recorded one (ekf if none)
  std::optional<bool> refine;                         // default: as recorded (false if none)
};

struct ReplayUavEpoch {
  int epoch = 0;
  int uav = 0;
  localization::Belief filter_belief;
  localization::Belief belief;  // what placement would use (refined, or the filter's)
  bool silent = false;          // ours: nothing arrived in this epoch; the belief is held from the last one
  bool has_beacon = false;
  bool has_truth = false;
  Eigen::Vector3d truth_m = Eigen::Vector3d::Zero();
  double error_m = 0.0, lateral_error_m = 0.0, nees = 0.0;  // of `belief` (0 without truth)
};

struct ReplayEpochMetrics {
  int epoch = 0;
  bool final_positions = false;  // the positions after the last iteration (no estimates)
  double icn = 0.0, icn_estimated = 0.0;
  double sinr_nv_db = 0.0, sinr_zf_db = 0.0, sinr_mf_db = 0.0, sum_rate_zf_bps_hz = 0.0;
  double rmse_m = 0.0, lateral_rmse_m = 0.0, mean_nees = 0.0;
  int fallback_uavs = 0, beacons = 0;
  int silent_uavs = 0;  // UAVs from which nothing arrived (their truth is not logged: ICN nan)
};

struct ReplayResult {
  std::string estimator;  // "ekf", "pf", "ekf+ceres", ...
  bool same_as_recorded = false;
  std::vector<ReplayUavEpoch> estimates;  // epoch-major
  std::vector<ReplayEpochMetrics> epochs;
  // Summary over every UAV-epoch with truth.
  double rmse_m = 0.0, lateral_rmse_m = 0.0, average_nees = 0.0;
  // The swarm-shape split (placement/swarm_shape.h) over the epochs with every UAV's truth: the
  // RMS common lateral offset, the shape residual's RMSE and its NEES per degree of freedom
  // (NaN without such an epoch).
  double common_lateral_rms_m = 0.0, shape_lateral_rmse_m = 0.0, shape_nees_per_dof = 0.0;
  double filter_rmse_m = 0.0;
  double final_icn = 0.0, final_sinr_zf_db = 0.0;
  double mean_icn = 0.0;  // over the epochs with every UAV's truth (nan if none)
  int fallback_uav_epochs = 0, fallback_epochs = 0;
  int silent_uav_epochs = 0;
  int num_beacons = 0, num_inexact_beacons = 0;
  // Against the logged beliefs (ours): how many were compared and how many equal bit for bit.
  int filter_beliefs_compared = 0, filter_beliefs_bitwise_equal = 0;
  // Refined beliefs: the means are reproduced bit for bit; the covariances to the last bits
  // only, because ceres::Covariance orders the parameter blocks by their heap addresses
  // (a different summation order in another process).
  int refined_beliefs_compared = 0, refined_beliefs_bitwise_equal = 0;
  int refined_means_bitwise_equal = 0;
  double refined_cov_max_rel_diff = 0.0;  // max |dP_ij| / max |P_ij|, upper triangle
};

// Throws common::InputError when the log holds nothing to replay (no UAV with an epoch).
ReplayResult replay_mission(const MissionLog& log, const ReplayOptions& options);

// estimates.csv, epochs.csv and summary.csv into `dir` (created if missing); throws
// std::runtime_error if a file cannot be written.
void write_replay_csv(const MissionLog& log, const ReplayResult& result, const std::string& dir);

// The summary as (key, value) rows. `stable`: only rows that do not depend on the process
// (summary.csv, compared with golden files); the refined covariances' last bits do.
std::vector<std::pair<std::string, std::string>> replay_summary_rows(const MissionLog& log, const ReplayResult& result,
                                                                     bool stable);

}  // namespace losmimo::rawlog
