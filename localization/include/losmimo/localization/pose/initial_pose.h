#pragma once
// The epoch-0 pose of a pose filter (pose/filter.h): a range fix when the first scans allow one,
// else the prior, as MRPT's localization apps start from init_PDF_* (the pose analogue of
// position/initial_belief.h).
//
// Prior: a Gaussian pose (e.g. ro-localization's [OdometryEstimation] pose with a spread) or a
// uniform box (pf-localization's init_PDF_mode = uniform: init_PDF_min/max_x, _y, _z, _yaw).
// Range fix: the usable readings of the epoch-0 scans (range_model.h's screen: each reading is
// counted in `counters` as received, rejected by reason, or fused into the fix) locate the
// sensor point c (range_fix.h), with the prior's moments mapped to c as its prior:
//   c0 = p0 + Rz(yaw0) s,  P0 = P_p + |s_xy|^2 diag(1, 1, 0)
// (whatever the heading, c lies on a circle of radius |s_xy| about p + s_z: a loose, sufficient
// bound on the heading's share, horizontal only).
// It is taken only with >= min_ranges_for_fix usable readings that share one sensor offset s
// (MRPT's setSensorPose writes one offset into every reading), a converged, consistent fix.
// The start distribution is then: yaw from the prior's yaw marginal (box: uniform in
// [min_yaw, max_yaw]; Gaussian: N(mean, var)), c ~ N(fix), independent, and p = c - Rz(yaw) s.
// A single scan says nothing about the heading (unless the offsets differ, which the fix does not
// use); the prior does.
// The particle filter samples this distribution exactly (sample_initial_pose); the EKF starts
// from its moments (moments()), linearised about the mean heading ybar:
//   mean = (c_hat - Rz(ybar) s, ybar),  cov_pp = P_c + g var_yaw g^T,  cov_p,yaw = g var_yaw,
//   g = -dRz/dyaw(ybar) s.
// A box's moments: centre, and width^2 / 12 per axis, uncorrelated.

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <mrpt/random/RandomGenerators.h>

#include "losmimo/localization/filter_config.h"
#include "losmimo/localization/pose/filter.h"
#include "losmimo/localization/pose/range_fix.h"
#include "losmimo/localization/pose/range_model.h"

namespace losmimo::localization {

// Uniform in [min, max] per axis (x_m, y_m, z_m, yaw_rad); min <= max, yaw width <= 2 pi.
struct PoseBox {
  Eigen::Vector4d min = Eigen::Vector4d::Zero();
  Eigen::Vector4d max = Eigen::Vector4d::Zero();
};

using PosePrior = std::variant<PoseBelief, PoseBox>;

// Throws std::invalid_argument naming the bad field: a non-finite or non-SPD Gaussian, or a box
// with min > max, a non-finite bound or a yaw width above 2 pi.
void validate(const PosePrior& prior);

struct SensorFix {
  RangeFix fix;                                                 // of the sensor point c
  Eigen::Vector3d sensor_on_robot_m = Eigen::Vector3d::Zero();  // s
};

struct InitialPose {
  PosePrior prior;
  std::optional<SensorFix> fix;  // the range fix, if taken
  std::string note;              // why no fix was taken, when scans were given
  // The epoch-0 readings (ranges_* fields only): received, rejected by the screen, and fused
  // when the fix is taken. Without a fix the usable ones are left to the filter (give the
  // epoch-0 scans to its first step() with a zero OdometryIncrement to fuse them there).
  FilterCounters counters;
  int usable_ranges_not_fused = 0;
};

// The box's moments, and the start distribution's (header).
PoseBelief moments(const PoseBox& box);
PoseBelief moments(const InitialPose& initial);

// The rule of the header. `prior` is validated (throws as validate()).
InitialPose initial_pose(const std::vector<BeaconRangeScan>& scans, const BeaconMap& beacons,
                         const PoseFilterConfig& config, const PosePrior& prior);
// The prior alone (no scan at epoch 0).
InitialPose initial_pose(const PosePrior& prior);

// One draw from the start distribution (yaw wrapped to (-pi, pi]).
Eigen::Vector4d sample_initial_pose(const InitialPose& initial, mrpt::random::CRandomGenerator& rng);

}  // namespace losmimo::localization
