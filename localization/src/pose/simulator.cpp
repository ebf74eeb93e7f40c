#include "losmimo/localization/pose/simulator.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace losmimo::localization {

namespace {

[[noreturn]] void fail(const std::string& field, double value, const std::string& rule) {
  std::ostringstream msg;
  msg << "range_simulator." << field << " = " << value << ": must be " << rule;
  throw std::invalid_argument(msg.str());
}

void require_non_negative(const std::string& field, double value) {
  if (!std::isfinite(value) || value < 0.0) fail(field, value, "finite and >= 0");
}

void require_fraction(const std::string& field, double value) {
  if (!std::isfinite(value) || value < 0.0 || value > 1.0) fail(field, value, "in [0, 1]");
}

}  // namespace

void validate(const RangeSimulatorConfig& config) {
  require_non_negative("sigma_range_m", config.sigma_range_m);
  require_non_negative("min_sensor_distance_m", config.min_sensor_distance_m);
  if (!std::isfinite(config.max_sensor_distance_m) || config.max_sensor_distance_m < config.min_sensor_distance_m) {
    fail("max_sensor_distance_m", config.max_sensor_distance_m, "finite and >= min_sensor_distance_m");
  }
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(config.sensor_on_robot_m(i))) {
      fail("sensor_on_robot_m(" + std::to_string(i) + ")", config.sensor_on_robot_m(i), "finite");
    }
  }
  if (config.period_epochs < 1) fail("period_epochs", config.period_epochs, ">= 1");
  for (std::size_t i = 0; i < config.outages.size(); ++i) {
    const std::string name = "outages[" + std::to_string(i) + "]";
    if (config.outages[i].first_epoch < 0) fail(name + ".first_epoch", config.outages[i].first_epoch, ">= 0");
    if (config.outages[i].num_epochs < 0) fail(name + ".num_epochs", config.outages[i].num_epochs, ">= 0");
  }
  require_fraction("outlier_fraction", config.outlier_fraction);
  require_non_negative("outlier_sigma_range_m", config.outlier_sigma_range_m);
  require_fraction("dropout_fraction", config.dropout_fraction);
  validate(config.odometry);
  require_non_negative("sigma_z_m", config.sigma_z_m);
}

RangeSensorSimulator::RangeSensorSimulator(const RangeSimulatorConfig& config, BeaconMap beacons, std::uint64_t seed)
    : config_(config), beacons_(std::move(beacons)), rng_(seed) {
  validate(config_);
}

OdometryIncrement RangeSensorSimulator::measure_odometry(const Eigen::Vector4d& true_increment) {
  const OdometryIncrement truth_model = odometry_2d(true_increment(kPoseX), true_increment(kPoseY),
                                                    true_increment(kPoseYaw), config_.odometry, config_.sigma_z_m);
  // Through the eigen-decomposition: the model's covariance may be singular (a zero minimum std).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(truth_model.cov);
  Eigen::Vector4d n;
  for (int i = 0; i < kPoseSize; ++i) n(i) = gaussian();
  const Eigen::Vector4d noise = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().cwiseProduct(n);
  Eigen::Vector4d reading = true_increment + noise;
  OdometryIncrement out =
      odometry_2d(reading(kPoseX), reading(kPoseY), reading(kPoseYaw), config_.odometry, config_.sigma_z_m);
  out.delta(kPoseZ) = reading(kPoseZ);
  return out;
}

bool RangeSensorSimulator::scan_scheduled(int epoch) const {
  if (epoch < 0) throw std::invalid_argument("epoch = " + std::to_string(epoch) + ": must be >= 0");
  if (epoch % config_.period_epochs != 0) return false;
  for (const OutageWindow& w : config_.outages) {
    if (epoch >= w.first_epoch && epoch - w.first_epoch < w.num_epochs) return false;
  }
  return true;
}

std::optional<BeaconRangeScan> RangeSensorSimulator::measure_ranges(const Eigen::Vector4d& true_pose, int epoch) {
  if (!scan_scheduled(epoch)) return std::nullopt;
  BeaconRangeScan scan;
  scan.std_error_m = config_.sigma_range_m;
  scan.min_sensor_distance_m = config_.min_sensor_distance_m;
  scan.max_sensor_distance_m = config_.max_sensor_distance_m;
  const Eigen::Vector3d sensor_m = sensor_position_m(true_pose, config_.sensor_on_robot_m);
  for (const auto& [id, beacon_m] : beacons_.beacons()) {
    const double d_m = (sensor_m - beacon_m).norm();
    // Every draw is taken whatever the outcome, so one beacon's fate never shifts another's noise.
    const bool outlier = uniform_(rng_) < config_.outlier_fraction;
    const bool dropped = uniform_(rng_) < config_.dropout_fraction;
    const double v_m = (outlier ? config_.outlier_sigma_range_m : config_.sigma_range_m) * gaussian();
    if (d_m < config_.min_sensor_distance_m || d_m > config_.max_sensor_distance_m || dropped) continue;
    if (outlier) ++num_outliers_;
    scan.ranges.push_back({id, d_m + v_m, config_.sensor_on_robot_m});
  }
  return scan;
}

}  // namespace losmimo::localization
