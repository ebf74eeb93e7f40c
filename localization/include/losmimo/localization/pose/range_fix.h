#pragma once
// Multilateration: where the range sensor is, from one epoch's ranges to mapped beacons and a
// Gaussian prior on that point. The epoch-0 pose (initial_pose.h) and the pose filters' reset
// (pose/robustness.h) take their fixes from here.
//
// Unknown c (the sensor point in the map frame [m]); readings j with beacon b_j, range r_j and
// 1-sigma s_j; prior c ~ N(c0, P0). The fix is the MAP estimate
//   c_hat = argmin  sum_j (r_j - |c - b_j|)^2 / s_j^2  +  (c - c0)^T P0^-1 (c - c0)
// by Gauss-Newton from c0 with step halving, J_j = (c - b_j)^T / |c - b_j|, and its covariance
//   cov = (P0^-1 + sum_j J_j^T J_j / s_j^2)^-1  at c_hat.
// The prior settles what the ranges leave open (beacons in one plane leave the side of the plane
// open; fewer than three leave a circle or a sphere); a wide prior (e.g. a uniform box's
// moments) lets the ranges decide the rest. Consistency: chi2 = sum_j (r_j - |c_hat - b_j|)^2 /
// s_j^2 must not exceed the chi-square quantile at p = 0.999 with as many degrees of freedom as
// readings (a wrong basin, or a bad reading, fails it).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace losmimo::localization {

struct RangeReading {
  Eigen::Vector3d beacon_m = Eigen::Vector3d::Zero();
  double range_m = 0.0;
  double sigma_m = 0.0;  // > 0
};

struct RangeFix {
  Eigen::Vector3d sensor_m = Eigen::Vector3d::Zero();  // c_hat
  Eigen::Matrix3d cov_m2 = Eigen::Matrix3d::Identity();
  int ranges_used = 0;
  double chi2 = 0.0;  // of the range residuals at c_hat
};

struct RangeFixResult {
  std::optional<RangeFix> fix;  // nullopt: not converged, inconsistent or unhealthy
  std::string problem;          // why there is no fix
};

// Requires readings with finite values and sigma_m > 0, c0 finite and P0 SPD (else no fix).
RangeFixResult range_fix(const std::vector<RangeReading>& readings, const Eigen::Vector3d& c0_m,
                         const Eigen::Matrix3d& P0_m2);

// The chi-square quantile with `dof` degrees of freedom at the standard-normal quantile z
// (Wilson-Hilferty; at z = 3.09, p = 0.999, it is 3% above the table at 1 dof, 2% at 3 dof and
// within 0.5% from 10 dof on: a slightly lenient consistency test for few readings).
double chi2_quantile(double dof, double z);
inline constexpr double kNormalQuantile999 = 3.090232306167813;

}  // namespace losmimo::localization
