#pragma once
// The one numeric-differentiation check shared by the fusion tests: central differences of a
// Ceres cost function's residuals against the Jacobians it reports.
//
// Step per parameter: h_i = kRelativeStep * max(1, |x_i|). Error per Jacobian block:
//   max |J_user - J_numeric| <= kJacobianTol * max(1, max |J_numeric|)
// i.e. relative to the block's scale, so that entries that are tiny compared with the rest of
// their block (the depth column of a CSI residual is ~1e-2 of the lateral ones) are judged by
// the block's accuracy, not their own. (Ceres' GradientChecker judges each entry on its own and
// uses Ridders' extrapolation from a 1% step: at 1 km that is a 10 m step, and it reports
// 1.7e-4 "relative" errors on those tiny entries that central differences do not show.)
#include <ceres/ceres.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace losmimo::test_support {

inline constexpr double kRelativeStep = 1e-6;
inline constexpr double kJacobianTol = 1e-6;

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// True when every block's Jacobian matches central differences; log explains a mismatch.
inline bool probe(const ceres::CostFunction& cost, const std::vector<double*>& blocks, std::string* log = nullptr) {
  const int num_residuals = cost.num_residuals();
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  std::vector<RowMajorMatrix> J(sizes.size());
  std::vector<double*> J_ptr(sizes.size());
  for (size_t b = 0; b < sizes.size(); ++b) {
    J[b].resize(num_residuals, sizes[b]);
    J_ptr[b] = J[b].data();
  }
  Eigen::VectorXd r(num_residuals), r_plus(num_residuals), r_minus(num_residuals);
  if (!cost.Evaluate(blocks.data(), r.data(), J_ptr.data())) {
    if (log != nullptr) *log = "Evaluate returned false";
    return false;
  }
  std::ostringstream out;
  bool ok = true;
  for (size_t b = 0; b < sizes.size(); ++b) {
    RowMajorMatrix numeric(num_residuals, sizes[b]);
    for (int i = 0; i < sizes[b]; ++i) {
      double& x = blocks[b][i];
      const double x0 = x;
      const double h = kRelativeStep * std::max(1.0, std::abs(x0));
      x = x0 + h;
      cost.Evaluate(blocks.data(), r_plus.data(), nullptr);
      x = x0 - h;
      cost.Evaluate(blocks.data(), r_minus.data(), nullptr);
      x = x0;
      numeric.col(i) = (r_plus - r_minus) / (2.0 * h);
    }
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    const double error = (J[b] - numeric).cwiseAbs().maxCoeff();
    if (!(error <= kJacobianTol * scale)) {
      ok = false;
      out << "block " << b << ": max error " << error << " (scale " << scale << ")\nuser\n"
          << J[b] << "\nnumeric\n"
          << numeric << "\n";
    }
  }
  if (log != nullptr) *log = out.str();
  return ok;
}

}  // namespace losmimo::test_support
