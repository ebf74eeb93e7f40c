#pragma once
// Seeded simulator of a ranging vehicle's sensors, for the pose filters' tests and for synthetic
// logs with known truth: robot-frame odometry (as CActionRobotMovement2D/3D carry it) and ranges
// to mapped beacons (as CObservationBeaconRanges carries them). One simulator per vehicle and
// run, with its own std::mt19937_64 (the position simulator, position/simulator.h, is untouched).
//
// Frames and models: odometry_model.h and range_model.h. Beacons: any BeaconMap, e.g. UWB
// anchors around a ground robot, or the BS's own antennas (bs_antenna_beacon_map: the paper's
// BS, 16 beacons within 0.75 m, so from 1 km the ranges say a lot about the distance and very
// little laterally).
// Odometry: the reading of a true increment u_true (robot frame) is u_true + n,
//   n ~ N(0, Sigma(u_true)), Sigma = odometry_2d's MRPT Gaussian model (x, y, yaw) and
//   sigma_z_m^2 on z; the reading carries Sigma(reading) as its covariance, as MRPT rebuilds
//   poseChange from the reading (the two differ by the noise's effect on Sigma, second order).
// Ranges: at epochs with k % period_epochs == 0 outside every outage window, one scan with one
// reading per mapped beacon whose true range d = |c(x) - b| (c the sensor point, sensor_on_robot_m)
// lies in [min_sensor_distance_m, max_sensor_distance_m] (a real sensor reports nothing else),
// in map order: range_m = d + v, v ~ N(0, sigma_range_m^2), or, with probability
// outlier_fraction, v ~ N(0, outlier_sigma_range_m^2); each reading independently dropped with
// probability dropout_fraction. The scan's std_error_m is sigma_range_m.

#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "losmimo/localization/pose/odometry_model.h"
#include "losmimo/localization/pose/range_model.h"
#include "losmimo/localization/position/simulator.h"

namespace losmimo::localization {

struct RangeSimulatorConfig {
  double sigma_range_m = 0.05;
  double min_sensor_distance_m = 0.0;
  double max_sensor_distance_m = 100.0;
  Eigen::Vector3d sensor_on_robot_m = Eigen::Vector3d::Zero();
  int period_epochs = 1;
  std::vector<OutageWindow> outages;
  double outlier_fraction = 0.0;  // in [0, 1]
  double outlier_sigma_range_m = 5.0;
  double dropout_fraction = 0.0;  // in [0, 1]
  GaussianMotionModel2D odometry;
  double sigma_z_m = 0.0;  // vertical odometry noise per step
};

// Throws std::invalid_argument naming the first bad field and its value.
void validate(const RangeSimulatorConfig& config);

class RangeSensorSimulator {
 public:
  RangeSensorSimulator(const RangeSimulatorConfig& config, BeaconMap beacons, std::uint64_t seed);

  const RangeSimulatorConfig& config() const { return config_; }
  const BeaconMap& beacons() const { return beacons_; }

  // The odometry reading of a true robot-frame increment (dx, dy, dz, dyaw).
  OdometryIncrement measure_odometry(const Eigen::Vector4d& true_increment);
  // Whether the schedule (period and outages) has a scan at this epoch (epoch >= 0).
  bool scan_scheduled(int epoch) const;
  // The scan at this epoch from the true pose, or nullopt if none is scheduled.
  std::optional<BeaconRangeScan> measure_ranges(const Eigen::Vector4d& true_pose, int epoch);

  int num_outliers() const { return num_outliers_; }

 private:
  double gaussian() { return normal_(rng_); }

  RangeSimulatorConfig config_;
  BeaconMap beacons_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  int num_outliers_ = 0;
};

}  // namespace losmimo::localization
