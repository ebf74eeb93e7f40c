#pragma once
// What the recorder's standard-type streams (format.h: DR, BS_RANGES) and the stock-app files
// written beside a log (recorder.h's beacons.ini, ro_export.h) share, so that they agree.

#include <algorithm>
#include <string>

#include <Eigen/Core>
#include <mrpt/obs/CObservationBeaconRanges.h>

#include "losmimo/localization/filter_config.h"
#include "losmimo/fusion/rawlog/mission/format.h"
#include "losmimo/fusion/rawlog/mission/mission.h"

namespace losmimo::rawlog::detail {

// 2026-01-01T00:00:00Z: a fixed origin keeps the logs (and their digests) reproducible. Epoch k
// is at kTimeOrigin_s + k * epoch_period_s.
inline constexpr double kTimeOrigin_s = 1767225600.0;

// The 1-sigma per axis [m] of a measured displacement d_m, as the filter assumes it
// (position/simulator.h): dr_sigma_floor_m + dr_sigma_fraction * |d_m|.
inline double dr_sigma_m(const localization::NoiseModel& noise, const Eigen::Vector3d& d_m) {
  return noise.dr_sigma_floor_m + noise.dr_sigma_fraction * d_m.norm();
}

// beaconRangesStd of the stock-app configs: the beacon's range sigma; a noise-free beacon
// (sigma 0) still needs a positive likelihood width in the stock apps: 1 mm, the smallest range
// sigma the filters assume.
inline double stock_beacon_ranges_std_m(const MissionConfig& config) {
  constexpr double kMinRangesStd_m = 1e-3;
  return std::max(config.closed_loop.simulator.sigma_range_m, kMinRangesStd_m);
}

// The beacon's range as one reading of the BS beacon (format.h), for stock range-only apps.
inline mrpt::obs::CObservationBeaconRanges bs_ranges_obs(const std::string& label, double t_s, double range_m,
                                                         double sigma_range_m) {
  mrpt::obs::CObservationBeaconRanges o;
  o.sensorLabel = label;
  o.timestamp = mrpt::Clock::fromDouble(t_s);
  o.stdError = static_cast<float>(sigma_range_m);
  o.minSensorDistance = 0.0f;
  o.maxSensorDistance = kBsRangesMaxDistance_m;
  mrpt::obs::CObservationBeaconRanges::TMeasurement z;
  z.beaconID = kBsBeaconId;
  z.sensedDistance = static_cast<float>(range_m);
  o.sensedData.push_back(z);
  return o;
}

}  // namespace losmimo::rawlog::detail
