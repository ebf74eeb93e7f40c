#include "losmimo/localization/position/robustness.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "losmimo/localization/position/beacon_model.h"

namespace losmimo::localization {

bool is_finite(const BeaconMeasurement& z) {
  return std::isfinite(z.range_m) && std::isfinite(z.azimuth_rad) && std::isfinite(z.elevation_rad);
}

double displacement_sigma_m(const FilterConfig& config, double distance_m) {
  const double sigma_m = config.noise.dr_sigma_floor_m + config.noise.dr_sigma_fraction * distance_m;
  return std::max(sigma_m, config.min_sigma_displacement_m);
}

ScreenedDisplacement screen_displacement(const FilterConfig& config, const Eigen::Vector3d& measured_m,
                                         FilterCounters& counters) {
  if (measured_m.allFinite()) return {measured_m, displacement_sigma_m(config, measured_m.norm())};
  ++counters.rejected_non_finite_displacement;
  return {Eigen::Vector3d::Zero(), config.missing_displacement_sigma_m};
}

Eigen::Matrix3d floored_beacon_cov(const FilterConfig& config) {
  return beacon_noise_cov(std::max(config.noise.sigma_range_m, config.min_sigma_range_m),
                          std::max(config.noise.sigma_angle_rad, config.min_sigma_angle_rad));
}

double mahalanobis2(const Eigen::Vector3d& y, const Eigen::Matrix3d& S) {
  const Eigen::LLT<Eigen::Matrix3d> llt(S);
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return y.dot(llt.solve(y));
}

Belief floored_beacon_fix(const FilterConfig& config, const BeaconMeasurement& z) {
  return beacon_fix(z, std::max(config.noise.sigma_range_m, config.min_sigma_range_m),
                    std::max(config.noise.sigma_angle_rad, config.min_sigma_angle_rad));
}

bool is_plausible(const FilterConfig& config, const BeaconMeasurement& z) {
  constexpr double kHalfPi_rad = 1.57079632679489661923;
  return is_finite(z) && z.range_m > 0.0 && z.range_m <= config.max_beacon_range_m &&
         std::abs(wrap_angle_rad(z.elevation_rad)) <= kHalfPi_rad;
}

BeaconVerdict screen_beacon(const FilterConfig& config, const std::optional<BeaconMeasurement>& beacon,
                            const Eigen::Vector3d& predicted_mean_m, const Eigen::Matrix3d& predicted_cov_m2,
                            int& consecutive_gated, FilterCounters& counters) {
  if (!beacon) return BeaconVerdict::kNone;
  ++counters.beacons_received;
  // A range <= 0 is as meaningless as a NaN: the inverse model and the gate need r > 0.
  if (!is_finite(*beacon) || beacon->range_m <= 0.0) {
    ++counters.rejected_non_finite_beacon;
    return BeaconVerdict::kNonFinite;
  }
  // A finite but impossible beacon (e.g. 1e300 m) would be gated until the reset rule took a
  // fix from it: reject it before the gate, so it never counts towards a reset.
  if (!is_plausible(config, *beacon)) {
    ++counters.rejected_out_of_range_beacon;
    return BeaconVerdict::kOutOfRange;
  }
  if (std::hypot(predicted_mean_m.x(), predicted_mean_m.y()) < kMinBeaconRho_m) {
    ++counters.rejected_geometry;
    return BeaconVerdict::kGeometry;
  }
  if (config.gate_enabled) {
    const Eigen::Matrix3d J_z_q = beacon_jacobian(predicted_mean_m);
    const Eigen::Matrix3d S = J_z_q * predicted_cov_m2 * J_z_q.transpose() + floored_beacon_cov(config);
    const Eigen::Vector3d y = beacon_innovation(to_vector(*beacon), beacon_predict(predicted_mean_m));
    if (!(mahalanobis2(y, S) <= config.gate_chi2)) {
      if (config.reset_after_rejections > 0 && consecutive_gated >= config.reset_after_rejections) {
        consecutive_gated = 0;
        ++counters.resets;
        ++counters.beacons_fused;
        return BeaconVerdict::kReset;
      }
      ++consecutive_gated;
      ++counters.rejected_gate;
      return BeaconVerdict::kGated;
    }
  }
  consecutive_gated = 0;
  ++counters.beacons_fused;
  return BeaconVerdict::kFuse;
}

void apply_health(const FilterConfig& config, int epochs_since_beacon, Belief& belief) {
  belief.epochs_since_beacon = epochs_since_beacon;
  belief.degraded = is_degraded(config, epochs_since_beacon, belief.cov_m2);
}

}  // namespace losmimo::localization
