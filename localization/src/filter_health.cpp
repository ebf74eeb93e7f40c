#include "losmimo/localization/filter_health.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace losmimo::localization {

bool is_degraded(const FilterConfig& config, int epochs_since_beacon, const Eigen::Matrix3d& position_cov_m2) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(position_cov_m2, Eigen::EigenvaluesOnly);
  const double max_sigma_m = std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0));
  return epochs_since_beacon >= config.degraded_after_epochs || !(max_sigma_m <= config.degraded_sigma_m);
}

template <int N>
std::optional<std::string> moments_problem(const Eigen::Matrix<double, N, 1>& mean,
                                           const Eigen::Matrix<double, N, N>& cov, const char* mean_name,
                                           const char* cov_name) {
  std::ostringstream msg;
  for (int i = 0; i < N; ++i) {
    if (!std::isfinite(mean(i))) {
      msg << mean_name << "(" << i << ") = " << mean(i);
      return msg.str();
    }
  }
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) {
      if (!std::isfinite(cov(i, j))) {
        msg << cov_name << "(" << i << ", " << j << ") = " << cov(i, j);
        return msg.str();
      }
    }
  }
  for (int i = 0; i < N; ++i) {
    if (cov(i, i) < 0.0) {
      msg << cov_name << "(" << i << ", " << i << ") = " << cov(i, i) << " < 0";
      return msg.str();
    }
  }
  const double asymmetry = (cov - cov.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > 1e-9 * (1.0 + cov.cwiseAbs().maxCoeff())) {
    msg << cov_name << " is asymmetric (max |P - P^T| = " << asymmetry << ")";
    return msg.str();
  }
  return std::nullopt;
}

template std::optional<std::string> moments_problem<3>(const Eigen::Vector3d&, const Eigen::Matrix3d&, const char*,
                                                       const char*);
template std::optional<std::string> moments_problem<4>(const Eigen::Vector4d&, const Eigen::Matrix4d&, const char*,
                                                       const char*);

std::optional<std::string> non_finite_state_problem(const FilterCounters& counters) {
  const std::int64_t n = counters.non_finite_state;
  if (n > 0) return "state became non-finite in " + std::to_string(n) + " epoch(s), covariance reset";
  return std::nullopt;
}

}  // namespace losmimo::localization
