#pragma once
// The error of a swarm's position estimates as the LoS-MIMO channel sees it: what the UAVs
// share, and the swarm's shape. A common lateral translation of every UAV multiplies each row of
// H by a phase and each column by a phase (to first order in t / R), which leaves the singular
// values, and so ICN and capacity, unchanged; a common move along boresight rescales the
// geometry slightly; an independent error of a few centimetres breaks the columns'
// orthogonality. Frame: the BS frame, boresight x (the link axis), lateral y and z; metres.
//
// With e_n = estimate_n - truth_n and r_n the truth's lateral offset (y, z) from the swarm's
// lateral centroid:
//   common_boresight_m  mean over n of e_n,x
//   common_lateral_m    mean over n of (e_n,y, e_n,z)
//   rotation_rad        theta minimising sum_n |e_lat,n - common_lateral - theta J r_n|^2,
//                       J r = (-r_z, r_y) (a small rotation about the boresight axis through the
//                       lateral centroid); 0 when every r_n is 0
//   shape_lateral_m     per UAV, e_lat,n - common_lateral - theta J r_n: the shape residual
// The residuals sum to zero and are orthogonal to J r (least squares): the lateral error splits
// into common, rotation and shape parts whose squares add up.

#include <Eigen/Core>

namespace losmimo::placement {

struct SwarmErrorSplit {
  double common_boresight_m = 0.0;
  Eigen::Vector2d common_lateral_m = Eigen::Vector2d::Zero();
  double rotation_rad = 0.0;
  Eigen::Matrix2Xd shape_lateral_m;
  // sqrt(mean_n |e_lat,n|^2), the whole lateral error, and sqrt(mean_n |shape_lateral_m,n|^2).
  double lateral_rmse_m = 0.0;
  double shape_lateral_rmse_m = 0.0;
};

// std::invalid_argument when the two are not 3 x N of the same N >= 1 or not finite.
SwarmErrorSplit split_swarm_error(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m);

// The split over the epochs of a run: add() one epoch's true and estimated positions (every UAV).
class SwarmShapeAccumulator {
 public:
  void add(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m);
  int epochs() const { return epochs_; }
  // sqrt(mean over epochs of |common_lateral_m|^2); NaN before any epoch.
  double common_lateral_rms_m() const;
  // sqrt(mean over epochs and UAVs of |shape_lateral_m|^2); NaN before any epoch.
  double shape_lateral_rmse_m() const;

 private:
  int epochs_ = 0;
  long long uav_epochs_ = 0;
  double common_sq_ = 0.0, shape_sq_ = 0.0;
};

}  // namespace losmimo::placement
