#include "losmimo/localization/filter_config.h"

#include "losmimo/placement/common/field_error.h"

namespace losmimo::localization {

std::string to_string(FilterKind kind) { return kind == FilterKind::kEkf ? "ekf" : "pf"; }

FilterKind filter_kind_from_string(const std::string& text) {
  if (text == "ekf") return FilterKind::kEkf;
  if (text == "pf") return FilterKind::kParticle;
  throw std::invalid_argument("localization: filter kind '" + text + "' (must be ekf or pf)");
}

std::string to_string(ResamplingMethod method) {
  switch (method) {
    case ResamplingMethod::kMultinomial:
      return "multinomial";
    case ResamplingMethod::kResidual:
      return "residual";
    case ResamplingMethod::kStratified:
      return "stratified";
    case ResamplingMethod::kSystematic:
      return "systematic";
  }
  return "unknown";
}

ResamplingMethod resampling_method_from_string(const std::string& text) {
  for (const auto method : {ResamplingMethod::kMultinomial, ResamplingMethod::kResidual, ResamplingMethod::kStratified,
                            ResamplingMethod::kSystematic}) {
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

}  // namespace losmimo::localization
