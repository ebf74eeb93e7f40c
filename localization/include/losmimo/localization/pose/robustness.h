#pragma once
// The range rules of pose/filter.h, shared by both pose filters: which readings of an epoch are
// fused, which are rejected and why, and when the filter re-initialises from a range fix. Pure
// functions of the predicted belief, so both filters apply the same rules to the same kind of
// belief (the particle filter passes its predicted moments), and each rule is tested on its own.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "losmimo/localization/filter_health.h"
#include "losmimo/localization/filter_config.h"
#include "losmimo/localization/filter_counters.h"
#include "losmimo/localization/pose/filter.h"
#include "losmimo/localization/pose/range_fix.h"
#include "losmimo/localization/pose/range_model.h"

namespace losmimo::localization {

// A reading that passed range_model.h's screen and the geometry check.
struct UsableRange {
  Eigen::Vector3d beacon_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d sensor_on_robot_m = Eigen::Vector3d::Zero();
  double range_m = 0.0;
  double sigma_m = 0.0;  // floored
};

enum class RangeEpochVerdict {
  kNone,   // no usable reading (no scan, or all rejected before the gate)
  kFuse,   // at least one reading passed the gate: `fuse` holds them
  kGated,  // every usable reading was gated
  kReset,  // gated for reset_after_rejections epochs: re-initialise from `reset_fix`
};

struct RangeUpdatePlan {
  RangeEpochVerdict verdict = RangeEpochVerdict::kNone;
  std::vector<UsableRange> fuse;
  RangeInnovations innovations;       // of the readings in `fuse`, against the prediction
  std::optional<RangeFix> reset_fix;  // of the sensor point, kReset only
  Eigen::Vector3d reset_sensor_on_robot_m = Eigen::Vector3d::Zero();
};

// Screens every reading of `scans` against the predicted belief (mean, cov) and applies the gate
// and reset rules of pose/filter.h, counting everything in `counters` (ranges_received, the
// rejections, ranges_fused for kFuse and kReset, resets). consecutive_gated_epochs is the
// filter's count of gated epochs in a row: kFuse clears it, kGated increments it, kNone leaves
// it. A reset whose fix fails (too few readings, several offsets, inconsistent) is a kGated epoch.
RangeUpdatePlan plan_range_update(const PoseFilterConfig& config, const BeaconMap& beacons,
                                  const std::vector<BeaconRangeScan>& scans, const Eigen::Vector4d& predicted_mean,
                                  const Eigen::Matrix4d& predicted_cov, int& consecutive_gated_epochs,
                                  FilterCounters& counters);

// The odometry noise a pose filter uses (pose/filter.h): the reading, or zero with the missing
// sigmas if it is not finite (counted), and Sigma_u + the floors on the diagonal.
OdometryIncrement screen_odometry(const PoseFilterConfig& config, const OdometryIncrement& odometry,
                                  FilterCounters& counters);

// Sets degraded and epochs_since_beacon from the position block (pose/filter.h's health rule).
void apply_health(const PoseFilterConfig& config, int epochs_since_beacon, PoseBelief& belief);

}  // namespace losmimo::localization
