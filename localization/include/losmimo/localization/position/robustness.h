#pragma once
// Building blocks shared by both filters: the checks, gates, floors and health rules that
// filter.h lists. Pure functions plus one small tracker, so each rule is tested on its own.

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "losmimo/localization/filter_health.h"
#include "losmimo/localization/position/filter.h"
#include "losmimo/localization/position/measurements.h"

namespace losmimo::localization {

bool is_finite(const BeaconMeasurement& z);

// Per-axis dead-reckoning 1-sigma for a displacement of length distance_m:
// max(dr_sigma_floor_m + dr_sigma_fraction * distance_m, min_sigma_displacement_m).
double displacement_sigma_m(const FilterConfig& config, double distance_m);

// The displacement an epoch predicts with and its per-axis sigma: the reading itself, or, when
// it is not finite, zero with missing_displacement_sigma_m (counted in `counters`).
struct ScreenedDisplacement {
  Eigen::Vector3d u_m = Eigen::Vector3d::Zero();
  double sigma_m = 0.0;
};
ScreenedDisplacement screen_displacement(const FilterConfig& config, const Eigen::Vector3d& measured_m,
                                         FilterCounters& counters);

// Floored beacon noise covariance R.
Eigen::Matrix3d floored_beacon_cov(const FilterConfig& config);

// Squared Mahalanobis distance y^T S^-1 y (S SPD; Cholesky solve).
double mahalanobis2(const Eigen::Vector3d& y, const Eigen::Matrix3d& S);

// make_spd(), the covariance floor, is filter_health.h's (shared with the pose filters).

// The beacon fix the reset rule re-initialises from (beacon_fix() with the floored sigmas).
Belief floored_beacon_fix(const FilterConfig& config, const BeaconMeasurement& z);

// True when a finite beacon is physically possible: 0 < range_m <= max_beacon_range_m and
// |wrap_angle_rad(elevation_rad)| <= pi/2. Every finite azimuth is a direction once wrapped,
// as the innovation and the beacon fix wrap it, so the azimuth is not checked.
bool is_plausible(const FilterConfig& config, const BeaconMeasurement& z);

// The outcome of screening one beacon against a predicted belief.
enum class BeaconVerdict { kNone, kNonFinite, kOutOfRange, kGeometry, kGated, kFuse, kReset };

// Screens the beacon (finite, physically plausible, geometry, gate, reset rule) and updates
// the counters and the consecutive-rejection count. predicted_mean_m/predicted_cov_m2: the
// belief after prediction. Only the gate touches consecutive_gated: a non-finite, implausible
// or badly placed beacon leaves it as it was, as an epoch without a beacon does.
BeaconVerdict screen_beacon(const FilterConfig& config, const std::optional<BeaconMeasurement>& beacon,
                            const Eigen::Vector3d& predicted_mean_m, const Eigen::Matrix3d& predicted_cov_m2,
                            int& consecutive_gated, FilterCounters& counters);

// Sets degraded and epochs_since_beacon of a belief from the health rules of filter.h.
void apply_health(const FilterConfig& config, int epochs_since_beacon, Belief& belief);

}  // namespace losmimo::localization
