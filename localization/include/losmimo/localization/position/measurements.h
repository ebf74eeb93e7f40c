#pragma once
// Value types shared by the sensor simulator, the filters, the fusion layer and the rawlogs.
//
// Frame: the BS array frame of placement/scenario.h (origin at the array centre, +x boresight,
// z up), metres and radians.
// Beacon: the UAV at q = (x, y, z) measures
//   range_m       = |q|                         (time of flight)
//   azimuth_rad   = atan2(y, x)                 (direction of departure, in (-pi, pi])
//   elevation_rad = atan2(z, sqrt(x^2 + y^2))   (in [-pi/2, pi/2])
// Dead reckoning: the UAV's measured displacement since the previous epoch (metres).

#include <Eigen/Core>

namespace losmimo::localization {

struct BeaconMeasurement {
  double range_m = 0.0;
  double azimuth_rad = 0.0;
  double elevation_rad = 0.0;
};

// A position belief: mean and covariance in the BS array frame.
struct Belief {
  Eigen::Vector3d mean_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cov_m2 = Eigen::Matrix3d::Identity();
  bool degraded = false;        // beacon timeout or covariance above its threshold
  int epochs_since_beacon = 0;  // epochs since the last fused beacon
};

}  // namespace losmimo::localization
