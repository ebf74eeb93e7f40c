#include "losmimo/localization/position/initial_belief.h"

#include <cmath>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/robustness.h"

namespace losmimo::localization {

std::string to_string(InitialBeliefSource source) {
  switch (source) {
    case InitialBeliefSource::kBeaconFix:
      return "beacon fix";
    case InitialBeliefSource::kPriorNoBeacon:
      return "prior (no beacon)";
    case InitialBeliefSource::kPriorImplausibleBeacon:
      return "prior (implausible beacon)";
    case InitialBeliefSource::kPriorHealthProblem:
      return "prior (beacon fix unhealthy)";
  }
  return "unknown";
}

Belief start_cube_prior(const placement::Scenario& scenario, const FilterConfig& config) {
  const double sigma_m = scenario.cube_side_m / std::sqrt(12.0);  // uniform in the cube
  Belief prior;
  prior.mean_m = scenario.cube_center_m;
  prior.cov_m2 = sigma_m * sigma_m * Eigen::Matrix3d::Identity();
  prior.degraded = true;
  prior.epochs_since_beacon = config.degraded_after_epochs;
  return prior;
}

InitialBelief initial_belief(const std::optional<BeaconMeasurement>& beacon, const FilterConfig& config,
                             const Belief& prior) {
  InitialBelief out;
  out.belief = prior;
  if (!beacon) {
    out.source = InitialBeliefSource::kPriorNoBeacon;
  } else if (!is_plausible(config, *beacon)) {
    out.source = InitialBeliefSource::kPriorImplausibleBeacon;
  } else {
    out.beacon_fix = beacon_fix(*beacon, config.noise.sigma_range_m, config.noise.sigma_angle_rad);
    out.belief = *out.beacon_fix;
    out.source = InitialBeliefSource::kBeaconFix;
  }
  if (const std::optional<std::string> problem = health_problem(out.belief)) {
    out.health_problem = *problem;
    out.belief = prior;
    out.source = InitialBeliefSource::kPriorHealthProblem;
  }
  return out;
}

}  // namespace losmimo::localization
