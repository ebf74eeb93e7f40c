// The beacon-range model (range_model.h): its Jacobian against central differences (including a
// sensor offset rotated by the heading), a deliberately wrong Jacobian caught by the same check,
// the beacon map's rules and the per-reading screen.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "losmimo/localization/pose/odometry_model.h"
#include "losmimo/localization/pose/range_model.h"
#include "losmimo/placement/scenario.h"
#include "support/numdiff.h"

namespace losmimo::localization {
namespace {

using test_support::jacobian_mismatch;
using test_support::numeric_jacobian;

constexpr double kPi = 3.14159265358979323846;
constexpr double kJacobianTolerance = 1e-6;
constexpr int kRandomPoints = 300;

Eigen::MatrixXd numeric_range_jacobian(const Eigen::Vector4d& x, const Eigen::Vector3d& s, const Eigen::Vector3d& b) {
  return numeric_jacobian(
      [&](const Eigen::VectorXd& v) { return Eigen::VectorXd::Constant(1, range_predict(Eigen::Vector4d(v), s, b)); },
      x);
}

TEST(RangeModel, Jacobian_MatchesCentralDifferences_WithRotatedSensorOffset) {
  // GIVEN: random poses (all headings), sensor offsets up to 1 m, beacons 0.5..50 m away.
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  for (int k = 0; k < kRandomPoints; ++k) {
    const Eigen::Vector4d x(20.0 * u(rng), 20.0 * u(rng), 2.0 * u(rng), kPi * u(rng));
    const Eigen::Vector3d s(u(rng), u(rng), 0.5 * u(rng));
    const Eigen::Vector3d b = sensor_position_m(x, s) +
                              (0.5 + 49.5 * std::abs(u(rng))) * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Eigen::MatrixXd J = range_jacobian(x, s, b);
    EXPECT_LT(jacobian_mismatch(J, numeric_range_jacobian(x, s, b)), kJacobianTolerance)
        << "x = " << x.transpose() << ", s = " << s.transpose();
    ++checked;
  }
  EXPECT_EQ(checked, kRandomPoints);
}

TEST(RangeModel, Jacobian_NearDegenerateGeometryStillMatches) {
  // A beacon 1 cm from the sensor, and one straight above it (e_x = e_y = 0: no heading term).
  const Eigen::Vector4d x(1.0, 2.0, 0.0, 0.7);
  const Eigen::Vector3d s(0.3, -0.2, 0.4);
  const Eigen::Vector3d c = sensor_position_m(x, s);
  for (const Eigen::Vector3d& b : {Eigen::Vector3d(c + Eigen::Vector3d(0.006, -0.008, 0.0)),
                                   Eigen::Vector3d(c + Eigen::Vector3d(0.0, 0.0, 5.0))}) {
    EXPECT_LT(jacobian_mismatch(range_jacobian(x, s, b), numeric_jacobian(
                                                             [&](const Eigen::VectorXd& v) {
                                                               return Eigen::VectorXd::Constant(
                                                                   1, range_predict(Eigen::Vector4d(v), s, b));
                                                             },
                                                             x, 1e-8)),
              1e-5);
  }
  // At the beacon itself the Jacobian is defined as zero (the filters reject the reading).
  EXPECT_EQ(range_jacobian(x, s, c), Eigen::RowVector4d::Zero());
}

TEST(RangeModel, WrongJacobian_UnrotatedSensorOffset_IsCaught) {
  // The slip the test must catch: the heading term computed with the offset as if yaw were 0
  // (e^T dRz/dyaw(0) s instead of e^T dRz/dyaw(yaw) s).
  const Eigen::Vector4d x(3.0, -4.0, 0.0, 2.0);
  const Eigen::Vector3d s(0.5, 0.2, 0.3);
  const Eigen::Vector3d b(10.0, 3.0, 2.0);
  Eigen::RowVector4d wrong = range_jacobian(x, s, b);
  const Eigen::Vector3d e = (sensor_position_m(x, s) - b).normalized();
  wrong(kPoseYaw) = e.x() * (-s.y()) + e.y() * s.x();
  EXPECT_GT(jacobian_mismatch(wrong, numeric_range_jacobian(x, s, b)), 100.0 * kJacobianTolerance);
}

TEST(RangeModel, SensorPosition_RotatesTheOffsetByTheHeading) {
  const Eigen::Vector3d c = sensor_position_m({1.0, 2.0, 3.0, kPi / 2.0}, {0.5, 0.0, 0.1});
  EXPECT_NEAR(c.x(), 1.0, 1e-15);
  EXPECT_NEAR(c.y(), 2.5, 1e-15);
  EXPECT_NEAR(c.z(), 3.1, 1e-15);
}

TEST(BeaconMap, RejectsInvalidIdDuplicateAndNonFinitePosition_NamingThem) {
  BeaconMap map;
  map.add(3, {1.0, 2.0, 0.0});
  EXPECT_EQ(*map.find(3), Eigen::Vector3d(1.0, 2.0, 0.0));
  EXPECT_EQ(map.find(4), nullptr);
  const auto message = [&](std::int32_t id, const Eigen::Vector3d& p) {
    try {
      map.add(id, p);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  EXPECT_NE(message(kInvalidBeaconId, {0.0, 0.0, 0.0}).find("beacon_id = -1"), std::string::npos);
  EXPECT_NE(message(3, {0.0, 0.0, 0.0}).find("beacon_id = 3"), std::string::npos);
  EXPECT_NE(message(5, {std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0}).find("must be finite"), std::string::npos);
  EXPECT_EQ(map.size(), 1U);
}

TEST(BeaconMap, BsAntennas_AreTheScenarioAntennaPositions) {
  const placement::Scenario scenario;
  const BeaconMap map = bs_antenna_beacon_map(scenario);
  const Eigen::Matrix3Xd antennas_m = placement::bs_antenna_positions_m(scenario);
  ASSERT_EQ(map.size(), static_cast<std::size_t>(scenario.num_bs_antennas()));
  for (int m = 0; m < scenario.num_bs_antennas(); ++m) EXPECT_EQ(*map.find(m), Eigen::Vector3d(antennas_m.col(m)));
}

TEST(RangeScreen, EachReasonInOrder) {
  BeaconMap map;
  map.add(1, {0.0, 0.0, 0.0});
  BeaconRangeScan scan;
  scan.min_sensor_distance_m = 0.5;
  scan.max_sensor_distance_m = 30.0;
  const double sigma_m = 0.01;
  const double max_plausible_m = 20.0;
  const auto verdict = [&](std::int32_t id, double range_m, double sigma = 0.01) {
    return screen_range({id, range_m, Eigen::Vector3d::Zero()}, scan, map, sigma, max_plausible_m);
  };
  EXPECT_EQ(verdict(1, 5.0), RangeVerdict::kUsable);
  EXPECT_EQ(verdict(1, std::numeric_limits<double>::quiet_NaN()), RangeVerdict::kNonFinite);
  EXPECT_EQ(verdict(1, 0.0), RangeVerdict::kNonFinite);  // a dropout, not a distance
  EXPECT_EQ(verdict(1, 5.0, std::numeric_limits<double>::quiet_NaN()), RangeVerdict::kNonFinite);
  EXPECT_EQ(verdict(99, std::numeric_limits<double>::infinity()), RangeVerdict::kNonFinite);  // first reason wins
  EXPECT_EQ(verdict(99, 5.0), RangeVerdict::kUnknownBeacon);
  EXPECT_EQ(verdict(kInvalidBeaconId, 5.0), RangeVerdict::kUnknownBeacon);
  EXPECT_EQ(verdict(1, 0.4), RangeVerdict::kOutsideSensorLimits);
  EXPECT_EQ(verdict(1, 31.0), RangeVerdict::kOutsideSensorLimits);
  EXPECT_EQ(verdict(1, 25.0), RangeVerdict::kImplausible);
  EXPECT_EQ(verdict(1, sigma_m + 0.5), RangeVerdict::kUsable);  // limits inclusive
  scan.max_sensor_distance_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(verdict(1, 5.0), RangeVerdict::kOutsideSensorLimits);

  FilterCounters counters;
  count_rejection(RangeVerdict::kUnknownBeacon, counters);
  count_rejection(RangeVerdict::kOutsideSensorLimits, counters);
  count_rejection(RangeVerdict::kUsable, counters);
  EXPECT_EQ(counters.rejected_unknown_beacon, 1);
  EXPECT_EQ(counters.rejected_outside_sensor_limits, 1);
  EXPECT_EQ(counters.rejected_ranges(), 2);
  EXPECT_EQ(counters.rejected_total(), 2);
}

}  // namespace
}  // namespace losmimo::localization
