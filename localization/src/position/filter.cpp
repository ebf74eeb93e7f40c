#include "losmimo/localization/position/filter.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/common/field_error.h"
#include "losmimo/localization/position/ekf.h"
#include "losmimo/localization/position/particle_filter.h"

namespace losmimo::localization {

namespace {

[[noreturn]] void fail(const std::string& field, double value, const std::string& rule) {
  std::ostringstream msg;
  msg << "localization: " << field << " = " << value << " (must be " << rule << ")";
  throw common::FieldError(field, msg.str());
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
  namespace r = filter_range;
  const auto require = [](const common::Range& range, double value, const char* field) {
    common::require_field_in(range, value, "filter", field);
  };
  require(r::sigma, config.noise.sigma_range_m, "noise.sigma_range_m");
  require(r::sigma, config.noise.sigma_angle_rad, "noise.sigma_angle_rad");
  require(r::sigma, config.noise.dr_sigma_floor_m, "noise.dr_sigma_floor_m");
  require(r::sigma, config.noise.dr_sigma_fraction, "noise.dr_sigma_fraction");
  require(r::gate_chi2, config.gate_chi2, "gate_chi2");
  require(r::max_beacon_range_m, config.max_beacon_range_m, "max_beacon_range_m");
  require(r::reset_after_rejections, config.reset_after_rejections, "reset_after_rejections");
  require(r::degraded_after_epochs, config.degraded_after_epochs, "degraded_after_epochs");
  require(r::positive, config.degraded_sigma_m, "degraded_sigma_m");
  require(r::positive, config.min_sigma_range_m, "min_sigma_range_m");
  require(r::positive, config.min_sigma_angle_rad, "min_sigma_angle_rad");
  require(r::positive, config.min_sigma_displacement_m, "min_sigma_displacement_m");
  require(r::positive, config.min_variance_m2, "min_variance_m2");
  require(r::positive, config.missing_displacement_sigma_m, "missing_displacement_sigma_m");
  require(r::num_particles, config.num_particles, "num_particles");
  require(r::ess_threshold, config.ess_threshold, "ess_threshold");
  require(r::regularization_bandwidth, config.regularization_bandwidth, "regularization_bandwidth");
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

FilterCounters& FilterCounters::operator+=(const FilterCounters& o) {
  epochs += o.epochs;
  beacons_received += o.beacons_received;
  beacons_fused += o.beacons_fused;
  rejected_non_finite_displacement += o.rejected_non_finite_displacement;
  rejected_non_finite_beacon += o.rejected_non_finite_beacon;
  rejected_out_of_range_beacon += o.rejected_out_of_range_beacon;
  rejected_geometry += o.rejected_geometry;
  rejected_gate += o.rejected_gate;
  resets += o.resets;
  covariance_repairs += o.covariance_repairs;
  resamplings += o.resamplings;
  non_finite_state += o.non_finite_state;
  ranges_received += o.ranges_received;
  ranges_fused += o.ranges_fused;
  rejected_non_finite_range += o.rejected_non_finite_range;
  rejected_unknown_beacon += o.rejected_unknown_beacon;
  rejected_outside_sensor_limits += o.rejected_outside_sensor_limits;
  rejected_implausible_range += o.rejected_implausible_range;
  rejected_range_geometry += o.rejected_range_geometry;
  rejected_range_gate += o.rejected_range_gate;
  return *this;
}

}  // namespace losmimo::localization
