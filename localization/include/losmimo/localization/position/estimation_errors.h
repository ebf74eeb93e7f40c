#pragma once
// How far a belief is from the truth: the one NEES and the error sums every estimator report
// (closed loop, mission replay, co-evaluation) is built from.
//
//   e = mean - truth                      [m], BS array frame
//   NEES = e^T P^-1 e                     dimensionless; chi-square with N dof when consistent,
//                                         so its mean is N (3 for a position belief)
//   RMSE = sqrt(sum |e|^2 / n)            3-D
//   lateral RMSE = sqrt(sum (e_y^2 + e_z^2) / n)   across the line of sight (the BS boresight
//                                         is +x), the axes placement is sensitive to.

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "losmimo/localization/position/measurements.h"

namespace losmimo::localization {

// e^T P^-1 e by an LDL^T solve (P symmetric positive semi-definite, N x N).
template <int N>
double nees(const Eigen::Matrix<double, N, 1>& error, const Eigen::Matrix<double, N, N>& cov) {
  return error.dot(cov.ldlt().solve(error));
}
// The NEES of a position belief against the true position.
double nees(const Belief& belief, const Eigen::Vector3d& truth_m);

// Running sums of position errors. Samples are added in call order; merging an accumulator
// adds its sums as they are (a per-epoch accumulator merged into a run's total sums the same
// terms in the same order as adding them one by one to the epoch's, then the epoch's to the total).
class ErrorAccumulator {
 public:
  // A belief: its mean's error and its NEES.
  void add(const Belief& belief, const Eigen::Vector3d& truth_m);
  // A point estimate (no covariance: NEES is not summed, nees_samples() does not grow).
  void add(const Eigen::Vector3d& estimate_m, const Eigen::Vector3d& truth_m);
  ErrorAccumulator& operator+=(const ErrorAccumulator& other);

  long samples() const { return samples_; }
  long nees_samples() const { return nees_samples_; }
  // NaN when there is no sample.
  double rmse_m() const;
  double lateral_rmse_m() const;
  double average_nees() const;
  double sum_squared_m2() const { return sq_m2_; }
  double sum_lateral_squared_m2() const { return lateral_sq_m2_; }
  double sum_nees() const { return nees_; }

 private:
  double sq_m2_ = 0.0;
  double lateral_sq_m2_ = 0.0;
  double nees_ = 0.0;
  long samples_ = 0;
  long nees_samples_ = 0;
};

}  // namespace losmimo::localization
