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

#include <vector>

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

// Degrees of freedom of the shape residual of N UAVs at these true positions: the 2N lateral
// coordinates less the common translation's 2 and, unless every UAV is at one lateral point,
// the rotation's 1 (2N - 3 for N >= 2 distinct UAVs; 0 for one UAV).
int shape_dof(const Eigen::Matrix3Xd& truth_m);

// The split's expected values when every UAV's lateral error is independent, N(0, sigma_m^2) per
// axis (the experiment's Gaussian model), for N UAVs not all at one lateral point:
// E|common_lateral|^2 = 2 sigma^2 / N and E sum_n |shape_n|^2 = shape_dof sigma^2 (the shape
// residual is an orthogonal projection of the 2N errors). std::invalid_argument for N < 1 or a
// negative or non-finite sigma.
struct ExpectedSwarmSplit {
  double common_lateral_rms_m = 0.0;  // sigma sqrt(2 / N)
  double shape_lateral_rmse_m = 0.0;  // sigma sqrt(shape_dof / N), shape_dof = 2N - 3 (0 for N = 1)
};
ExpectedSwarmSplit expected_split_of_independent_errors(int num_uavs, double sigma_m);

// NEES of one epoch's shape residual over its degrees of freedom (1 for consistent beliefs):
// with e the 2N lateral errors (y0, z0, y1, z1, ...), S the block diagonal of the UAVs' lateral
// covariances [m^2] and Q an orthonormal basis of the shape subspace,
// (Q^T e)^T (Q^T S Q)^-1 (Q^T e) / shape_dof, chi-square(shape_dof) / shape_dof for Gaussian
// errors of covariance S. NaN when shape_dof is 0; std::invalid_argument as split_swarm_error,
// or when the covariances are not N symmetric positive definite 2 x 2 matrices.
double shape_nees_per_dof(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m,
                          const std::vector<Eigen::Matrix2d>& lateral_cov_m2);

// The split over the epochs of a run: add() one epoch's true and estimated positions (every UAV).
class SwarmShapeAccumulator {
 public:
  void add(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m);
  // The same, with the estimates' lateral covariances, which the shape NEES needs.
  void add(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m,
           const std::vector<Eigen::Matrix2d>& lateral_cov_m2);
  int epochs() const { return epochs_; }
  // sqrt(mean over epochs of |common_lateral_m|^2); NaN before any epoch.
  double common_lateral_rms_m() const;
  // sqrt(mean over epochs and UAVs of |shape_lateral_m|^2); NaN before any epoch.
  double shape_lateral_rmse_m() const;
  // Mean over the epochs added with covariances of shape_nees_per_dof (an epoch whose
  // covariances shape_nees_per_dof refuses is left out of it); NaN before any.
  double shape_nees_per_dof() const;

 private:
  int epochs_ = 0;
  long long uav_epochs_ = 0;
  double common_sq_ = 0.0, shape_sq_ = 0.0;
  int nees_epochs_ = 0;
  double nees_sum_ = 0.0;
};

}  // namespace losmimo::placement
