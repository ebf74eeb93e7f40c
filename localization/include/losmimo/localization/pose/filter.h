#pragma once
// Pose filters: a vehicle with robot-frame odometry ranging to beacons at known positions, the
// problem of MRPT's ro-localization / pf-localization on CObservationBeaconRanges logs. The EKF
// (pose/ekf.h, mrpt::bayes::CKalmanFilterCapable) and the particle filter (pose/particle_filter.h,
// mrpt::bayes::CParticleFilter) share this interface, this configuration and these rules.
//
// State x = (x_m, y_m, z_m, yaw_rad), map frame (odometry_model.h). What is used: odometry
// increments (robot frame, with their covariance) and beacon ranges (range_model.h). No IMU: the
// heading is propagated by the odometry and observed through the ranges only when the sensor sits
// off the robot's origin (sensorLocationOnRobot != 0) and the robot moves; a heading prior
// (InitialPose) is what makes it known at the start, as MRPT's init_PDF_min/max_yaw does.
// The world-frame-displacement position filters of position/filter.h stay what the UAV closed loop uses.
//
// One step() is one epoch: predict with the odometry, then fuse the scans' ranges.
//  - odometry: Sigma_u + diag(min_sigma_displacement_m^2 (x, y, z), min_sigma_yaw_rad^2) is the
//    noise used (a floor: never an odometry better than that; it also keeps Sigma_u invertible,
//    which the particle filter's proposal needs). A non-finite increment or covariance predicts
//    in place with missing_displacement_sigma_m and missing_yaw_sigma_rad (counted in
//    rejected_non_finite_displacement).
//  - ranges: screen_range() (range_model.h) with max_beacon_range_m as the plausibility limit,
//    then the geometry check (predicted distance >= kMinRangeGeometry_m), then a per-reading gate
//    against the prediction: y^2 / (H P H^T + sigma^2) <= range_gate_chi2 (1 dof). Every reading
//    is gated against the same predicted belief, so their order does not matter; the ones that
//    pass are fused together.
//  - sigma of a reading: the scan's std_error_m when use_observation_std (MRPT's
//    beaconRangesUseObservationStd), else noise.sigma_range_m (beaconRangesStd); floored at
//    min_sigma_range_m.
//  - reset: an epoch whose usable readings are all gated counts as a rejected epoch; after
//    reset_after_rejections of them in a row, the position is re-initialised from a range fix of
//    the epoch's usable readings (initial_pose.h), if there are at least min_ranges_for_fix and
//    the fix is consistent; the heading keeps its mean and variance.
//  - health: degraded when epochs_since_beacon >= degraded_after_epochs (an epoch with at least
//    one fused range resets it) or when the largest 1-sigma axis of the position block exceeds
//    degraded_sigma_m; covariance symmetrised with eigenvalues >= min_variance_m2; a non-finite
//    state is counted in non_finite_state (health_problem()).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "losmimo/localization/filter_config.h"
#include "losmimo/localization/filter_counters.h"
#include "losmimo/localization/position/measurements.h"
#include "losmimo/localization/pose/odometry_model.h"
#include "losmimo/localization/pose/range_model.h"

namespace losmimo::localization {

struct PoseFilterConfig {
  // Shared with the position filters: gate_enabled, reset_after_rejections, max_beacon_range_m,
  // degraded_*, the floors, missing_displacement_sigma_m, the particle filter's options, and
  // noise.sigma_range_m as the configured range 1-sigma (noise.sigma_angle_rad and the
  // dead-reckoning fields are not used: odometry brings its own covariance).
  FilterConfig filter;
  bool use_observation_std = false;  // take each scan's std_error_m (beaconRangesUseObservationStd)
  // Gate per reading on y^2 / S; 10.83 is the 1-dof chi-square quantile at p = 0.999.
  double range_gate_chi2 = 10.83;
  double min_sigma_yaw_rad = 1e-5;     // heading floor of the odometry noise, per step
  double missing_yaw_sigma_rad = 0.5;  // heading 1-sigma of a step with non-finite odometry
  int min_ranges_for_fix = 3;          // usable readings a range fix needs (initial_pose.h)
};

// Throws std::invalid_argument naming the first bad field and its value (validate(FilterConfig)
// for the shared part).
void validate(const PoseFilterConfig& config);

struct PoseBelief {
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();  // (x_m, y_m, z_m, yaw_rad), yaw in (-pi, pi]
  Eigen::Matrix4d cov = Eigen::Matrix4d::Identity();
  bool degraded = false;
  int epochs_since_beacon = 0;  // epochs since the last epoch with a fused range

  // The position block as a position Belief (same flags).
  Belief position() const;
};

// The first numerical problem of a pose belief, as health_problem(const Belief&) words it
// ("mean(3) = nan", "cov(0, 3) = inf", ...), or nullopt.
std::optional<std::string> health_problem(const PoseBelief& belief);

// The innovations of an epoch's fused readings against the predicted belief, for residual and
// consistency reports: y_j = r_j - h_j(predicted mean), S_j = H_j P H_j^T + sigma_j^2.
// Averaged over epochs, nis_sum / fused is ~1 for a consistent filter (each reading alone).
// A reading the filter used: in an update, or in the range fix of a reset.
struct FusedRange {
  Eigen::Vector3d beacon_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d sensor_on_robot_m = Eigen::Vector3d::Zero();
  double range_m = 0.0;
};

struct RangeInnovations {
  int fused = 0;                     // readings fused in the update (not a reset's)
  double sum_sq_m2 = 0.0;            // sum of y_j^2
  double nis_sum = 0.0;              // sum of y_j^2 / S_j
  std::vector<FusedRange> readings;  // every reading the epoch used (update or reset fix); gated ones are not here
};

// The 1-sigma a filter assumes for the readings of `scan` (see above).
double range_sigma_m(const PoseFilterConfig& config, const BeaconRangeScan& scan);

class PoseFilter {
 public:
  virtual ~PoseFilter() = default;

  // One epoch: prediction with the odometry, then the ranges of every scan (none: prediction only).
  virtual void step(const OdometryIncrement& odometry, const std::vector<BeaconRangeScan>& scans) = 0;
  virtual PoseBelief belief() const = 0;
  virtual const FilterCounters& counters() const = 0;
  virtual FilterKind kind() const = 0;
  // The last step()'s innovations (zero when it fused no reading, or reset).
  virtual const RangeInnovations& last_innovations() const = 0;
};

// health_problem(filter.belief()) or the non-finite-state count, as for PositionFilter.
std::optional<std::string> health_problem(const PoseFilter& filter);

struct InitialPose;  // initial_pose.h

// A filter over `beacons` starting from `initial` (the EKF from its moments, the particle filter
// from the distribution itself). `seed` drives the particle filter's generator only.
std::unique_ptr<PoseFilter> make_pose_filter(FilterKind kind, const PoseFilterConfig& config, const BeaconMap& beacons,
                                             const InitialPose& initial, std::uint64_t seed);

}  // namespace losmimo::localization
