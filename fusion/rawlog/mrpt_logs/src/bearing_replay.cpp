#include "losmimo/fusion/rawlog/mrpt_logs/bearing_replay.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <sstream>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/localization/range_az_el.h"
#include "losmimo/fusion/rawlog/mrpt_logs/range_log.h"

namespace losmimo::mrpt_logs {

namespace {

using namespace localization;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

double rms(double sum_sq, std::int64_t n) { return n ? std::sqrt(sum_sq / static_cast<double>(n)) : kNan; }

// The reason a log has nothing to fuse against `landmarks`, or empty.
std::string nothing_to_fuse(const BearingLog& log, const BeaconMap& landmarks) {
  if (log.bearing_observations == 0) {
    return "no CObservationBearingRange in the log (read: " + describe_counts(log.used) +
           "; skipped: " + describe_counts(log.skipped) + ")";
  }
  if (landmarks.empty()) return "no landmark map";
  if (log.readings_without_id > 0) return "";  // associated by nearest neighbour
  std::set<std::int32_t> ids;
  for (const BearingFrame& f : log.frames)
    for (const BearingScan& s : f.scans)
      for (const BearingReading& r : s.readings) {
        if (landmarks.find(r.landmark_id)) return "";
        ids.insert(r.landmark_id);
      }
  std::ostringstream s;
  s << "none of the log's " << ids.size() << " landmark IDs (first " << (ids.empty() ? -1 : *ids.begin())
    << ") is in the landmark map (" << landmarks.size() << " landmarks, first ID " << landmarks.beacons().begin()->first
    << ")";
  return s.str();
}

// Landmark IDs the map lacks: first step and count, one note each; throws with `strict`.
void check_ids(const BearingLog& log, const BeaconMap& landmarks, bool strict, BearingReplayResult& out) {
  for (const BearingFrame& f : log.frames)
    for (const BearingScan& s : f.scans)
      for (const BearingReading& r : s.readings) {
        if (r.landmark_id < 0 || landmarks.find(r.landmark_id)) continue;
        if (strict) {
          throw common::InputError("landmark ID " + std::to_string(r.landmark_id) + " (frame " +
                                   std::to_string(f.step) + ") is not in the landmark map (--strict)");
        }
        auto [it, fresh] = out.unknown_ids.try_emplace(r.landmark_id, f.step, 0);
        ++it->second.second;
      }
  for (const auto& [id, first_and_count] : out.unknown_ids) {
    out.notes.push_back("landmark ID " + std::to_string(id) + " (first at frame " +
                        std::to_string(first_and_count.first) + ") is not in the landmark map: its " +
                        std::to_string(first_and_count.second) + " reading(s) are skipped");
  }
}

OdometryIncrement6 frame_increment(const BearingFrame& frame, std::size_t k, const BearingReplayOptions& o) {
  OdometryIncrement6 u;
  if (k == 0) return u;
  if (frame.has_odometry) {
    u = frame.odometry;
    u.cov(kP6Z, kP6Z) += o.odometry_z_sigma_additional_m * o.odometry_z_sigma_additional_m;
    return u;
  }
  const double q = o.no_odometry_sigma(0) * o.no_odometry_sigma(0);
  u.cov(kP6X, kP6X) = u.cov(kP6Y, kP6Y) = q;
  u.cov(kP6Yaw, kP6Yaw) = o.no_odometry_sigma(1) * o.no_odometry_sigma(1);
  return u;
}

void score(BearingTrackRow& row, const Pose6& truth) {
  row.has_truth = true;
  row.truth = truth;
  row.error_m = (row.belief.mean.head<3>() - truth.head<3>()).norm();
  row.error_xy_m = (row.belief.mean.head<2>() - truth.head<2>()).norm();
  row.yaw_error_rad = wrap_angle_rad(row.belief.mean(kP6Yaw) - truth(kP6Yaw));
  row.dr_error_m = (row.dead_reckoning.head<3>() - truth.head<3>()).norm();
}

void summarize(BearingReplayResult& out) {
  double e2 = 0.0, exy2 = 0.0, yaw2 = 0.0, dr2 = 0.0;
  for (const BearingTrackRow& r : out.track) {
    if (!r.has_truth) continue;
    ++out.truth_frames;
    e2 += r.error_m * r.error_m;
    exy2 += r.error_xy_m * r.error_xy_m;
    yaw2 += r.yaw_error_rad * r.yaw_error_rad;
    dr2 += r.dr_error_m * r.dr_error_m;
  }
  out.rmse_m = rms(e2, out.truth_frames);
  out.rmse_xy_m = rms(exy2, out.truth_frames);
  out.yaw_rmse_rad = rms(yaw2, out.truth_frames);
  out.dr_rmse_m = rms(dr2, out.truth_frames);
  const LandmarkCounters& c = out.counters;
  out.mean_nis = c.fused ? c.nis_sum / static_cast<double>(c.fused) : kNan;
}

void refine(const LandmarkFilterConfig& config, const LandmarkBelief& start,
            const std::vector<fusion::BearingSmootherFrame>& frames, BearingReplayResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out.smoother = fusion::smooth_bearing_track(config, start, frames);
  out.refine_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.refined = true;
  double e2 = 0.0, e2_xy = 0.0;
  for (std::size_t k = 0; k < out.track.size(); ++k) {
    BearingTrackRow& row = out.track[k];
    row.refined = out.smoother.track[k];
    if (!row.has_truth) continue;
    row.refined_error_m = (row.refined->head<3>() - row.truth.head<3>()).norm();
    e2 += row.refined_error_m * row.refined_error_m;
    e2_xy += (row.refined->head<2>() - row.truth.head<2>()).squaredNorm();
  }
  out.smoother.track.clear();  // kept in the rows
  out.refined_rmse_m = rms(e2, out.truth_frames);
  out.refined_rmse_xy_m = rms(e2_xy, out.truth_frames);
}

}  // namespace

BearingReplayResult replay_bearings(const BearingLog& log, const BeaconMap& landmarks,
                                    const BearingReplayOptions& options) {
  if (const std::string why = nothing_to_fuse(log, landmarks); !why.empty()) throw common::InputError(why);
  BearingReplayResult out;
  check_ids(log, landmarks, options.strict, out);
  LandmarkFilterConfig config = options.config;
  config.planar = log.planar();
  out.planar = config.planar;
  out.estimator = to_string(options.estimator);
  out.particles = options.estimator == FilterKind::kParticle ? config.num_particles : 0;
  if (log.valid_covariance_observations > 0) {
    out.notes.push_back(std::to_string(log.valid_covariance_observations) +
                        " observation(s) carry per-reading covariances (validCovariances); the replay uses the "
                        "sensor_std_* fields or the configured noise instead");
  }
  LandmarkBelief start;
  start.cov.setZero();  // kf-slam's start: the map origin, exactly
  const std::unique_ptr<LandmarkPoseFilter> filter =
      make_landmark_filter(options.estimator, config, landmarks, start, options.seed);
  std::vector<fusion::BearingSmootherFrame> smoother_frames;
  Pose6 dr = start.mean;
  for (std::size_t k = 0; k < log.frames.size(); ++k) {
    const BearingFrame& frame = log.frames[k];
    std::vector<BearingScan> scans = frame.scans;
    if (options.ignore_sensor_pose)
      for (BearingScan& s : scans) s.sensor_on_robot.setZero();
    const OdometryIncrement6 u = frame_increment(frame, k, options);
    const std::int64_t fused_before = filter->counters().fused;
    const double nis_before = filter->counters().nis_sum;
    filter->step(u, scans);
    BearingTrackRow row;
    row.step = frame.step;
    row.timestamp_s = frame.timestamp_s;
    row.belief = filter->belief();
    for (const BearingScan& s : scans) row.readings += static_cast<int>(s.readings.size());
    row.fused = static_cast<int>(filter->counters().fused - fused_before);
    row.nis_sum = filter->counters().nis_sum - nis_before;
    if (k > 0 && frame.has_odometry) dr = compose_pose6(dr, frame.odometry.delta);
    row.dead_reckoning = dr;
    if (k < options.ground_truth.size()) score(row, options.ground_truth[k]);
    if (options.refine) {
      LandmarkCounters unused;  // the filter's association rule against its own estimate
      smoother_frames.push_back({u, associate(config, landmarks, scans, row.belief, unused), row.belief});
    }
    out.track.push_back(row);
  }
  out.counters = filter->counters();
  if (out.counters.fused == 0) {
    const LandmarkCounters& c = out.counters;
    throw common::InputError("no reading was fused: " + std::to_string(c.readings) + " received, unknown ID " +
                             std::to_string(c.unknown_id) + ", outside every gate " + std::to_string(c.gated) +
                             ", degenerate geometry " + std::to_string(c.degenerate));
  }
  summarize(out);
  if (options.refine) refine(config, start, smoother_frames, out);
  return out;
}

}  // namespace losmimo::mrpt_logs
