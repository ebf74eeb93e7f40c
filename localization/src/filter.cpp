#include "losmimo/localization/filter.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/common/field_error.h"
#include "losmimo/localization/ekf_filter.h"
#include "losmimo/localization/particle_filter.h"

namespace losmimo::localization {

namespace {

[[noreturn]] void fail(const std::string& field, double value, const std::string& rule) {
  std::ostringstream msg;
  msg << "localization: " << field << " = " << value << " (must be " << rule << ")";
  throw common::FieldError(field, msg.str());
}

void require_finite_non_negative(const std::string& field, double value) {
  if (!std::isfinite(value) || value < 0.0) fail(field, value, "finite and >= 0");
}

void require_finite_positive(const std::string& field, double value) {
  if (!std::isfinite(value) || value <= 0.0) fail(field, value, "finite and > 0");
}

}  // namespace

std::string to_string(FilterKind kind) { return kind == FilterKind::kEkf ? "ekf" : "pf"; }

FilterKind filter_kind_from_string(const std::string& text) {
  if (text == "ekf") return FilterKind::kEkf;
  if (text == "pf") return FilterKind::kParticle;
  throw std::invalid_argument("localization: filter kind '" + text + "' (must be ekf or pf)");
}

std::string to_string(ResamplingMethod method) {
  switch (method) {
    case ResamplingMethod::kMultinomial: return "multinomial";
    case ResamplingMethod::kResidual: return "residual";
    case ResamplingMethod::kStratified: return "stratified";
    case ResamplingMethod::kSystematic: return "systematic";
  }
  return "unknown";
}

ResamplingMethod resampling_method_from_string(const std::string& text) {
  for (const auto method : {ResamplingMethod::kMultinomial, ResamplingMethod::kResidual,
                            ResamplingMethod::kStratified, ResamplingMethod::kSystematic}) {
    if (to_string(method) == text) return method;
  }
  throw std::invalid_argument("localization: resampling method '" + text +
                              "' (must be multinomial, residual, stratified or systematic)");
}

void validate(const FilterConfig& config) {
  require_finite_non_negative("noise.sigma_range_m", config.noise.sigma_range_m);
  require_finite_non_negative("noise.sigma_angle_rad", config.noise.sigma_angle_rad);
  require_finite_non_negative("noise.dr_sigma_floor_m", config.noise.dr_sigma_floor_m);
  require_finite_non_negative("noise.dr_sigma_fraction", config.noise.dr_sigma_fraction);
  require_finite_positive("gate_chi2", config.gate_chi2);
  require_finite_positive("max_beacon_range_m", config.max_beacon_range_m);
  if (config.reset_after_rejections < 0) {
    fail("reset_after_rejections", config.reset_after_rejections, ">= 0");
  }
  if (config.degraded_after_epochs < 1) {
    fail("degraded_after_epochs", config.degraded_after_epochs, ">= 1");
  }
  require_finite_positive("degraded_sigma_m", config.degraded_sigma_m);
  require_finite_positive("min_sigma_range_m", config.min_sigma_range_m);
  require_finite_positive("min_sigma_angle_rad", config.min_sigma_angle_rad);
  require_finite_positive("min_sigma_displacement_m", config.min_sigma_displacement_m);
  require_finite_positive("min_variance_m2", config.min_variance_m2);
  require_finite_positive("missing_displacement_sigma_m", config.missing_displacement_sigma_m);
  if (config.num_particles < 1) fail("num_particles", config.num_particles, ">= 1");
  if (!std::isfinite(config.ess_threshold) || config.ess_threshold <= 0.0 ||
      config.ess_threshold > 1.0) {
    fail("ess_threshold", config.ess_threshold, "in (0, 1]");
  }
  if (!std::isfinite(config.regularization_bandwidth) || config.regularization_bandwidth < 0.0 ||
      config.regularization_bandwidth >= 1.0) {
    fail("regularization_bandwidth", config.regularization_bandwidth, "in [0, 1)");
  }
}

void validate(const Belief& belief) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(belief.mean_m(i))) {
      fail("belief.mean_m(" + std::to_string(i) + ")", belief.mean_m(i), "finite");
    }
  }
  if (!belief.cov_m2.allFinite()) {
    fail("belief.cov_m2 (a non-finite entry)", belief.cov_m2.sum(), "finite");
  }
  if ((belief.cov_m2 - belief.cov_m2.transpose()).cwiseAbs().maxCoeff() >
      1e-9 * (1.0 + belief.cov_m2.cwiseAbs().maxCoeff())) {
    fail("belief.cov_m2 asymmetry", (belief.cov_m2 - belief.cov_m2.transpose()).norm(),
         "symmetric");
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(belief.cov_m2);
  if (llt.info() != Eigen::Success) {
    fail("belief.cov_m2 determinant", belief.cov_m2.determinant(), "positive definite");
  }
}

std::optional<std::string> health_problem(const Belief& belief) {
  std::ostringstream msg;
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(belief.mean_m(i))) {
      msg << "mean_m(" << i << ") = " << belief.mean_m(i);
      return msg.str();
    }
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!std::isfinite(belief.cov_m2(i, j))) {
        msg << "cov_m2(" << i << ", " << j << ") = " << belief.cov_m2(i, j);
        return msg.str();
      }
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (belief.cov_m2(i, i) < 0.0) {
      msg << "cov_m2(" << i << ", " << i << ") = " << belief.cov_m2(i, i) << " < 0";
      return msg.str();
    }
  }
  const double asymmetry = (belief.cov_m2 - belief.cov_m2.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > 1e-9 * (1.0 + belief.cov_m2.cwiseAbs().maxCoeff())) {
    msg << "cov_m2 is asymmetric (max |P - P^T| = " << asymmetry << ")";
    return msg.str();
  }
  return std::nullopt;
}

std::optional<std::string> health_problem(const PositionFilter& filter) {
  if (std::optional<std::string> problem = health_problem(filter.belief())) return problem;
  const std::int64_t n = filter.counters().non_finite_state;
  if (n > 0) {
    return "state became non-finite in " + std::to_string(n) + " epoch(s), covariance reset";
  }
  return std::nullopt;
}

std::unique_ptr<PositionFilter> make_filter(FilterKind kind, const FilterConfig& config,
                                            const Belief& initial, std::uint64_t seed) {
  switch (kind) {
    case FilterKind::kEkf: return std::make_unique<EkfPositionFilter>(config, initial);
    case FilterKind::kParticle:
      return std::make_unique<ParticlePositionFilter>(config, initial, seed);
  }
  throw std::invalid_argument("localization: unknown filter kind");
}

}  // namespace losmimo::localization
