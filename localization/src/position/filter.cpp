#include "losmimo/localization/position/filter.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/localization/filter_health.h"
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
    fail("belief.cov_m2 asymmetry", (belief.cov_m2 - belief.cov_m2.transpose()).norm(), "symmetric");
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(belief.cov_m2);
  if (llt.info() != Eigen::Success) {
    fail("belief.cov_m2 determinant", belief.cov_m2.determinant(), "positive definite");
  }
}

std::optional<std::string> health_problem(const Belief& belief) {
  return moments_problem<3>(belief.mean_m, belief.cov_m2, "mean_m", "cov_m2");
}

std::optional<std::string> health_problem(const PositionFilter& filter) { return filter_health_problem(filter); }

std::unique_ptr<PositionFilter> make_filter(FilterKind kind, const FilterConfig& config, const Belief& initial,
                                            std::uint64_t seed) {
  return make_filter_of_kind<PositionFilter, EkfPositionFilter, ParticlePositionFilter>(kind, seed, config, initial);
}

}  // namespace losmimo::localization
