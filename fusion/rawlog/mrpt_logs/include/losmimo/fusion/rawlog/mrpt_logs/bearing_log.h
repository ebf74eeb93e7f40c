#pragma once
// A bearing-range rawlog (MRPT's kf-slam logs, or any log with CObservationBearingRange) read
// into frames for the landmark pose filters (localization/pose/landmark_filter.h).
//
// Frames:
//  - sensory-frame format: one frame per CSensoryFrame, `step` its 0-based index among the log's
//    sensory frames. Its odometry is every action since the previous sensory frame, composed in
//    order in the robot frame (CPose3D composition, landmark_model.h):
//      CActionRobotMovement2D  poseChange's mean (x, y, phi) as (x, y, 0, phi, 0, 0) and its 3x3
//                              covariance in the x-y-yaw rows
//      CActionRobotMovement3D  poseChange's mean and 6x6 covariance (CPose3D order)
//    u = u1 (+) u2, Sigma = J_x Sigma_1 J_x^T + J_u Sigma_2 J_u^T. A sensory frame with no action
//    before it (the first one of MRPT's logs) has no odometry; an action after the last sensory
//    frame is counted in trailing_actions.
//  - observation format: each top-level CObservationBearingRange is a frame (`step` its index
//    among the top-level observations), with the odometry of the cumulative 2-D
//    CObservationOdometry readings between frames (MRPT's default Gaussian motion model).
// Every CObservationBearingRange becomes one BearingScan: its readings as (range, azimuth =
// yaw, elevation = -pitch) with their landmark IDs, sensorLocationOnRobot, sensor_std_range /
// _yaw / _pitch and maxSensorDistance. Anything else is counted by class in `skipped`.
// The log is planar when it has no CActionRobotMovement3D and every reading's pitch is 0 (MRPT's
// 2-D kf-slam demo): the pose filters then hold z, pitch and roll at 0.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "losmimo/localization/pose/landmark_filter.h"
#include "losmimo/fusion/rawlog/io/reader.h"

namespace losmimo::mrpt_logs {

struct BearingFrame {
  std::int64_t step = 0;
  double timestamp_s = 0.0;  // MRPT time as seconds since the Unix epoch; nan if none
  bool has_odometry = false;
  localization::OdometryIncrement6 odometry;
  std::vector<localization::BearingScan> scans;
};

struct BearingLog {
  std::vector<BearingFrame> frames;
  std::int64_t bearing_observations = 0;  // CObservationBearingRange read
  std::int64_t readings = 0;              // readings in them
  std::int64_t readings_without_id = 0;   // landmarkID -1
  std::int64_t max_readings_per_observation = 0;
  std::int64_t valid_covariance_observations = 0;  // validCovariances set (their 3x3 are not used)
  std::int64_t actions_3d = 0;
  std::int64_t nonzero_pitch_readings = 0;
  std::int64_t trailing_actions = 0;
  std::map<std::string, std::int64_t> used;
  std::map<std::string, std::int64_t> skipped;
  rawlog_io::RawlogReadStatus read_status;

  bool planar() const { return actions_3d == 0 && nonzero_pitch_readings == 0; }
};

// Reads the whole log (reader.h's limits and sandbox apply). Never throws on the log's content.
BearingLog load_bearing_log(rawlog_io::RawlogReader& reader);

}  // namespace losmimo::mrpt_logs
