#include "losmimo/fusion/rawlog/mrpt_logs/range_replay.h"

#include "losmimo/fusion/rawlog/io/labels.h"

#include <Eigen/Cholesky>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <tuple>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/localization/position/beacon_model.h"

namespace losmimo::mrpt_logs {

namespace {

using namespace localization;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;

PoseBox beacon_box(const BeaconMap& beacons) {
  PoseBox box;
  box.min = Eigen::Vector4d::Constant(std::numeric_limits<double>::infinity());
  box.max = -box.min;
  for (const auto& [id, p] : beacons.beacons()) {
    box.min.head<3>() = box.min.head<3>().cwiseMin(p);
    box.max.head<3>() = box.max.head<3>().cwiseMax(p);
  }
  box.min(kPoseZ) -= 1.0;
  box.max(kPoseZ) += 1.0;
  box.min(kPoseYaw) = -kPi;
  box.max(kPoseYaw) = kPi;
  return box;
}

std::string describe(const PosePrior& prior) {
  std::ostringstream s;
  if (const auto* box = std::get_if<PoseBox>(&prior)) {
    s << "uniform x [" << box->min(0) << ", " << box->max(0) << "] y [" << box->min(1) << ", " << box->max(1) << "] z ["
      << box->min(2) << ", " << box->max(2) << "] yaw [" << box->min(3) << ", " << box->max(3) << "] rad";
  } else {
    const auto& g = std::get<PoseBelief>(prior);
    s << "Gaussian mean (" << g.mean(0) << ", " << g.mean(1) << ", " << g.mean(2) << ", " << g.mean(3)
      << " rad) sigma (" << std::sqrt(g.cov(0, 0)) << ", " << std::sqrt(g.cov(1, 1)) << ", " << std::sqrt(g.cov(2, 2))
      << ", " << std::sqrt(g.cov(3, 3)) << " rad)";
  }
  return s.str();
}

// Post-fit residuals at `pose` of the readings the frame fused: those of the filter's update (or
// reset fix), or, for a frame that gave the start fix, every reading that passed the screen.
// Adds the squared residuals to sum_sq_m2 and returns their number.
int post_fit(const RangeFrame& frame, const BeaconMap& beacons, const PoseFilterConfig& config,
             const RangeInnovations& innovations, const Eigen::Vector4d& pose, bool start_fix, double& sum_sq_m2) {
  int n = 0;
  const auto add = [&](double range_m, const Eigen::Vector3d& sensor_m, const Eigen::Vector3d& beacon_m) {
    const double e = range_m - range_predict(pose, sensor_m, beacon_m);
    sum_sq_m2 += e * e;
    ++n;
  };
  if (!start_fix) {
    for (const FusedRange& r : innovations.readings) add(r.range_m, r.sensor_on_robot_m, r.beacon_m);
    return n;
  }
  for (const BeaconRangeScan& scan : frame.scans) {
    const double sigma = range_sigma_m(config, scan);
    for (const BeaconRange& r : scan.ranges) {
      if (screen_range(r, scan, beacons, sigma, config.filter.max_beacon_range_m) != RangeVerdict::kUsable) continue;
      add(r.range_m, r.sensor_on_robot_m, *beacons.find(r.beacon_id));
    }
  }
  return n;
}

// e = estimate - truth in (x, y) and its NEES against the estimate's x-y covariance.
std::pair<double, double> error_and_nees(const PoseBelief& belief, const Eigen::Vector3d& truth) {
  const Eigen::Vector2d e = belief.mean.head<2>() - truth.head<2>();
  return {e.norm(), e.dot(belief.cov.topLeftCorner<2, 2>().ldlt().solve(e))};
}

double rms(double sum_sq, std::int64_t n) { return n ? std::sqrt(sum_sq / static_cast<double>(n)) : kNan; }

// The smoother over the filter's frames (header: Refinement); fills the rows' refined fields.
void refine(const RangeLog& log, const BeaconMap& beacons, const RangeReplayOptions& options, bool start_fix,
            std::vector<fusion::SmootherFrame> frames, RangeReplayResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out.smoother = fusion::smooth_range_track(options.config, beacons, frames, *options.refine);
  out.refine_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.refined = true;
  const int w = options.refine->window_frames;
  out.refine_mode = w == 0 ? "batch" : "window " + std::to_string(w);
  double res_sq = 0.0, res_sq_settled = 0.0, err_sq = 0.0, nees = 0.0;
  for (std::size_t k = 0; k < out.track.size(); ++k) {
    RangeTrackRow& row = out.track[k];
    row.refined = out.smoother.track[k];
    post_fit(log.frames[k], beacons, options.config, row.innovations, row.refined->mean, k == 0 && start_fix,
             row.refined_residual_sum_sq_m2);
    res_sq += row.refined_residual_sum_sq_m2;
    if (row.step >= options.settle_steps) res_sq_settled += row.refined_residual_sum_sq_m2;
    if (row.has_truth) {
      std::tie(row.refined_error_m, row.refined_nees) = error_and_nees(*row.refined, row.truth);
      err_sq += row.refined_error_m * row.refined_error_m;
      nees += row.refined_nees;
    }
  }
  out.smoother.track.clear();  // kept in the rows
  out.refined_residual_rms_m = rms(res_sq, out.residuals);
  out.refined_residual_rms_settled_m = rms(res_sq_settled, out.residuals_settled);
  out.refined_rmse_m = rms(err_sq, out.truth_frames);
  out.refined_mean_nees = out.truth_frames ? nees / static_cast<double>(out.truth_frames) : kNan;
}

// The reason a log has nothing to fuse, or empty.
std::string nothing_to_fuse(const RangeLog& log, const BeaconMap& beacons) {
  if (log.beacon_observations == 0) {
    return "no CObservationBeaconRanges in the log (read: " + describe_counts(log.used) +
           "; skipped: " + describe_counts(log.skipped) + ")";
  }
  if (beacons.empty()) return "no beacon map";
  if (log.beacon_uavs.size() > 1) {
    // One track per log: several vehicles' ranges would be fused as one's. The labels are the
    // two streams losmimo-record writes for stock apps (rawlog/format.h: ODOMETRY, BS_RANGES).
    const int first = *log.beacon_uavs.begin();
    return "the log holds the CObservationBeaconRanges of " + std::to_string(log.beacon_uavs.size()) +
           " UAVs (UAVnn_ labels); keep one, e.g. rawlog-edit -i LOG -o ONE.rawlog --keep-label " +
           rawlog_io::uav_label(first, "ODOMETRY") + "," + rawlog_io::uav_label(first, "BS_RANGES");
  }
  std::set<std::int32_t> ids;
  for (const RangeFrame& f : log.frames)
    for (const BeaconRangeScan& s : f.scans)
      for (const BeaconRange& r : s.ranges) ids.insert(r.beacon_id);
  for (const std::int32_t id : ids)
    if (beacons.find(id)) return "";
  std::ostringstream s;
  s << "none of the log's beacon IDs (";
  int n = 0;
  for (const std::int32_t id : ids) {
    if (n++ == 10) {
      s << ", ...";
      break;
    }
    s << (n > 1 ? ", " : "") << id;
  }
  s << ") is in the beacon map (IDs ";
  n = 0;
  for (const auto& [id, p] : beacons.beacons()) {
    if (n++ == 10) {
      s << ", ...";
      break;
    }
    s << (n > 1 ? ", " : "") << id;
  }
  s << ")";
  return s.str();
}

// The frame's odometry for the filter: its own, or (after frame 0) the no-odometry random walk.
OdometryIncrement frame_increment(const RangeFrame& frame, std::size_t k, const RangeReplayOptions& options) {
  OdometryIncrement u;
  if (k > 0 && frame.has_odometry) {
    u = frame.odometry;
  } else if (k > 0) {
    const double q = options.no_odometry_sigma_m * options.no_odometry_sigma_m;
    u.cov.diagonal() << q, q, q, options.no_odometry_sigma_yaw_rad * options.no_odometry_sigma_yaw_rad;
  }
  return u;
}

// Ground-truth row `pair` in the map frame: origin (+) row (2-D), as ro-localization aligns it.
Eigen::Vector3d truth_of_pair(const RangeReplayOptions& options, std::size_t pair) {
  const Eigen::Vector3d& rel = options.ground_truth[pair];
  const Eigen::Vector3d& o = options.ground_truth_origin;
  const double c = std::cos(o(2)), sn = std::sin(o(2));
  return Eigen::Vector3d(o(0) + c * rel(0) - sn * rel(1), o(1) + sn * rel(0) + c * rel(1),
                         wrap_angle_rad(o(2) + rel(2)));
}

// Every frame through the filter (frame 0 already in it when it gave the start fix): one track
// row each, with dead reckoning, truth and post-fit residuals; with refinement, the frames the
// smoother will be given.
void run_filter(const RangeLog& log, const BeaconMap& beacons, const RangeReplayOptions& options,
                const InitialPose& start, PoseFilter& filter, RangeReplayResult& out,
                std::vector<fusion::SmootherFrame>& smoother_frames) {
  Eigen::Vector4d dr = moments(start).mean;
  std::size_t pair = 0;  // (action, sensory frame) pairs so far: the ground-truth row index
  for (std::size_t k = 0; k < log.frames.size(); ++k) {
    const RangeFrame& frame = log.frames[k];
    RangeTrackRow row;
    row.step = frame.step;
    row.timestamp_s = frame.timestamp_s;
    for (const BeaconRangeScan& s : frame.scans) row.ranges += static_cast<int>(s.ranges.size());
    if (k == 0 && start.fix) {
      row.belief = filter.belief();
      if (options.refine) smoother_frames.push_back({{}, frame.scans, {}});
    } else {
      const OdometryIncrement u = frame_increment(frame, k, options);
      filter.step(u, frame.scans);
      if (options.refine) smoother_frames.push_back({u, frame.scans, {}});
      row.belief = filter.belief();
      row.innovations = filter.last_innovations();
      if (k > 0 && frame.has_odometry) dr = compose(dr, frame.odometry.delta);
    }
    row.dead_reckoning = dr;
    if (frame.has_odometry && pair < options.ground_truth.size()) {
      row.has_truth = true;
      row.truth = truth_of_pair(options, pair);
      std::tie(row.error_m, row.nees) = error_and_nees(row.belief, row.truth);
      row.dr_error_m = (dr.head<2>() - row.truth.head<2>()).norm();
    }
    if (frame.has_odometry) ++pair;
    row.residuals = post_fit(frame, beacons, options.config, row.innovations, row.belief.mean,
                             k == 0 && start.fix.has_value(), row.residual_sum_sq_m2);
    if (options.refine) smoother_frames.back().filter_belief = row.belief;
    out.track.push_back(row);
  }
}

std::string no_range_fused(const FilterCounters& c) {
  return "no range was fused: " + std::to_string(c.ranges_received) + " received, rejected: unknown beacon " +
         std::to_string(c.rejected_unknown_beacon) + ", outside sensor limits " +
         std::to_string(c.rejected_outside_sensor_limits) + ", non-finite " +
         std::to_string(c.rejected_non_finite_range) + ", implausible " + std::to_string(c.rejected_implausible_range) +
         ", gate " + std::to_string(c.rejected_range_gate);
}

// The summary figures over the track (innovations, residuals, errors against the truth).
// Throws common::InputError when no range was fused.
void summarize_track(const RangeReplayOptions& options, RangeReplayResult& out) {
  double innov_sq = 0.0, nis = 0.0, res_sq = 0.0, res_sq_settled = 0.0, err_sq = 0.0, nees = 0.0, dr_sq = 0.0;
  std::int64_t innov_n = 0;
  for (const RangeTrackRow& r : out.track) {
    innov_sq += r.innovations.sum_sq_m2;
    nis += r.innovations.nis_sum;
    innov_n += r.innovations.fused;
    res_sq += r.residual_sum_sq_m2;
    out.residuals += r.residuals;
    if (r.has_truth) {
      ++out.truth_frames;
      err_sq += r.error_m * r.error_m;
      nees += r.nees;
      dr_sq += r.dr_error_m * r.dr_error_m;
    }
    if (r.step >= options.settle_steps) {
      res_sq_settled += r.residual_sum_sq_m2;
      out.residuals_settled += r.residuals;
    }
  }
  if (out.counters.ranges_fused == 0) throw common::InputError(no_range_fused(out.counters));
  out.innovation_rms_m = innov_n ? std::sqrt(innov_sq / static_cast<double>(innov_n)) : kNan;
  out.mean_nis = innov_n ? nis / static_cast<double>(innov_n) : kNan;
  out.residual_rms_m = out.residuals ? std::sqrt(res_sq / static_cast<double>(out.residuals)) : kNan;
  out.residual_rms_settled_m =
      out.residuals_settled ? std::sqrt(res_sq_settled / static_cast<double>(out.residuals_settled)) : kNan;
  const double nt = static_cast<double>(out.truth_frames);
  out.rmse_m = out.truth_frames ? std::sqrt(err_sq / nt) : kNan;
  out.mean_nees = out.truth_frames ? nees / nt : kNan;
  out.dr_rmse_m = out.truth_frames ? std::sqrt(dr_sq / nt) : kNan;
}

}  // namespace

RangeReplayResult replay_ranges(const RangeLog& log, const BeaconMap& beacons, const RangeReplayOptions& options) {
  if (const std::string why = nothing_to_fuse(log, beacons); !why.empty()) throw common::InputError(why);
  validate(options.config);
  if (options.refine) fusion::validate(*options.refine);
  RangeReplayResult out;
  out.estimator = to_string(options.estimator);
  out.settle_steps = options.settle_steps;
  const PosePrior prior = options.prior ? *options.prior : PosePrior(beacon_box(beacons));
  out.prior_description = describe(prior);

  const InitialPose start = initial_pose(log.frames.front().scans, beacons, options.config, prior);
  // Without a fix, frame 0's readings are counted by the filter's first step() instead.
  if (start.fix) {
    out.counters += start.counters;
    out.fused_in_fix = start.counters.ranges_fused;
  }
  const std::unique_ptr<PoseFilter> filter =
      make_pose_filter(options.estimator, options.config, beacons, start, options.seed);
  std::vector<fusion::SmootherFrame> smoother_frames;  // what the filter was given, for refine()
  run_filter(log, beacons, options, start, *filter, out, smoother_frames);
  out.counters += filter->counters();
  summarize_track(options, out);
  if (options.refine) refine(log, beacons, options, start.fix.has_value(), std::move(smoother_frames), out);
  return out;
}

void write_range_readings_csv(const RangeLog& log, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  f << "step,beacon_id,range_m,sensor_x_m,sensor_y_m,sensor_z_m,std_error_m\n";
  for (const RangeFrame& fr : log.frames)
    for (const BeaconRangeScan& s : fr.scans)
      for (const BeaconRange& r : s.ranges) {
        f << fr.step << "," << r.beacon_id << "," << common::format_csv(r.range_m) << ","
          << common::format_csv(r.sensor_on_robot_m.x()) << "," << common::format_csv(r.sensor_on_robot_m.y()) << ","
          << common::format_csv(r.sensor_on_robot_m.z()) << "," << common::format_csv(s.std_error_m) << "\n";
      }
  if (!f) throw std::runtime_error(path + ": write failed");
}

void write_range_track_csv(const RangeReplayResult& result, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot write");
  f << "step,timestamp_s,x_m,y_m,z_m,heading_rad,var_x_m2,var_y_m2,var_z_m2,var_heading_rad2,ranges,fused,"
       "innovation_rms_m,nis,residual_rms_m,dr_x_m,dr_y_m,dr_z_m,dr_heading_rad,gt_x_m,gt_y_m,gt_heading_rad,error_m,"
       "nees,dr_error_m";
  if (result.refined) {
    f << ",refined_x_m,refined_y_m,refined_z_m,refined_heading_rad,refined_var_x_m2,refined_var_y_m2,refined_var_z_m2,"
         "refined_var_heading_rad2,refined_residual_rms_m,refined_error_m,refined_nees";
  }
  f << "\n";
  for (const RangeTrackRow& r : result.track) {
    const auto& m = r.belief.mean;
    const auto& P = r.belief.cov;
    const int n = r.innovations.fused;
    f << r.step << "," << common::format_g(r.timestamp_s, common::kExactDigits) << "," << common::format_csv(m(0))
      << "," << common::format_csv(m(1)) << "," << common::format_csv(m(2)) << "," << common::format_csv(m(3)) << ","
      << common::format_csv(P(0, 0)) << "," << common::format_csv(P(1, 1)) << "," << common::format_csv(P(2, 2)) << ","
      << common::format_csv(P(3, 3)) << "," << r.ranges << "," << n << ","
      << (n ? common::format_csv(std::sqrt(r.innovations.sum_sq_m2 / n)) : "nan") << ","
      << (n ? common::format_csv(r.innovations.nis_sum / n) : "nan") << ","
      << (r.residuals ? common::format_csv(std::sqrt(r.residual_sum_sq_m2 / r.residuals)) : "nan") << ","
      << common::format_csv(r.dead_reckoning(0)) << "," << common::format_csv(r.dead_reckoning(1)) << ","
      << common::format_csv(r.dead_reckoning(2)) << "," << common::format_csv(r.dead_reckoning(3));
    if (r.has_truth) {
      f << "," << common::format_csv(r.truth(0)) << "," << common::format_csv(r.truth(1)) << ","
        << common::format_csv(r.truth(2)) << "," << common::format_csv(r.error_m) << "," << common::format_csv(r.nees)
        << "," << common::format_csv(r.dr_error_m);
    } else {
      f << ",nan,nan,nan,nan,nan,nan";
    }
    if (r.refined) {
      const auto& rm = r.refined->mean;
      const auto& rP = r.refined->cov;
      f << "," << common::format_csv(rm(0)) << "," << common::format_csv(rm(1)) << "," << common::format_csv(rm(2))
        << "," << common::format_csv(rm(3)) << "," << common::format_csv(rP(0, 0)) << ","
        << common::format_csv(rP(1, 1)) << "," << common::format_csv(rP(2, 2)) << "," << common::format_csv(rP(3, 3))
        << "," << (r.residuals ? common::format_csv(std::sqrt(r.refined_residual_sum_sq_m2 / r.residuals)) : "nan")
        << "," << (r.has_truth ? common::format_csv(r.refined_error_m) : "nan") << ","
        << (r.has_truth ? common::format_csv(r.refined_nees) : "nan");
    }
    f << "\n";
  }
  if (!f) throw std::runtime_error(path + ": write failed");
}

std::vector<std::pair<std::string, std::string>> range_summary_rows(const RangeLog& log, const RangeReplayResult& r) {
  const FilterCounters& c = r.counters;
  const auto i = [](std::int64_t v) { return std::to_string(v); };
  std::vector<std::pair<std::string, std::string>> rows = {
      {"mode", "range_only"},
      {"estimator", r.estimator},
      {"prior", r.prior_description},
      {"frames", i(static_cast<std::int64_t>(r.track.size()))},
      {"beacon_observations", i(log.beacon_observations)},
      {"ranges_received", i(c.ranges_received)},
      {"ranges_fused", i(c.ranges_fused)},
      {"ranges_fused_in_start_fix", i(r.fused_in_fix)},
      {"skipped_unknown_beacon", i(c.rejected_unknown_beacon)},
      {"skipped_outside_sensor_limits", i(c.rejected_outside_sensor_limits)},
      {"skipped_non_finite_range", i(c.rejected_non_finite_range)},
      {"skipped_implausible_range", i(c.rejected_implausible_range)},
      {"skipped_geometry", i(c.rejected_range_geometry)},
      {"skipped_gate", i(c.rejected_range_gate)},
      {"resets", i(c.resets)},
      {"innovation_rms_m", common::format_csv(r.innovation_rms_m)},
      {"mean_nis", common::format_csv(r.mean_nis)},
      {"residual_readings", i(r.residuals)},
      {"residual_rms_m", common::format_csv(r.residual_rms_m)},
      {"settle_steps", std::to_string(r.settle_steps)},
      {"residual_rms_settled_m", common::format_csv(r.residual_rms_settled_m)},
      {"residual_readings_settled", i(r.residuals_settled)},
      {"ground_truth_frames", i(r.truth_frames)},
      {"rmse_xy_m", common::format_csv(r.rmse_m)},
      {"mean_nees_xy", common::format_csv(r.mean_nees)},
      {"dead_reckoning_rmse_xy_m", common::format_csv(r.dr_rmse_m)},
  };
  if (r.refined) {
    const fusion::RangeSmootherResult& sm = r.smoother;
    rows.insert(rows.end(),
                {
                    {"refinement", r.refine_mode},
                    {"refined_residual_rms_m", common::format_csv(r.refined_residual_rms_m)},
                    {"refined_residual_rms_settled_m", common::format_csv(r.refined_residual_rms_settled_m)},
                    {"refined_rmse_xy_m", common::format_csv(r.refined_rmse_m)},
                    {"refined_mean_nees_xy", common::format_csv(r.refined_mean_nees)},
                    {"refined_ranges_used", i(sm.ranges_used)},
                    {"refined_ranges_down_weighted", i(sm.ranges_down_weighted)},
                    {"refined_problems", std::to_string(sm.problems)},
                    {"refined_not_converged", std::to_string(sm.not_converged)},
                    {"refined_iterations", i(sm.iterations)},
                    {"refined_covariance_fallbacks", std::to_string(sm.covariance_fallbacks)},
                });
  }
  rows.push_back({"other_classes_skipped", describe_counts(log.skipped)});
  rows.push_back({"trailing_actions", i(log.trailing_actions)});
  if (!r.track.empty()) {
    const auto& m = r.track.back().belief.mean;
    const auto& d = r.track.back().dead_reckoning;
    rows.push_back({"final_x_m", common::format_csv(m(0))});
    rows.push_back({"final_y_m", common::format_csv(m(1))});
    rows.push_back({"final_heading_rad", common::format_csv(m(3))});
    rows.push_back({"final_dr_x_m", common::format_csv(d(0))});
    rows.push_back({"final_dr_y_m", common::format_csv(d(1))});
    rows.push_back({"final_dr_heading_rad", common::format_csv(d(3))});
    if (const auto& f = r.track.back().refined) {
      rows.push_back({"final_refined_x_m", common::format_csv(f->mean(0))});
      rows.push_back({"final_refined_y_m", common::format_csv(f->mean(1))});
      rows.push_back({"final_refined_heading_rad", common::format_csv(f->mean(3))});
    }
  }
  return rows;
}

}  // namespace losmimo::mrpt_logs
