#include "losmimo/placement/stall.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <numeric>

namespace losmimo::placement {

StallDetector::StallDetector(int window, double min_relative_decrease)
    : window_(window), min_relative_decrease_(min_relative_decrease), history_(window + 1) {}

bool StallDetector::update(double objective) {
  // Ring buffer of the last window + 1 values.
  history_(count_ % (window_ + 1)) = objective;
  ++count_;
  if (count_ <= window_) return false;
  const double oldest = history_(count_ % (window_ + 1));
  return objective > (1.0 - min_relative_decrease_) * oldest;
}

void StallDetector::reset() { count_ = 0; }

std::vector<int> uavs_by_redundancy(const SwarmChannel& channel) {
  // The left singular vector of sigma_min is H v / sigma_min with v the eigenvector of the
  // smallest eigenvalue of G = H^H H: an Nt x Nt Hermitian problem instead of an SVD of H. On
  // the UAV side (Nr < Nt) the Gram matrix is K = H H^H, whose eigenvector is that vector itself.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(channel.gram());
  const Eigen::VectorXd weight = channel.gram_side() == SwarmChannel::GramSide::kUavs
                                     ? Eigen::VectorXd(eig.eigenvectors().col(0).cwiseAbs2())
                                     : Eigen::VectorXd((channel.H() * eig.eigenvectors().col(0)).cwiseAbs2());
  std::vector<int> order(weight.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return weight(a) > weight(b); });
  return order;
}

double lateral_period_m(double wavelength_m, double depth_m, double bs_spacing_m) {
  return wavelength_m * depth_m / bs_spacing_m;
}

LateralSearch search_lateral_period(const UavObjective& view, const Eigen::Vector3d& q_m, double period_m,
                                    int half_grid) {
  // (2 half_grid + 1)^2 candidates, spacing period / (2 half_grid)
  const double spacing = period_m / (2 * half_grid);
  LateralSearch result;
  result.objective_at_start = view.objective_at(q_m);
  result.best_objective = result.objective_at_start;
  for (int i = -half_grid; i <= half_grid; ++i) {
    for (int j = -half_grid; j <= half_grid; ++j) {
      const Eigen::Vector3d offset(0.0, i * spacing, j * spacing);
      const double f = view.objective_at(q_m + offset);
      if (f < result.best_objective) {
        result.best_objective = f;
        result.offset_m = offset;
      }
    }
  }
  return result;
}

}  // namespace losmimo::placement
