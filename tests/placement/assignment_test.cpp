#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "losmimo/placement/assignment.h"

namespace lp = losmimo::placement;

namespace {
double total(const Eigen::MatrixXd& c, const std::vector<int>& a) {
  double t = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) t += c(i, a[i]);
  return t;
}

// Exhaustive search over every injective assignment: the independent reference.
double brute_force_min(const Eigen::MatrixXd& c) {
  std::vector<int> cols(c.cols());
  std::iota(cols.begin(), cols.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    best = std::min(best, total(c, std::vector<int>(cols.begin(), cols.begin() + c.rows())));
  } while (std::next_permutation(cols.begin(), cols.end()));
  return best;
}
}  // namespace

TEST(MinCostAssignment, RandomMatrices_MatchExhaustiveSearch) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 2 + trial % 6;
    const int m = n + trial % 2;
    Eigen::MatrixXd c(n, m);
    for (Eigen::Index i = 0; i < c.size(); ++i) c(i) = u(rng);
    const std::vector<int> a = lp::min_cost_assignment(c);
    std::vector<int> sorted = a;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "columns reused";
    EXPECT_NEAR(total(c, a), brute_force_min(c), 1e-9) << "n=" << n << " m=" << m;
  }
}

TEST(MinCostAssignment, BadShapesAndValues_Throw) {
  EXPECT_THROW(lp::min_cost_assignment(Eigen::MatrixXd::Zero(3, 2)), std::invalid_argument);
  Eigen::MatrixXd c = Eigen::MatrixXd::Ones(2, 2);
  c(1, 1) = std::nan("");
  EXPECT_THROW(lp::min_cost_assignment(c), std::invalid_argument);
}
