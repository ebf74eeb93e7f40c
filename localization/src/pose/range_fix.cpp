#include "losmimo/localization/pose/range_fix.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "losmimo/localization/pose/range_model.h"

namespace losmimo::localization {

namespace {

constexpr int kMaxIterations = 50;
constexpr int kMaxHalvings = 30;
constexpr double kRelativeStepTolerance = 1e-10;

// The MAP cost of the header at c.
double cost(const std::vector<RangeReading>& readings, const Eigen::Vector3d& c_m, const Eigen::Vector3d& c0_m,
            const Eigen::LLT<Eigen::Matrix3d>& prior_llt) {
  double chi2 = 0.0;
  for (const RangeReading& r : readings) {
    const double y = (r.range_m - (c_m - r.beacon_m).norm()) / r.sigma_m;
    chi2 += y * y;
  }
  const Eigen::Vector3d dc = c_m - c0_m;
  return chi2 + dc.dot(prior_llt.solve(dc));
}

}  // namespace

double chi2_quantile(double dof, double z) {
  const double c = 2.0 / (9.0 * dof);
  return dof * std::pow(1.0 - c + z * std::sqrt(c), 3);
}

namespace {
// Adds the ranges' information J^T J / s^2 at c_m to `info`, and, where given, J (r - h) / s^2 to
// `gradient` and every reading's squared whitened residual to `chi2` (a reading within
// kMinRangeGeometry_m of its beacon has no direction: residual only).
void add_ranges(const std::vector<RangeReading>& readings, const Eigen::Vector3d& c_m, Eigen::Matrix3d& info,
                Eigen::Vector3d* gradient, double* chi2) {
  for (const RangeReading& r : readings) {
    const Eigen::Vector3d d_m = c_m - r.beacon_m;
    const double h_m = d_m.norm();
    if (chi2) {
      const double y = (r.range_m - h_m) / r.sigma_m;
      *chi2 += y * y;
    }
    if (h_m < kMinRangeGeometry_m) continue;
    const Eigen::Vector3d J = d_m / h_m;
    info.noalias() += J * J.transpose() / (r.sigma_m * r.sigma_m);
    if (gradient) *gradient += J * (r.range_m - h_m) / (r.sigma_m * r.sigma_m);
  }
}
}  // namespace

RangeFixResult range_fix(const std::vector<RangeReading>& readings, const Eigen::Vector3d& c0_m,
                         const Eigen::Matrix3d& P0_m2) {
  RangeFixResult out;
  if (readings.empty()) {
    out.problem = "no usable range";
    return out;
  }
  const auto bad = [](const RangeReading& r) {
    return !r.beacon_m.allFinite() || !std::isfinite(r.range_m) || !std::isfinite(r.sigma_m) || !(r.sigma_m > 0.0);
  };
  if (std::any_of(readings.begin(), readings.end(), bad)) {
    out.problem = "a reading is not finite";
    return out;
  }
  const Eigen::LLT<Eigen::Matrix3d> prior_llt(P0_m2);
  if (!c0_m.allFinite() || !P0_m2.allFinite() || prior_llt.info() != Eigen::Success) {
    out.problem = "the prior is not finite and positive definite";
    return out;
  }
  const Eigen::Matrix3d prior_info = prior_llt.solve(Eigen::Matrix3d::Identity());

  Eigen::Vector3d c_m = c0_m;
  double current = cost(readings, c_m, c0_m, prior_llt);
  bool converged = false;
  Eigen::Matrix3d info = prior_info;
  for (int it = 0; it < kMaxIterations && !converged; ++it) {
    // Normal equations of the linearised cost: (P0^-1 + sum J^T J / s^2) dc = gradient.
    info = prior_info;
    Eigen::Vector3d g = prior_info * (c0_m - c_m);
    add_ranges(readings, c_m, info, &g, nullptr);
    const Eigen::LLT<Eigen::Matrix3d> llt(info);
    if (llt.info() != Eigen::Success) break;
    Eigen::Vector3d step_m = llt.solve(g);
    bool improved = false;
    for (int h = 0; h < kMaxHalvings; ++h) {
      const double trial = cost(readings, c_m + step_m, c0_m, prior_llt);
      if (trial <= current) {
        c_m += step_m;
        current = trial;
        improved = true;
        break;
      }
      step_m *= 0.5;
    }
    converged = !improved || step_m.norm() <= kRelativeStepTolerance * (1.0 + c_m.norm());
  }
  // Covariance at the solution (the information of the last linearisation point, refreshed).
  info = prior_info;
  double chi2 = 0.0;
  add_ranges(readings, c_m, info, nullptr, &chi2);
  const Eigen::LLT<Eigen::Matrix3d> llt(info);
  if (!converged || llt.info() != Eigen::Success) {
    out.problem = "multilateration did not converge";
    return out;
  }
  const double limit = chi2_quantile(static_cast<double>(readings.size()), kNormalQuantile999);
  if (!(chi2 <= limit)) {
    std::ostringstream msg;
    msg << "range residuals inconsistent (chi2 = " << chi2 << " > " << limit << ")";
    out.problem = msg.str();
    return out;
  }
  RangeFix fix;
  fix.sensor_m = c_m;
  fix.cov_m2 = llt.solve(Eigen::Matrix3d::Identity());
  fix.cov_m2 = 0.5 * (fix.cov_m2 + fix.cov_m2.transpose()).eval();
  fix.ranges_used = static_cast<int>(readings.size());
  fix.chi2 = chi2;
  if (!fix.sensor_m.allFinite() || !fix.cov_m2.allFinite()) {
    out.problem = "the fix is not finite";
    return out;
  }
  out.fix = fix;
  return out;
}

}  // namespace losmimo::localization
