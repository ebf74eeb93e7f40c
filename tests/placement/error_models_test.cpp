#include <gtest/gtest.h>

#include <cmath>

#include "losmimo/placement/swarm.h"

namespace lp = losmimo::placement;

namespace {
constexpr int kDraws = 10000;
constexpr double kRelTolerance = 0.05;

double sample_std(const std::vector<double>& v) {
  double mean = 0.0;
  for (const double x : v) mean += x;
  mean /= v.size();
  double ss = 0.0;
  for (const double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / (v.size() - 1));
}
}  // namespace

TEST(ErrorModel, LocalizationError_HasSigmaLocPerAxis) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd q = Eigen::Matrix3Xd::Constant(3, 1, 0.0).colwise() + s.cube_center_m;
  lp::Swarm swarm(model, q, {0.12, 0.0}, 4);
  std::vector<std::vector<double>> err(3);
  for (int i = 0; i < kDraws; ++i) {
    const Eigen::Vector3d e = swarm.estimate_position(0) - q.col(0);
    for (int a = 0; a < 3; ++a) err[a].push_back(e(a));
  }
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(sample_std(err[a]), 0.12, kRelTolerance * 0.12) << a;
  EXPECT_EQ(swarm.true_positions_m(), q);  // estimating does not move the UAV
}

TEST(ErrorModel, ActuationError_HasSigmaActPerAxisAndIsCountedAsFlown) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd q = Eigen::Matrix3Xd::Constant(3, 1, 0.0).colwise() + s.cube_center_m;
  lp::Swarm swarm(model, q, {0.0, 0.07}, 5);
  const Eigen::Vector3d command(0.3, -0.2, 0.1);
  std::vector<std::vector<double>> err(3);
  double flown = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const Eigen::Vector3d before = swarm.true_positions_m().col(0);
    const Eigen::Vector3d actual = swarm.move(0, command, lp::MotionKind::kPlacement);
    EXPECT_EQ(swarm.true_positions_m().col(0), before + actual);
    flown += actual.norm();
    for (int a = 0; a < 3; ++a) err[a].push_back(actual(a) - command(a));
  }
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(sample_std(err[a]), 0.07, kRelTolerance * 0.07) << a;
  EXPECT_NEAR(swarm.placement_distance_m()(0), flown, 1e-9 * flown);
  EXPECT_EQ(swarm.probe_distance_m()(0), 0.0);
}

TEST(ErrorModel, NegativeOrNanSigma_IsRejectedNamingTheField) {
  try {
    lp::validate(lp::ErrorModel{-0.1, 0.0});
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sigma_loc_m"), std::string::npos);
  }
  EXPECT_THROW(lp::validate(lp::ErrorModel{0.0, std::nan("")}), std::invalid_argument);
}
