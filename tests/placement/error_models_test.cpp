#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "losmimo/placement/kernels.h"
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

TEST(ErrorModel, Draws_AreTheCounterBasedStreamOfTheSeed_ComputedByTheScalarReference) {
  // GIVEN a swarm with seed 11 and 0.05 m actuation error, and the scalar reference kernels'
  // normal numbers of stream 11 (a plain std::log / std::cos implementation)
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd q = Eigen::Matrix3Xd::Constant(3, 1, 0.0).colwise() + s.cube_center_m;
  lp::Swarm swarm(model, q, {0.0, 0.05}, 11);
  constexpr int kBlocks = 20;  // 320 numbers: past the swarm's 192-number buffer
  std::vector<double> expected(16 * kBlocks);
  lp::kernels::reference_kernels().normals(11, 0, expected.data(), kBlocks);
  // WHEN it moves 100 times (three numbers per move)
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d actual = swarm.move(0, Eigen::Vector3d::Zero(), lp::MotionKind::kPlacement);
    // THEN move i's error is 0.05 times numbers 3i .. 3i + 2 of the stream
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(actual(a), 0.05 * expected[3 * i + a], 1e-15) << i << " " << a;
  }
}

namespace {
// Four UAVs apart at the scenario's cube centre.
Eigen::Matrix3Xd four_uavs(const lp::Scenario& s) {
  Eigen::Matrix3Xd q = Eigen::Matrix3Xd::Zero(3, 4).colwise() + s.cube_center_m;
  for (int m = 0; m < 4; ++m) q.col(m) += Eigen::Vector3d(0.0, 3.0 * m, -2.0 * m);
  return q;
}
}  // namespace

TEST(ErrorModel, CommonModePart_IsOneOffsetSharedByEveryUavAndEstimate_OnTopOfTheSameIndependentDraws) {
  // GIVEN: two swarms with the same seed and independent sigma, one with a common-mode part.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd q = four_uavs(s);
  lp::ErrorModel plain{0.05, 0.0};
  lp::ErrorModel with_common = plain;
  with_common.sigma_loc_common_m = 0.5;
  lp::Swarm a(model, q, plain, 17), b(model, q, with_common, 17);
  // WHEN: every UAV estimates its position several times.
  std::vector<Eigen::Vector3d> offsets;
  for (int k = 0; k < 5; ++k) {
    for (int m = 0; m < 4; ++m) offsets.push_back(b.estimate_position(m) - a.estimate_position(m));
  }
  // THEN: the difference is one vector for every UAV and estimate (the independent draws are
  // the plain swarm's: the common part has a generator of its own), of the common part's size.
  for (const Eigen::Vector3d& d : offsets) EXPECT_LT((d - offsets.front()).norm(), 1e-12);
  EXPECT_GT(offsets.front().norm(), 1e-3);
  EXPECT_EQ(a.normal_blocks_drawn(), b.normal_blocks_drawn());
}

TEST(ErrorModel, CommonModePart_HasSigmaPerAxisAcrossSeeds_AndLeavesTheShapeExact) {
  // GIVEN: no independent error, a common part of 0.3 m per axis.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::Matrix3Xd q = four_uavs(s);
  lp::ErrorModel errors{0.0, 0.0};
  errors.sigma_loc_common_m = 0.3;
  std::vector<std::vector<double>> err(3);
  for (int seed = 0; seed < 2000; ++seed) {
    lp::Swarm swarm(model, q, errors, static_cast<std::uint64_t>(seed));
    const Eigen::Vector3d e0 = swarm.estimate_position(0) - q.col(0);
    // THEN: every UAV is off by the same vector (nothing but a translation of the swarm).
    for (int m = 1; m < 4; ++m) EXPECT_LT((swarm.estimate_position(m) - q.col(m) - e0).norm(), 1e-9);
    for (int i = 0; i < 3; ++i) err[i].push_back(e0(i));
  }
  // AND: across seeds (runs) the offset is N(0, 0.3^2) per axis (sample std within ~5 sigma of its
  // standard error, 0.3 / sqrt(2 x 2000) = 0.0047 m).
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(sample_std(err[i]), 0.3, 0.025) << i;
  // AND: under rms_3d the 0.3 m is the RMS length of the 3-D offset.
  errors.sigma_convention = lp::SigmaConvention::kRms3d;
  EXPECT_DOUBLE_EQ(errors.axis_sigma_loc_common_m(), 0.3 / std::sqrt(3.0));
}

TEST(ErrorModel, NegativeCommonModeSigma_IsRejectedNamingTheField) {
  lp::ErrorModel errors;
  errors.sigma_loc_common_m = -0.1;
  try {
    lp::validate(errors);
    FAIL() << "accepted a negative sigma_loc_common_m";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("sigma_loc_common_m"), std::string::npos) << e.what();
  }
}
