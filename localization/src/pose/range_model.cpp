#include "losmimo/localization/pose/range_model.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "losmimo/localization/pose/odometry_model.h"

namespace losmimo::localization {

void BeaconMap::add(std::int32_t id, const Eigen::Vector3d& position_m) {
  if (id == kInvalidBeaconId) {
    throw std::invalid_argument("beacon_id = -1: must not be MRPT's INVALID_BEACON_ID");
  }
  if (!position_m.allFinite()) {
    std::ostringstream msg;
    msg << "beacon " << id << " position_m = (" << position_m.transpose() << "): must be finite";
    throw std::invalid_argument(msg.str());
  }
  if (!beacons_.emplace(id, position_m).second) {
    throw std::invalid_argument("beacon_id = " + std::to_string(id) + ": must be unique in the beacon map");
  }
}

const Eigen::Vector3d* BeaconMap::find(std::int32_t id) const {
  const auto it = beacons_.find(id);
  return it == beacons_.end() ? nullptr : &it->second;
}

BeaconMap bs_antenna_beacon_map(const placement::Scenario& scenario) {
  const Eigen::Matrix3Xd antennas_m = placement::bs_antenna_positions_m(scenario);
  BeaconMap map;
  for (Eigen::Index m = 0; m < antennas_m.cols(); ++m) map.add(static_cast<std::int32_t>(m), antennas_m.col(m));
  return map;
}

Eigen::Vector3d sensor_position_m(const Eigen::Vector4d& pose, const Eigen::Vector3d& sensor_on_robot_m) {
  const double c = std::cos(pose(kPoseYaw));
  const double s = std::sin(pose(kPoseYaw));
  return {pose(kPoseX) + c * sensor_on_robot_m.x() - s * sensor_on_robot_m.y(),
          pose(kPoseY) + s * sensor_on_robot_m.x() + c * sensor_on_robot_m.y(), pose(kPoseZ) + sensor_on_robot_m.z()};
}

double range_predict(const Eigen::Vector4d& pose, const Eigen::Vector3d& sensor_on_robot_m,
                     const Eigen::Vector3d& beacon_m) {
  return (sensor_position_m(pose, sensor_on_robot_m) - beacon_m).norm();
}

Eigen::RowVector4d range_jacobian(const Eigen::Vector4d& pose, const Eigen::Vector3d& sensor_on_robot_m,
                                  const Eigen::Vector3d& beacon_m) {
  const Eigen::Vector3d d_m = sensor_position_m(pose, sensor_on_robot_m) - beacon_m;
  const double h_m = d_m.norm();
  if (!(h_m >= kMinRangeGeometry_m)) return Eigen::RowVector4d::Zero();
  const Eigen::Vector3d e = d_m / h_m;
  const double c = std::cos(pose(kPoseYaw));
  const double s = std::sin(pose(kPoseYaw));
  const double dcx_dyaw = -s * sensor_on_robot_m.x() - c * sensor_on_robot_m.y();
  const double dcy_dyaw = c * sensor_on_robot_m.x() - s * sensor_on_robot_m.y();
  return {e.x(), e.y(), e.z(), e.x() * dcx_dyaw + e.y() * dcy_dyaw};
}

RangeVerdict screen_range(const BeaconRange& reading, const BeaconRangeScan& scan, const BeaconMap& map,
                          double sigma_range_m, double max_beacon_range_m) {
  if (!std::isfinite(reading.range_m) || reading.range_m <= 0.0 || !reading.sensor_on_robot_m.allFinite() ||
      !std::isfinite(sigma_range_m) || sigma_range_m <= 0.0) {
    return RangeVerdict::kNonFinite;
  }
  if (map.find(reading.beacon_id) == nullptr) return RangeVerdict::kUnknownBeacon;
  if (!(reading.range_m >= scan.min_sensor_distance_m && reading.range_m <= scan.max_sensor_distance_m)) {
    return RangeVerdict::kOutsideSensorLimits;
  }
  if (reading.range_m > max_beacon_range_m) return RangeVerdict::kImplausible;
  return RangeVerdict::kUsable;
}

void count_rejection(RangeVerdict verdict, FilterCounters& counters) {
  switch (verdict) {
    case RangeVerdict::kUsable:
      return;
    case RangeVerdict::kNonFinite:
      ++counters.rejected_non_finite_range;
      return;
    case RangeVerdict::kUnknownBeacon:
      ++counters.rejected_unknown_beacon;
      return;
    case RangeVerdict::kOutsideSensorLimits:
      ++counters.rejected_outside_sensor_limits;
      return;
    case RangeVerdict::kImplausible:
      ++counters.rejected_implausible_range;
      return;
  }
}

}  // namespace losmimo::localization
