#include "losmimo/placement/stall.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <numeric>
#include <optional>
#include <vector>

#include "lanczos.h"

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

namespace {
// The eigenvector of the smallest eigenvalue of the swarm's Hermitian Gram matrix: n Lanczos
// steps reduce it to a real tridiagonal T = V^H G V (lanczos.h), whose smallest eigenvector s
// (bisection and inverse iteration) gives it as V s: ~4x faster than Eigen's complex Hermitian
// solver at 16 x 16 (bench_placement BM_UavsByRedundancy). An invariant Krylov space (which
// may miss the smallest eigenvalue) takes that solver instead.
Eigen::VectorXcd smallest_eigenvector(const SwarmChannel& channel) {
  thread_local detail::LanczosBasis basis;
  std::optional<detail::DensePlanes> dense;  // the UAVs' Gram matrix is kept dense
  const kernels::GramPlanes G = channel.gram_side() == SwarmChannel::GramSide::kBsAntennas
                                    ? channel.gram_planes()
                                    : dense.emplace(channel.gram()).planes();
  const Eigen::Index k = detail::lanczos(channel.model().kernels(), G, G.n, basis);
  if (k < G.n) return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd>(channel.gram()).eigenvectors().col(0);
  return detail::combine(basis, G.n, detail::smallest_tridiagonal_eigenvector(basis.alpha, basis.beta));
}
}  // namespace

std::vector<int> uavs_by_redundancy(const SwarmChannel& channel) {
  // The left singular vector of sigma_min is H v / sigma_min with v the eigenvector of the
  // smallest eigenvalue of G = H^H H: an Nt x Nt Hermitian problem instead of an SVD of H. On
  // the UAV side (Nr < Nt) the Gram matrix is K = H H^H, whose eigenvector is that vector itself.
  const Eigen::VectorXcd v = smallest_eigenvector(channel);
  const Eigen::VectorXd weight = channel.gram_side() == SwarmChannel::GramSide::kUavs
                                     ? Eigen::VectorXd(v.cwiseAbs2())
                                     : Eigen::VectorXd((channel.H() * v).cwiseAbs2());
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
  // (2 half_grid + 1)^2 candidates, spacing period / (2 half_grid), all evaluated in passes of
  // kernels::kLanes; the centre (offset 0) gives f at the start, from the same passes.
  const double spacing = period_m / (2 * half_grid);
  const int side = 2 * half_grid + 1;
  thread_local Eigen::Matrix3Xd candidates;
  thread_local std::vector<double> f;
  candidates.resize(3, side * side);
  f.resize(static_cast<std::size_t>(side) * side);
  for (int i = -half_grid, c = 0; i <= half_grid; ++i) {
    for (int j = -half_grid; j <= half_grid; ++j, ++c) {
      candidates.col(c) = q_m + Eigen::Vector3d(0.0, i * spacing, j * spacing);
    }
  }
  view.objectives_at(candidates, false, f.data());
  LateralSearch result;
  result.objective_at_start = f[static_cast<std::size_t>(side * half_grid + half_grid)];
  result.best_objective = result.objective_at_start;
  for (int i = -half_grid, c = 0; i <= half_grid; ++i) {
    for (int j = -half_grid; j <= half_grid; ++j, ++c) {
      if (f[static_cast<std::size_t>(c)] < result.best_objective) {
        result.best_objective = f[static_cast<std::size_t>(c)];
        result.offset_m = Eigen::Vector3d(0.0, i * spacing, j * spacing);
      }
    }
  }
  return result;
}

}  // namespace losmimo::placement
