#include "losmimo/localization/pose/filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "losmimo/localization/filter_health.h"
#include "losmimo/localization/pose/initial_pose.h"
#include "losmimo/localization/pose/ekf.h"
#include "losmimo/localization/pose/particle_filter.h"

namespace losmimo::localization {

namespace {

[[noreturn]] void fail(const std::string& field, double value, const std::string& rule) {
  std::ostringstream msg;
  msg << field << " = " << value << ": must be " << rule;
  throw std::invalid_argument(msg.str());
}

}  // namespace

void validate(const PoseFilterConfig& config) {
  validate(config.filter);
  if (!std::isfinite(config.range_gate_chi2) || config.range_gate_chi2 <= 0.0) {
    fail("range_gate_chi2", config.range_gate_chi2, "finite and > 0");
  }
  if (!std::isfinite(config.min_sigma_yaw_rad) || config.min_sigma_yaw_rad <= 0.0) {
    fail("min_sigma_yaw_rad", config.min_sigma_yaw_rad, "finite and > 0");
  }
  if (!std::isfinite(config.missing_yaw_sigma_rad) || config.missing_yaw_sigma_rad <= 0.0) {
    fail("missing_yaw_sigma_rad", config.missing_yaw_sigma_rad, "finite and > 0");
  }
  if (config.min_ranges_for_fix < 1) fail("min_ranges_for_fix", config.min_ranges_for_fix, ">= 1");
}

Belief PoseBelief::position() const {
  Belief b;
  b.mean_m = mean.head<3>();
  b.cov_m2 = cov.topLeftCorner<3, 3>();
  b.degraded = degraded;
  b.epochs_since_beacon = epochs_since_beacon;
  return b;
}

std::optional<std::string> health_problem(const PoseBelief& belief) {
  return moments_problem<4>(belief.mean, belief.cov, "mean", "cov");
}

double range_sigma_m(const PoseFilterConfig& config, const BeaconRangeScan& scan) {
  const double sigma_m = config.use_observation_std ? scan.std_error_m : config.filter.noise.sigma_range_m;
  if (!std::isfinite(sigma_m) || sigma_m < 0.0) return std::numeric_limits<double>::quiet_NaN();  // screened out
  return std::max(sigma_m, config.filter.min_sigma_range_m);
}

std::optional<std::string> health_problem(const PoseFilter& filter) { return filter_health_problem(filter); }

std::unique_ptr<PoseFilter> make_pose_filter(FilterKind kind, const PoseFilterConfig& config, const BeaconMap& beacons,
                                             const InitialPose& initial, std::uint64_t seed) {
  return make_filter_of_kind<PoseFilter, EkfPoseFilter, ParticlePoseFilter>(kind, seed, config, beacons, initial);
}

}  // namespace losmimo::localization
