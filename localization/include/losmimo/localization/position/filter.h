#pragma once
// The common interface of the position filters (EKF and particle filter, both through MRPT).
//
// State q_k = UAV position at epoch k in the BS array frame [m] (position only: the UAV's
// velocity is not estimated; dead reckoning supplies the motion between epochs).
// Motion:  q_k = q_{k-1} + d_k - n_k,  d_k the measured displacement (dead reckoning),
//          n_k ~ N(0, sigma_d(|d_k|)^2 I),  sigma_d(s) = dr_sigma_floor_m + dr_sigma_fraction * s.
//          The actuation error is inside the true displacement that dead reckoning measures,
//          so it needs no separate term here.
// Beacon:  z_k = h(q_k) + v_k, v_k ~ N(0, R) (beacon_model.h).
//
// One call to step() is one epoch: predict with d_k, then fuse the beacon if there is one and
// it passes the checks. Robustness, on by default:
//  - non-finite displacement: the epoch predicts with d = 0 and sigma missing_displacement_sigma_m;
//  - non-finite beacon, or beacon with rho < kMinBeaconRho_m at the prediction: not fused;
//  - physically implausible beacon: range_m > max_beacon_range_m, or an elevation outside
//    [-pi/2, pi/2] once wrapped to (-pi, pi] (any finite azimuth is a direction after
//    wrapping): never fused, never used for a reset, and not a gate rejection (it neither
//    counts towards reset_after_rejections nor clears that count, exactly as if the epoch had
//    no beacon); counted in FilterCounters::rejected_out_of_range_beacon;
//  - Mahalanobis gate: fuse only if y^T S^-1 y <= gate_chi2 (y innovation, S = H P H^T + R);
//    after reset_after_rejections gated beacons in a row the filter re-initialises from the
//    next beacon fix (the belief had lost track, and the gate would reject forever);
//  - noise floors on every sigma; covariance symmetrised with eigenvalues >= min_variance_m2;
//  - degraded when epochs_since_beacon >= degraded_after_epochs, or when the largest 1-sigma
//    axis of the covariance exceeds degraded_sigma_m;
//  - counters of everything rejected (FilterCounters);
//  - numerical health: a covariance that becomes non-finite (e.g. a beacon fix at an absurd
//    range overflows r^2 sigma_angle^2) is replaced by missing_displacement_sigma_m^2 I and
//    counted in FilterCounters::non_finite_state; health_problem() reports it, and a
//    non-finite or inconsistent belief, so that the caller can stop (the closed loop does).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "losmimo/localization/filter_config.h"
#include "losmimo/localization/filter_counters.h"
#include "losmimo/localization/position/measurements.h"

namespace losmimo::localization {

// Throws std::invalid_argument if the belief is non-finite or its covariance not SPD.
void validate(const Belief& belief);

// The first numerical problem of a belief, or nullopt when it is healthy: a non-finite mean
// ("mean_m(1) = nan") or covariance entry ("cov_m2(0, 2) = inf"), a negative variance
// ("cov_m2(2, 2) = -0.5 < 0") or an asymmetric covariance. Cheap (no factorisation): for a
// check after every epoch; validate() is the strict test (SPD) for inputs.
std::optional<std::string> health_problem(const Belief& belief);

class PositionFilter {
 public:
  virtual ~PositionFilter() = default;

  // One epoch: prediction with the measured displacement, then the beacon if any.
  virtual void step(const Eigen::Vector3d& measured_displacement_m, const std::optional<BeaconMeasurement>& beacon) = 0;
  virtual Belief belief() const = 0;
  virtual const FilterCounters& counters() const = 0;
  virtual FilterKind kind() const = 0;
};

// The filter's health after a step: health_problem(filter.belief()), or, if the state ever
// became non-finite (FilterCounters::non_finite_state), "state became non-finite in N
// epoch(s), covariance reset". nullopt when healthy.
std::optional<std::string> health_problem(const PositionFilter& filter);

// A filter starting from `initial` (validated). `seed` drives the filter's own random generator
// (the particle filter's; the EKF draws no random numbers): equal seeds, equal results, in any
// thread.
std::unique_ptr<PositionFilter> make_filter(FilterKind kind, const FilterConfig& config, const Belief& initial,
                                            std::uint64_t seed);

}  // namespace losmimo::localization
