#pragma once
// A range-only rawlog (MRPT's RO-SLAM / ro-localization logs, or any log with
// CObservationBeaconRanges) read into frames for the pose filters (localization/pose_filter.h).
//
// Frames:
//  - sensory-frame format (CActionCollection, CSensoryFrame, ...): one frame per CSensoryFrame,
//    `step` = its 0-based index among the log's sensory frames. Its odometry is every action
//    since the previous sensory frame, composed in order (robot frame, odometry_model.h):
//      CActionRobotMovement2D  poseChange's mean (x, y, phi) and 3x3 covariance (MRPT rebuilds
//                              poseChange from the raw increment and the motion model on load)
//      CActionRobotMovement3D  poseChange.mean's (x, y, z, yaw) and the x-y-z-yaw block of cov
//    u = u1 (+) u2, Sigma = J_x'_x Sigma_1 J_x'_x^T + J_x'_u Sigma_2 J_x'_u^T (exact for the
//    linear-in-u composition about the means). A sensory frame with no action before it (the
//    first one of MRPT's logs) has no odometry (`has_odometry` false); an action after the last
//    sensory frame is counted in trailing_actions and not used.
//  - observation format: each top-level CObservationBeaconRanges is a frame, `step` its 0-based
//    index among the log's top-level observations; CObservationOdometry readings (cumulative,
//    2-D) between frames give its odometry as increment_between(previous, current) with MRPT's
//    default Gaussian motion model (the odometry carries no covariance of its own).
// Every CObservationBeaconRanges of a sensory frame becomes one BeaconRangeScan (ID, range,
// sensorLocationOnRobot, stdError, min/maxSensorDistance). Timestamp of a frame: its first
// observation with a valid timestamp (MRPT's convention for a sensory frame), else nan.
// Anything else is counted by class in `skipped` and ignored.

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "losmimo/localization/pose/odometry_model.h"
#include "losmimo/localization/pose/range_model.h"
#include "losmimo/fusion/rawlog/io/reader.h"

namespace losmimo::mrpt_logs {

struct RangeFrame {
  std::int64_t step = 0;     // 0-based index of the frame in the log (header)
  double timestamp_s = 0.0;  // MRPT time as seconds since the Unix epoch; nan if none
  bool has_odometry = false;
  localization::OdometryIncrement odometry;
  std::vector<localization::BeaconRangeScan> scans;
};

struct RangeLog {
  std::vector<RangeFrame> frames;
  std::int64_t beacon_observations = 0;  // CObservationBeaconRanges read
  std::int64_t ranges = 0;               // readings in them
  std::int64_t trailing_actions = 0;
  std::set<int> beacon_uavs;                    // nn of the CObservationBeaconRanges labelled "UAVnn_..." (format.h)
  std::map<std::string, std::int64_t> used;     // class -> count
  std::map<std::string, std::int64_t> skipped;  // class -> count
  rawlog_io::RawlogReadStatus read_status;
};

// Reads the whole log (reader.h's limits and sandbox apply). Never throws on the log's content.
RangeLog load_range_log(rawlog_io::RawlogReader& reader);

// "CObservation2DRangeScan x 343, CObservationImage x 2" (classes by name), or "none".
std::string describe_counts(const std::map<std::string, std::int64_t>& counts);

}  // namespace losmimo::mrpt_logs
