#pragma once
// The health rules both filter families apply to their beliefs (position/filter.h and
// pose/filter.h list them), written once:
//  - covariance repair after every update: a non-finite state is counted
//    (FilterCounters::non_finite_state) and its covariance replaced by
//    missing_displacement_sigma_m^2 I; otherwise P is symmetrised and its eigenvalues raised to
//    min_variance_m2 (counted in covariance_repairs when raised);
//  - degraded: epochs_since_beacon >= degraded_after_epochs, or the largest 1-sigma axis of the
//    position covariance above degraded_sigma_m (a pose filter passes its position block);
//  - health_problem(): the first non-finite mean or covariance entry, negative variance or
//    asymmetric covariance of a belief, then the filter's non-finite-state count.

#include <optional>
#include <string>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "losmimo/localization/filter_config.h"
#include "losmimo/localization/filter_counters.h"

namespace losmimo::localization {

// Symmetrises P and raises its eigenvalues to at least min_variance. Returns true if any
// eigenvalue had to be raised (or P had a non-finite entry, in which case P becomes
// fallback_variance * I).
template <int N>
bool make_spd(Eigen::Matrix<double, N, N>& P, double min_variance, double fallback_variance) {
  using Mat = Eigen::Matrix<double, N, N>;
  if (!P.allFinite()) {
    P = fallback_variance * Mat::Identity();
    return true;
  }
  P = 0.5 * (P + P.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Mat> eig(P);
  const Eigen::Matrix<double, N, 1> lambda = eig.eigenvalues();
  if (lambda.minCoeff() >= min_variance) return false;
  const Eigen::Matrix<double, N, 1> floored = lambda.cwiseMax(min_variance);
  P = eig.eigenvectors() * floored.asDiagonal() * eig.eigenvectors().transpose();
  P = 0.5 * (P + P.transpose()).eval();
  return true;
}

// The variance a non-finite covariance is replaced by: missing_displacement_sigma_m^2.
inline double fallback_variance_m2(const FilterConfig& config) {
  return config.missing_displacement_sigma_m * config.missing_displacement_sigma_m;
}

// The repair after an update (above): counts a non-finite (mean, P) and makes P SPD.
template <int N>
void repair_covariance(const Eigen::Matrix<double, N, 1>& mean, Eigen::Matrix<double, N, N>& P,
                       const FilterConfig& config, FilterCounters& counters) {
  if (!P.allFinite() || !mean.allFinite()) ++counters.non_finite_state;
  if (make_spd<N>(P, config.min_variance_m2, fallback_variance_m2(config))) ++counters.covariance_repairs;
}

// The degraded rule above, from the position covariance [m^2].
bool is_degraded(const FilterConfig& config, int epochs_since_beacon, const Eigen::Matrix3d& position_cov_m2);

// The first numerical problem of a mean and covariance, named as `mean_name`(i) and
// `cov_name`(i, j) ("mean_m(1) = nan", "cov(0, 3) = inf", "cov_m2(2, 2) = -0.5 < 0",
// "cov_m2 is asymmetric (max |P - P^T| = ...)"), or nullopt. Defined for N = 3 and 4.
template <int N>
std::optional<std::string> moments_problem(const Eigen::Matrix<double, N, 1>& mean,
                                           const Eigen::Matrix<double, N, N>& cov, const char* mean_name,
                                           const char* cov_name);

// "state became non-finite in N epoch(s), covariance reset", or nullopt when the count is 0.
std::optional<std::string> non_finite_state_problem(const FilterCounters& counters);

// A filter's health (PositionFilter, PoseFilter): its belief's problem, else its state's.
template <class Filter>
std::optional<std::string> filter_health_problem(const Filter& filter) {
  if (std::optional<std::string> problem = health_problem(filter.belief())) return problem;
  return non_finite_state_problem(filter.counters());
}

}  // namespace losmimo::localization
