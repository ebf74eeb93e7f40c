#include "losmimo/localization/position/simulator.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "losmimo/localization/position/beacon_model.h"

namespace losmimo::localization {

void validate(const SimulatorConfig& config) {
  namespace r = simulator_range;
  const auto require = [](const common::Range& range, double value, const std::string& field) {
    common::require_field_in(range, value, "simulator", field);
  };
  require(r::sigma, config.sigma_range_m, "sigma_range_m");
  require(r::sigma, config.sigma_angle_rad, "sigma_angle_rad");
  require(r::beacon_period_epochs, config.beacon_period_epochs, "beacon_period_epochs");
  for (std::size_t i = 0; i < config.outages.size(); ++i) {
    const std::string name = "outages[" + std::to_string(i) + "]";
    require(r::outage_epoch, config.outages[i].first_epoch, name + ".first_epoch");
    require(r::outage_epoch, config.outages[i].num_epochs, name + ".num_epochs");
  }
  require(r::outlier_fraction, config.outlier_fraction, "outlier_fraction");
  require(r::sigma, config.outlier_sigma_range_m, "outlier_sigma_range_m");
  require(r::sigma, config.outlier_sigma_angle_rad, "outlier_sigma_angle_rad");
  require(r::sigma, config.dr_sigma_floor_m, "dr_sigma_floor_m");
  require(r::sigma, config.dr_sigma_fraction, "dr_sigma_fraction");
  require(r::sigma, config.sigma_act_m, "sigma_act_m");
  require(r::angle_bias, config.bs_azimuth_bias_rad, "bs_azimuth_bias_rad");
  require(r::angle_bias, config.bs_elevation_bias_rad, "bs_elevation_bias_rad");
  require(r::position_error, config.beacon_range_bias_m, "beacon_range_bias_m");
  for (int a = 0; a < 3; ++a)
    require(r::position_error, config.bs_position_error_m(a), "bs_position_error_m[" + std::to_string(a) + "]");
}

SensorSimulator::SensorSimulator(const SimulatorConfig& config, std::uint64_t seed) : config_(config), rng_(seed) {
  validate(config_);
}

Eigen::Vector3d SensorSimulator::actuate(const Eigen::Vector3d& commanded_m) {
  Eigen::Vector3d d = commanded_m;
  for (int a = 0; a < 3; ++a) d(a) += config_.sigma_act_m * gaussian();
  return d;
}

Eigen::Vector3d SensorSimulator::measure_displacement(const Eigen::Vector3d& true_displacement_m) {
  const double sigma_m = config_.dr_sigma_floor_m + config_.dr_sigma_fraction * true_displacement_m.norm();
  Eigen::Vector3d measured = true_displacement_m;
  for (int a = 0; a < 3; ++a) measured(a) += sigma_m * gaussian();
  return measured;
}

bool SensorSimulator::beacon_scheduled(int epoch) const {
  if (epoch < 0) {
    throw std::invalid_argument("localization: beacon epoch = " + std::to_string(epoch) + " (must be >= 0)");
  }
  if (epoch % config_.beacon_period_epochs != 0) return false;
  for (const OutageWindow& w : config_.outages) {
    if (epoch >= w.first_epoch && epoch - w.first_epoch < w.num_epochs) return false;
  }
  return true;
}

std::optional<BeaconMeasurement> SensorSimulator::measure_beacon(const Eigen::Vector3d& true_q_m, int epoch) {
  if (!beacon_scheduled(epoch)) return std::nullopt;
  const bool outlier = uniform_(rng_) < config_.outlier_fraction;
  const double sigma_range_m = outlier ? config_.outlier_sigma_range_m : config_.sigma_range_m;
  const double sigma_angle_rad = outlier ? config_.outlier_sigma_angle_rad : config_.sigma_angle_rad;
  if (outlier) ++num_outliers_;
  Eigen::Vector3d z_true = beacon_predict(true_q_m - config_.bs_position_error_m);
  // Only when set, so that a config without them measures bit for bit as before (-0 + 0 is +0).
  if (config_.beacon_range_bias_m != 0.0) z_true(0) += config_.beacon_range_bias_m;
  if (config_.bs_azimuth_bias_rad != 0.0) z_true(1) += config_.bs_azimuth_bias_rad;
  if (config_.bs_elevation_bias_rad != 0.0) z_true(2) += config_.bs_elevation_bias_rad;
  BeaconMeasurement z;
  z.range_m = z_true(0) + sigma_range_m * gaussian();
  z.azimuth_rad = wrap_angle_rad(z_true(1) + sigma_angle_rad * gaussian());
  z.elevation_rad = z_true(2) + sigma_angle_rad * gaussian();
  return z;
}

}  // namespace losmimo::localization
