#pragma once
// The epoch-0 position belief of a UAV: the one rule that the closed loop, the rawlog replay and
// the co-evaluation's URA position source all start their filters from.
//
// Rule, in order:
//  1. no beacon at epoch 0                        -> the prior (kPriorNoBeacon);
//  2. a beacon that fails is_plausible()           -> the prior (kPriorImplausibleBeacon): the
//     same screen the filters apply (robustness.h), so an absurd reading never seeds a filter;
//  3. otherwise the beacon-only fix, beacon_fix(z, noise.sigma_range_m, noise.sigma_angle_rad)
//     (the configured sigmas as they are, not floored);
//  4. a belief that health_problem() flags (e.g. a fix whose covariance overflowed)
//                                                  -> the prior (kPriorHealthProblem), with the
//     problem's text, so that the caller can stop (the closed loop ends the run) or go on.
// The prior is normally start_cube_prior(): the UAVs start uniformly in the start cube, so its
// mean is the cube centre and its 1-sigma per axis cube_side_m / sqrt(12) (the uniform
// distribution's); it is marked degraded, with epochs_since_beacon = degraded_after_epochs (no
// beacon has been fused yet).

#include <optional>
#include <string>

#include "losmimo/localization/position/filter.h"
#include "losmimo/localization/position/measurements.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::localization {

enum class InitialBeliefSource { kBeaconFix, kPriorNoBeacon, kPriorImplausibleBeacon, kPriorHealthProblem };

std::string to_string(InitialBeliefSource source);

struct InitialBelief {
  Belief belief;  // what the filter starts from
  InitialBeliefSource source = InitialBeliefSource::kPriorNoBeacon;
  // The fix of a plausible beacon, also when step 4 rejected it (callers score every fix taken).
  std::optional<Belief> beacon_fix;
  std::string health_problem;  // step 4's finding, empty otherwise

  // True when the filter starts from the beacon: callers then count the beacon as fused.
  bool beacon_used() const { return source == InitialBeliefSource::kBeaconFix; }
};

// The start-cube prior described above.
Belief start_cube_prior(const placement::Scenario& scenario, const FilterConfig& config);

// The rule above. `prior` is returned as it is when no fix is taken.
InitialBelief initial_belief(const std::optional<BeaconMeasurement>& beacon, const FilterConfig& config,
                             const Belief& prior);

}  // namespace losmimo::localization
