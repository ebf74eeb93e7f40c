#pragma once
// Ranges to beacons at known positions, as MRPT's CObservationBeaconRanges carries them: the
// beacon map, one scan's readings, the range model with its Jacobian, and the per-range screen.
//
// Frames: the map frame of the beacon positions and of the pose x = (x_m, y_m, z_m, yaw_rad)
// (odometry_model.h); each reading's sensor position s [m] is in the robot frame
// (sensorLocationOnRobot).
// Model of one reading of beacon b:
//   c(x)  = p + Rz(yaw) s            the sensor in the map frame, p = (x, y, z)
//   h(x)  = |c(x) - b|               [m]
//   J_h_x = [e^T, e^T dRz/dyaw s],   e = (c(x) - b) / h(x)  (unit vector beacon -> sensor),
//   e^T dRz/dyaw s = e_x (-sin(yaw) s_x - cos(yaw) s_y) + e_y (cos(yaw) s_x - sin(yaw) s_y).
// Noise: z = h(x) + v, v ~ N(0, sigma^2), independent between readings; sigma is the scan's
// stdError or the configured sigma (pose/filter.h), floored.
// Degenerate geometry: h is not differentiable at c = b; screen_range() cannot see the pose, so
// the filters reject a reading whose predicted h is below kMinRangeGeometry_m.
//
// Screen of one reading, in this order (the first failing check is the reason it is counted
// under in FilterCounters, never fused):
//   non-finite or <= 0 range, or an unusable stdError when the filter takes it from the scan
//                                                 -> rejected_non_finite_range
//   beacon ID not in the map (INVALID_BEACON_ID = -1 never is)
//                                                 -> rejected_unknown_beacon
//   outside [minSensorDistance, maxSensorDistance] (a non-finite limit rejects every reading)
//                                                 -> rejected_outside_sensor_limits
//   above max_beacon_range_m (the physical plausibility screen of position/filter.h)
//                                                 -> rejected_implausible_range
// A range of exactly 0 is a dropout in real logs (MRPT's UWB demo has six), not a distance.

#include <cstdint>
#include <map>
#include <vector>

#include <Eigen/Core>

#include "losmimo/localization/filter_config.h"
#include "losmimo/localization/filter_counters.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::localization {

inline constexpr std::int32_t kInvalidBeaconId = -1;  // MRPT's INVALID_BEACON_ID
inline constexpr double kMinRangeGeometry_m = 1e-6;

// Beacon ID -> position in the map frame [m].
class BeaconMap {
 public:
  // Throws std::invalid_argument for kInvalidBeaconId, a duplicate ID or a non-finite position.
  void add(std::int32_t id, const Eigen::Vector3d& position_m);
  // nullptr when the ID is not in the map.
  const Eigen::Vector3d* find(std::int32_t id) const;
  std::size_t size() const { return beacons_.size(); }
  bool empty() const { return beacons_.empty(); }
  const std::map<std::int32_t, Eigen::Vector3d>& beacons() const { return beacons_; }

 private:
  std::map<std::int32_t, Eigen::Vector3d> beacons_;
};

// The BS antennas as beacons (the paper's BS, placement/scenario.h): ID m = antenna m, at
// bs_antenna_positions_m(scenario).col(m), in the BS array frame.
BeaconMap bs_antenna_beacon_map(const placement::Scenario& scenario);

// One reading (CObservationBeaconRanges::TMeasurement).
struct BeaconRange {
  std::int32_t beacon_id = kInvalidBeaconId;
  double range_m = 0.0;                                         // sensedDistance
  Eigen::Vector3d sensor_on_robot_m = Eigen::Vector3d::Zero();  // sensorLocationOnRobot
};

// One CObservationBeaconRanges (MRPT's defaults).
struct BeaconRangeScan {
  std::vector<BeaconRange> ranges;  // sensedData
  double std_error_m = 0.01;        // stdError
  double min_sensor_distance_m = 0.0;
  double max_sensor_distance_m = 100.0;
};

// c(x), h(x) and J_h_x above.
Eigen::Vector3d sensor_position_m(const Eigen::Vector4d& pose, const Eigen::Vector3d& sensor_on_robot_m);
double range_predict(const Eigen::Vector4d& pose, const Eigen::Vector3d& sensor_on_robot_m,
                     const Eigen::Vector3d& beacon_m);
// J_h_x; zero when h < kMinRangeGeometry_m.
Eigen::RowVector4d range_jacobian(const Eigen::Vector4d& pose, const Eigen::Vector3d& sensor_on_robot_m,
                                  const Eigen::Vector3d& beacon_m);

enum class RangeVerdict { kUsable, kNonFinite, kUnknownBeacon, kOutsideSensorLimits, kImplausible };

// The screen above. sigma_range_m: the 1-sigma the filter would use for this scan (a
// non-finite or non-positive one rejects the reading as kNonFinite).
RangeVerdict screen_range(const BeaconRange& reading, const BeaconRangeScan& scan, const BeaconMap& map,
                          double sigma_range_m, double max_beacon_range_m);

// Adds one rejection to the counter of its reason (kUsable adds nothing).
void count_rejection(RangeVerdict verdict, FilterCounters& counters);

}  // namespace losmimo::localization
