// The escapes' building blocks against independent computations: the redundancy order against
// the left singular vector of H's smallest singular value (Eigen's JacobiSVD), and the batched
// lateral search against UavObjective::objective_at point by point.

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>
#include <set>

#include "losmimo/placement/stall.h"
#include "support/scenarios.h"

namespace losmimo::placement {
namespace {

Eigen::Matrix3Xd random_start(const Scenario& s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return random_start_positions_m(s, rng);
}

Scenario with_side(int side) { return test_support::square_array_scenario(side); }

TEST(UavsByRedundancy, OrdersByTheSmallestLeftSingularVector) {
  int separated = 0;
  for (const int side : {2, 4, 8}) {
    const Scenario s = with_side(side);
    const ChannelModel model(s);
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      const SwarmChannel channel(model, random_start(s, seed));
      const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(channel.H(), Eigen::ComputeFullU);
      const Eigen::VectorXd weight = svd.matrixU().col(channel.num_uavs() - 1).cwiseAbs2();
      const Eigen::VectorXd sv2 = svd.singularValues().cwiseAbs2();
      const Eigen::Index n = sv2.size();
      // Only where the smallest eigenvalue of G is separated (its eigenvector well defined)
      if (sv2(n - 2) - sv2(n - 1) < 1e-3 * sv2(0)) continue;
      ++separated;
      const std::vector<int> order = uavs_by_redundancy(channel);
      ASSERT_EQ(static_cast<int>(order.size()), channel.num_uavs());
      EXPECT_EQ(std::set<int>(order.begin(), order.end()).size(), order.size());
      // THEN the weights of the SVD's vector do not increase along the order (ties to 1e-9)
      for (std::size_t i = 1; i < order.size(); ++i) {
        EXPECT_GE(weight(order[i - 1]), weight(order[i]) - 1e-9)
            << "side " << side << " seed " << seed << " rank " << i;
      }
    }
  }
  EXPECT_GE(separated, 10);  // 14 of the 30 channels
}

TEST(UavsByRedundancy, FewerUavsThanAntennas_UsesTheUavsGram) {
  Scenario s = with_side(4);
  s.num_uavs = 5;
  const ChannelModel model(s);
  const SwarmChannel channel(model, random_start(s, 3));
  const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(channel.H(), Eigen::ComputeFullU);
  const Eigen::VectorXd weight = svd.matrixU().col(s.num_uavs - 1).cwiseAbs2();
  const std::vector<int> order = uavs_by_redundancy(channel);
  for (std::size_t i = 1; i < order.size(); ++i) EXPECT_GE(weight(order[i - 1]), weight(order[i]) - 1e-9);
}

TEST(LateralSearch, BatchedGrid_FindsThePointwiseBest) {
  const Scenario s = with_side(4);
  const ChannelModel model(s);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Eigen::Matrix3Xd q = random_start(s, seed);
    const SwarmChannel channel(model, q);
    const UavObjective view(channel, 2);
    const double period = lateral_period_m(s.wavelength_m(), q(0, 2), s.bs_spacing_m);
    const LateralSearch search = search_lateral_period(view, q.col(2), period, 3);
    // The same grid point by point with the single-row form
    const double spacing = period / 6;
    double best = view.objective_at(q.col(2));
    Eigen::Vector3d best_offset = Eigen::Vector3d::Zero();
    for (int i = -3; i <= 3; ++i) {
      for (int j = -3; j <= 3; ++j) {
        const Eigen::Vector3d offset(0.0, i * spacing, j * spacing);
        const double f = view.objective_at(q.col(2) + offset);
        if (f < best) {
          best = f;
          best_offset = offset;
        }
      }
    }
    EXPECT_NEAR(search.objective_at_start, view.objective_at(q.col(2)), 1e-9 * std::abs(search.objective_at_start));
    EXPECT_NEAR(search.best_objective, best, 1e-9 * std::abs(best));
    EXPECT_LT((search.offset_m - best_offset).norm(), 1e-12) << "seed " << seed;
  }
}

}  // namespace
}  // namespace losmimo::placement
