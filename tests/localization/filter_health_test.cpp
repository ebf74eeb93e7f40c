// Numerical health of the filters (issue 8): health_problem() names the first non-finite or
// inconsistent part of a belief, and a filter whose state became non-finite says so.
#include <gtest/gtest.h>

#include <limits>
#include <optional>
#include <string>

#include "losmimo/localization/filter.h"

namespace losmimo::localization {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Belief healthy_belief() {
  Belief b;
  b.mean_m = Eigen::Vector3d(1000.0, 2.0, 30.0);
  b.cov_m2 << 0.04, 0.01, 0.0, 0.01, 0.09, 0.005, 0.0, 0.005, 0.0225;
  return b;
}

std::string problem_of(const Belief& b) {
  const std::optional<std::string> p = health_problem(b);
  return p ? *p : std::string("healthy");
}

TEST(BeliefHealth, HealthyBelief_HasNoProblem) {
  EXPECT_EQ(problem_of(healthy_belief()), "healthy");
  Belief zero_variance = healthy_belief();  // PSD-ish is enough: a zero variance is no fault
  zero_variance.cov_m2.setZero();
  EXPECT_EQ(problem_of(zero_variance), "healthy");
}

TEST(BeliefHealth, NonFiniteMean_IsNamedWithItsAxis) {
  Belief b = healthy_belief();
  b.mean_m(1) = kNan;
  EXPECT_EQ(problem_of(b), "mean_m(1) = nan");
  b.mean_m(1) = 2.0;
  b.mean_m(2) = -kInf;
  EXPECT_EQ(problem_of(b), "mean_m(2) = -inf");
}

TEST(BeliefHealth, NonFiniteCovariance_IsNamedWithItsEntry) {
  Belief b = healthy_belief();
  b.cov_m2(0, 2) = kInf;
  b.cov_m2(2, 0) = kInf;
  EXPECT_EQ(problem_of(b), "cov_m2(0, 2) = inf");
  b = healthy_belief();
  b.cov_m2(1, 1) = kNan;
  EXPECT_EQ(problem_of(b), "cov_m2(1, 1) = nan");
}

TEST(BeliefHealth, NegativeVarianceAndAsymmetry_AreReported) {
  Belief b = healthy_belief();
  b.cov_m2(2, 2) = -0.5;
  EXPECT_EQ(problem_of(b), "cov_m2(2, 2) = -0.5 < 0");
  b = healthy_belief();
  b.cov_m2(0, 1) = 0.02;  // (1, 0) stays 0.01
  EXPECT_NE(problem_of(b).find("cov_m2 is asymmetric"), std::string::npos) << problem_of(b);
  // Rounding-level asymmetry is not a fault.
  b = healthy_belief();
  b.cov_m2(0, 1) += 1e-15;
  EXPECT_EQ(problem_of(b), "healthy");
}

class FilterHealth : public ::testing::TestWithParam<FilterKind> {};

TEST_P(FilterHealth, NominalEpochs_StayHealthy) {
  // GIVEN: a filter with sane beacons and displacements.
  FilterConfig config;
  config.num_particles = 200;
  auto filter = make_filter(GetParam(), config, healthy_belief(), 7);
  // WHEN
  for (int k = 0; k < 20; ++k) {
    filter->step(Eigen::Vector3d(0.0, 0.01, 0.0), BeaconMeasurement{1000.45, 0.002 + 1e-5 * k, 0.03});
  }
  // THEN
  EXPECT_FALSE(health_problem(*filter).has_value()) << *health_problem(*filter);
  EXPECT_EQ(filter->counters().non_finite_state, 0);
}

TEST_P(FilterHealth, BeaconFixAtAnAbsurdRange_OverflowsTheCovarianceAndIsReported) {
  // GIVEN: a filter without the plausibility screen (max_beacon_range_m opened up to DBL_MAX)
  // that keeps receiving a finite beacon at 1e300 m. The gate rejects it (its Mahalanobis
  // distance is infinite) until the reset rule re-initialises from a beacon fix, whose lateral
  // variance (r sigma_angle)^2 = 1e592 m^2 overflows.
  FilterConfig config;
  config.num_particles = 200;
  config.reset_after_rejections = 3;
  config.max_beacon_range_m = std::numeric_limits<double>::max();
  auto filter = make_filter(GetParam(), config, healthy_belief(), 7);
  const BeaconMeasurement absurd{1e300, 0.002, 0.03};
  // WHEN: the gated epochs: still healthy.
  for (int k = 0; k < config.reset_after_rejections; ++k) {
    filter->step(Eigen::Vector3d::Zero(), absurd);
    ASSERT_FALSE(health_problem(*filter).has_value()) << "epoch " << k << ": " << *health_problem(*filter);
  }
  // ... then the reset.
  filter->step(Eigen::Vector3d::Zero(), absurd);
  // THEN: the filter repaired its covariance (so its belief may look finite) but reports it.
  EXPECT_EQ(filter->counters().resets, 1);
  EXPECT_GE(filter->counters().non_finite_state, 1);
  const std::optional<std::string> problem = health_problem(*filter);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("non-finite"), std::string::npos) << *problem;
}

INSTANTIATE_TEST_SUITE_P(BothFilters, FilterHealth,
                         ::testing::Values(FilterKind::kEkf, FilterKind::kParticle),
                         [](const ::testing::TestParamInfo<FilterKind>& info) {
                           return to_string(info.param);
                         });

}  // namespace
}  // namespace losmimo::localization
