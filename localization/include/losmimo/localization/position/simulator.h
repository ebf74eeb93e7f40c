#pragma once
// Seeded simulator of what a UAV's sensors report, for the tests, the closed loop and the
// rawlog recorder. One simulator per UAV and trial, each with its own std::mt19937_64.
//
// Frame: BS array frame (placement/scenario.h), metres and radians. Epoch k = 0, 1, 2, ...
// Actuation (the placement model, placement/swarm.h): a commanded motion c becomes the true
//   displacement d = c + e_act, e_act ~ N(0, sigma_act_m^2 I); the UAV does not see e_act.
//   In a closed loop the placement Swarm applies it; actuate() is for stand-alone runs.
// Dead reckoning: d_meas = d + e_dr, e_dr ~ N(0, s^2 I), s = dr_sigma_floor_m +
//   dr_sigma_fraction * |d| (per axis, per epoch).
// Beacon (measurements.h for h): at epochs with k % beacon_period_epochs == 0 outside every
//   outage window, z = h(q) + v, v ~ N(0, diag(sigma_range_m^2, sigma_angle_rad^2,
//   sigma_angle_rad^2)), azimuth wrapped to (-pi, pi]. With probability outlier_fraction the
//   beacon is a gross error instead: v ~ N(0, diag(outlier_sigma_range_m^2,
//   outlier_sigma_angle_rad^2, outlier_sigma_angle_rad^2)).
//   Common-mode errors: z = h(q - bs_position_error_m) + (beacon_range_bias_m,
//   bs_azimuth_bias_rad, bs_elevation_bias_rad) + v: the BS measures from where it stands, with
//   its array's mounting offsets, while every filter assumes the nominal BS (origin, no bias).
// Defaults: sigma_angle_rad = 1e-4 gives a lateral 1-sigma of r * sigma_angle = 0.1 m per
//   cross-range axis at r = 1 km, and sigma_range_m = 0.1 m matches it along the range, so the
//   beacon-only fix at 1 km is ~0.1 m (1-sigma) on each axis. Gross errors are 200x nominal.

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "losmimo/placement/common/range.h"
#include "losmimo/localization/position/measurements.h"

namespace losmimo::localization {

struct OutageWindow {
  int first_epoch = 0;
  int num_epochs = 0;  // no beacon for epochs first_epoch .. first_epoch + num_epochs - 1
};

struct SimulatorConfig {
  double sigma_range_m = 0.1;
  double sigma_angle_rad = 1e-4;
  int beacon_period_epochs = 1;
  std::vector<OutageWindow> outages;
  double outlier_fraction = 0.0;  // in [0, 1]
  double outlier_sigma_range_m = 20.0;
  double outlier_sigma_angle_rad = 0.02;
  double dr_sigma_floor_m = 0.01;
  double dr_sigma_fraction = 0.02;
  double sigma_act_m = 0.0;  // actuation error, used by actuate() only
  // Common-mode beacon errors, the same for every UAV of a swarm (they all range and bear from
  // one BS); 0 = none. The filters do not know them.
  double bs_azimuth_bias_rad = 0.0;    // the BS array mounted rotated: azimuths read this much more
  double bs_elevation_bias_rad = 0.0;  // ... and elevations
  double beacon_range_bias_m = 0.0;    // every range reads this much more
  Eigen::Vector3d bs_position_error_m = Eigen::Vector3d::Zero();  // the BS stands here, not at the origin
};

// The values each field accepts (validate() and the keys that set them).
namespace simulator_range {
inline constexpr common::Range sigma = common::Range::at_least(0.0);  // every *_sigma_* and sigma_act_m
inline constexpr common::Range beacon_period_epochs = common::Range::closed(1, 1'000'000);
inline constexpr common::Range outlier_fraction = common::Range::closed(0.0, 1.0);
inline constexpr common::Range outage_epoch = common::Range::closed(0, 1e9);       // first_epoch, num_epochs
inline constexpr common::Range angle_bias = common::Range::closed(-0.1, 0.1);      // [rad]: a mounting error
inline constexpr common::Range position_error = common::Range::closed(-1e3, 1e3);  // range bias, BS position [m]
}  // namespace simulator_range

// Throws common::FieldError naming the first bad field and its value.
void validate(const SimulatorConfig& config);

class SensorSimulator {
 public:
  SensorSimulator(const SimulatorConfig& config, std::uint64_t seed);

  const SimulatorConfig& config() const { return config_; }

  // True displacement for a commanded one (actuation error added).
  Eigen::Vector3d actuate(const Eigen::Vector3d& commanded_m);
  // Dead-reckoning reading of a true displacement.
  Eigen::Vector3d measure_displacement(const Eigen::Vector3d& true_displacement_m);
  // Whether the schedule (period and outages) has a beacon at this epoch (epoch >= 0).
  bool beacon_scheduled(int epoch) const;
  // The beacon at this epoch from true position true_q_m, or nullopt if none is scheduled.
  std::optional<BeaconMeasurement> measure_beacon(const Eigen::Vector3d& true_q_m, int epoch);

  // Gross errors produced so far.
  int num_outliers() const { return num_outliers_; }

 private:
  double gaussian() { return normal_(rng_); }

  SimulatorConfig config_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  int num_outliers_ = 0;
};

}  // namespace losmimo::localization
