// Centralized solution of eq. 4 (fusion/centralized.h): seeded starts, checked independently.
#include "losmimo/fusion/centralized.h"

#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "losmimo/placement/assignment.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/ura.h"

namespace losmimo::fusion {
namespace {

TEST(TravelStats, TwoUavs_SumsMeansAndSquares) {
  Eigen::Matrix3Xd from(3, 2), to(3, 2);
  from << 0, 0, 0, 0, 0, 0;
  to << 3, 0, 4, 0, 0, 0;  // columns (3,4,0) and (0,0,0)
  const TravelStats t = travel_stats(from, to);
  EXPECT_DOUBLE_EQ(t.total_m, 5.0);
  EXPECT_DOUBLE_EQ(t.mean_m, 2.5);
  EXPECT_DOUBLE_EQ(t.max_m, 5.0);
  EXPECT_DOUBLE_EQ(t.total_squared_m2, 25.0);
  EXPECT_DOUBLE_EQ(t.mean_squared_m2, 12.5);
}

TEST(CentralizedConfig, BadField_ThrowsNamingFieldAndValue) {
  CentralizedConfig c;
  c.mu_growth = 0.5;
  try {
    validate(c);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mu_growth = 0.5"), std::string::npos) << e.what();
  }
  CentralizedConfig a;
  a.target_icn = 1.0;
  EXPECT_THROW(validate(a), std::invalid_argument);
  EXPECT_NO_THROW(validate(CentralizedConfig{}));
}

}  // namespace
}  // namespace losmimo::fusion
