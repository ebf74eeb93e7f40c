#include "losmimo/localization/pose/robustness.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "losmimo/localization/position/robustness.h"

namespace losmimo::localization {

RangeUpdatePlan plan_range_update(const PoseFilterConfig& config, const BeaconMap& beacons,
                                  const std::vector<BeaconRangeScan>& scans, const Eigen::Vector4d& predicted_mean,
                                  const Eigen::Matrix4d& predicted_cov, int& consecutive_gated_epochs,
                                  FilterCounters& counters) {
  RangeUpdatePlan plan;
  std::vector<UsableRange> gated;
  for (const BeaconRangeScan& scan : scans) {
    const double sigma_m = range_sigma_m(config, scan);
    for (const BeaconRange& r : scan.ranges) {
      ++counters.ranges_received;
      const RangeVerdict verdict = screen_range(r, scan, beacons, sigma_m, config.filter.max_beacon_range_m);
      if (verdict != RangeVerdict::kUsable) {
        count_rejection(verdict, counters);
        continue;
      }
      const UsableRange u{*beacons.find(r.beacon_id), r.sensor_on_robot_m, r.range_m, sigma_m};
      if (!(range_predict(predicted_mean, u.sensor_on_robot_m, u.beacon_m) >= kMinRangeGeometry_m)) {
        ++counters.rejected_range_geometry;
        continue;
      }
      const Eigen::RowVector4d H = range_jacobian(predicted_mean, u.sensor_on_robot_m, u.beacon_m);
      const double S = H.dot(predicted_cov * H.transpose()) + u.sigma_m * u.sigma_m;
      const double y = u.range_m - range_predict(predicted_mean, u.sensor_on_robot_m, u.beacon_m);
      if (config.filter.gate_enabled && !(y * y <= config.range_gate_chi2 * S)) {
        gated.push_back(u);
        continue;
      }
      plan.fuse.push_back(u);
      plan.innovations.readings.push_back({u.beacon_m, u.sensor_on_robot_m, u.range_m});
      ++plan.innovations.fused;
      plan.innovations.sum_sq_m2 += y * y;
      plan.innovations.nis_sum += y * y / S;
    }
  }
  const auto count_gated = [&] { counters.rejected_range_gate += static_cast<std::int64_t>(gated.size()); };
  if (!plan.fuse.empty()) {
    plan.verdict = RangeEpochVerdict::kFuse;
    counters.ranges_fused += static_cast<std::int64_t>(plan.fuse.size());
    count_gated();
    consecutive_gated_epochs = 0;
    return plan;
  }
  if (gated.empty()) return plan;  // kNone
  const int reset_after = config.filter.reset_after_rejections;
  if (reset_after > 0 && consecutive_gated_epochs >= reset_after &&
      static_cast<int>(gated.size()) >= config.min_ranges_for_fix &&
      std::all_of(gated.begin(), gated.end(),
                  [&](const UsableRange& u) { return u.sensor_on_robot_m == gated.front().sensor_on_robot_m; })) {
    // The belief lost track: a fix from this epoch's readings, with the prediction (widened by
    // missing_displacement_sigma_m) as its prior.
    std::vector<RangeReading> readings;
    for (const UsableRange& u : gated) readings.push_back({u.beacon_m, u.range_m, u.sigma_m});
    const Eigen::Vector3d s = gated.front().sensor_on_robot_m;
    const double widen = config.filter.missing_displacement_sigma_m;
    const RangeFixResult result =
        range_fix(readings, sensor_position_m(predicted_mean, s),
                  predicted_cov.topLeftCorner<3, 3>() + widen * widen * Eigen::Matrix3d::Identity());
    if (result.fix) {
      plan.verdict = RangeEpochVerdict::kReset;
      plan.reset_fix = result.fix;
      plan.reset_sensor_on_robot_m = s;
      consecutive_gated_epochs = 0;
      ++counters.resets;
      counters.ranges_fused += static_cast<std::int64_t>(gated.size());
      for (const UsableRange& u : gated)
        plan.innovations.readings.push_back({u.beacon_m, u.sensor_on_robot_m, u.range_m});
      return plan;
    }
  }
  plan.verdict = RangeEpochVerdict::kGated;
  ++consecutive_gated_epochs;
  count_gated();
  return plan;
}

OdometryIncrement screen_odometry(const PoseFilterConfig& config, const OdometryIncrement& odometry,
                                  FilterCounters& counters) {
  const double f_m = config.filter.min_sigma_displacement_m;
  const double f_yaw = config.min_sigma_yaw_rad;
  const Eigen::Vector4d floor(f_m * f_m, f_m * f_m, f_m * f_m, f_yaw * f_yaw);
  OdometryIncrement u = odometry;
  u.cov = 0.5 * (u.cov + u.cov.transpose()).eval();
  u.cov.diagonal() += floor;
  // Not finite, or a covariance that is not positive semi-definite: no usable reading.
  if (!u.delta.allFinite() || !u.cov.allFinite() || u.cov.llt().info() != Eigen::Success) {
    ++counters.rejected_non_finite_displacement;
    const double s_m = config.filter.missing_displacement_sigma_m;
    const double s_yaw = config.missing_yaw_sigma_rad;
    u.delta.setZero();
    u.cov = Eigen::Vector4d(s_m * s_m, s_m * s_m, s_m * s_m, s_yaw * s_yaw).asDiagonal();
    u.cov.diagonal() += floor;
  }
  return u;
}

void apply_health(const PoseFilterConfig& config, int epochs_since_beacon, PoseBelief& belief) {
  belief.epochs_since_beacon = epochs_since_beacon;
  belief.degraded = is_degraded(config.filter, epochs_since_beacon, belief.cov.topLeftCorner<3, 3>());
}

}  // namespace losmimo::localization
