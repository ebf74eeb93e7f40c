#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "losmimo/placement/experiment/summary.h"

namespace le = losmimo::experiment;

TEST(ExperimentStats, Estimate_MatchesStudentTClosedForm) {
  // 1..10: mean 5.5, sd sqrt(55/6), t_{0.975, 9} = 2.262157
  std::vector<double> v;
  for (int i = 1; i <= 10; ++i) v.push_back(i);
  v.push_back(std::nan(""));  // undefined values are skipped
  const le::Estimate e = le::estimate(v);
  EXPECT_EQ(e.n, 10);
  EXPECT_DOUBLE_EQ(e.mean, 5.5);
  EXPECT_NEAR(e.ci95, 2.262157 * std::sqrt(55.0 / 6.0) / std::sqrt(10.0), 0.003 * e.ci95);
}
