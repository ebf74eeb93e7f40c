// The beacon model against independent computations: values worked out by hand from the
// header's formulas, MRPT's own spherical coordinates, central differences for both Jacobians,
// the inverse model, angle wrapping, and a Monte Carlo check of the fix covariance.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <mrpt/math/TPoint3D.h>
#include <mrpt/poses/CPose3D.h>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/simulator.h"
#include "support/numdiff.h"

namespace losmimo::localization {
namespace {

using test_support::jacobian_mismatch;
using test_support::numeric_jacobian;

constexpr double kPi = 3.14159265358979323846;
constexpr double kJacobianTolerance = 1e-6;  // relative, central differences at h ~ 1e-6 |x|

Eigen::VectorXd h_of(const Eigen::VectorXd& q) { return beacon_predict(q.head<3>()); }

// Angle-aware difference of two observations (azimuth may cross the +-pi cut).
Eigen::VectorXd observation_diff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return beacon_innovation(a.head<3>(), b.head<3>());
}

std::vector<Eigen::Vector3d> test_points() {
  std::vector<Eigen::Vector3d> points = {
      {1000.0, 0.0, 0.0},      // boresight, 1 km
      {1025.0, -25.0, 25.0},   // corner of the default start cube
      {3.0, 2.0, 0.5},         // close to the array
      {1.5, 0.5, 800.0},       // near-degenerate: almost above the array (rho ~ 1.6 m)
      {-1000.0, 1e-3, -10.0},  // behind the array, azimuth next to the +-pi cut
      {0.0, 500.0, 0.0},       // azimuth exactly pi/2
  };
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1500.0, 1500.0);
  for (int i = 0; i < 20; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  return points;
}

// h(q) worked out by hand from the header: r = |q|, az = atan2(y, x), el = atan2(z, rho),
// rho = sqrt(x^2 + y^2). Pythagorean triples keep r and rho exact; the angles are written as
// the closed form and its decimal value (from a calculator, not from this code).
struct HandValue {
  Eigen::Vector3d q_m;
  double range_m, azimuth_rad, elevation_rad;
};

std::vector<HandValue> hand_values() {
  return {
      // (3, 4, 0): level with the array, off both axes. rho = 5, r = 5;
      // az = atan2(4, 3) = atan(4/3) = 0.9272952180016122; el = atan2(0, 5) = 0.
      {{3.0, 4.0, 0.0}, 5.0, 0.9272952180016122, 0.0},
      // (3, 4, 12): above. rho = 5, r = sqrt(25 + 144) = 13; az = atan(4/3) = 0.9272952180016122;
      // el = atan2(12, 5) = asin(12/13) = 1.176005207095135.
      {{3.0, 4.0, 12.0}, 13.0, 0.9272952180016122, 1.176005207095135},
      // (-6, -8, -7.5): below, behind, third quadrant. rho = 10, r = sqrt(100 + 56.25) = 12.5;
      // az = atan2(-8, -6) = -(pi - atan(8/6)) = -(3.141592653589793 - 0.9272952180016122)
      //    = -2.214297435588181;
      // el = atan2(-7.5, 10) = -atan(0.75) = -asin(0.6) = -0.6435011087932844.
      {{-6.0, -8.0, -7.5}, 12.5, -2.214297435588181, -0.6435011087932844},
      // (1000, 0, 1000): above, on the boresight's vertical plane. rho = 1000,
      // r = 1000 sqrt(2) = 1414.213562373095; az = 0; el = atan2(1000, 1000) = pi/4
      //   = 0.7853981633974483.
      {{1000.0, 0.0, 1000.0}, 1414.213562373095, 0.0, 0.7853981633974483},
      // (-1, 1, -sqrt(2)): below, behind, second quadrant. rho = sqrt(2), r = sqrt(2 + 2) = 2;
      // az = atan2(1, -1) = 3 pi/4 = 2.356194490192345; el = atan2(-sqrt(2), sqrt(2)) = -pi/4
      //   = -0.7853981633974483.
      {{-1.0, 1.0, -std::sqrt(2.0)}, 2.0, 2.356194490192345, -0.7853981633974483},
  };
}

constexpr double kHandTolerance = 1e-12;  // relative for the range, absolute [rad] for angles

TEST(BeaconPredict, HandComputedPointsAboveAndBelowTheArray_RangeAzimuthElevation) {
  for (const HandValue& v : hand_values()) {
    const Eigen::Vector3d z = beacon_predict(v.q_m);
    EXPECT_NEAR(z(0), v.range_m, kHandTolerance * v.range_m) << "q = " << v.q_m.transpose();
    EXPECT_NEAR(z(1), v.azimuth_rad, kHandTolerance) << "q = " << v.q_m.transpose();
    EXPECT_NEAR(z(2), v.elevation_rad, kHandTolerance) << "q = " << v.q_m.transpose();
  }
}

TEST(BeaconPredict, SignAndArgumentSlips_FailTheHandValues) {
  // Negative control: a model returning MRPT's pitch (-el) instead of el, or atan2(x, y)
  // instead of atan2(y, x), misses the hand values by far more than kHandTolerance: the
  // elevation slip at the four points with el != 0, the azimuth slip at all five.
  int elevation_slips_caught = 0, azimuth_slips_caught = 0;
  for (const HandValue& v : hand_values()) {
    const Eigen::Vector3d z = beacon_predict(v.q_m);
    elevation_slips_caught += std::abs(-z(2) - v.elevation_rad) > 0.5;
    azimuth_slips_caught += std::abs(std::atan2(v.q_m.x(), v.q_m.y()) - v.azimuth_rad) > 0.1;
  }
  EXPECT_EQ(elevation_slips_caught, 4);
  EXPECT_EQ(azimuth_slips_caught, 5);
}

TEST(BeaconPredict, AgainstMrptSphericalCoordinates_YawIsAzimuthAndPitchIsMinusElevation) {
  // MRPT's convention (CPose3D::sphericalCoordinates, the model of CObservationBearingRange,
  // whose header calls pitch "negative elevation"): from the identity pose, range = |q|,
  // yaw = atan2(y, x), pitch = -asin(z / range). Ours: the same range and yaw (az), and
  // el = atan2(z, rho) = asin(z / r) = -pitch. The rawlog writer stores pitch = -el for that
  // reason (rawlog/format.h).
  const mrpt::poses::CPose3D bs;  // the array frame itself
  for (const HandValue& v : hand_values()) {
    double range_m = 0.0, yaw_rad = 0.0, pitch_rad = 0.0;
    bs.sphericalCoordinates(mrpt::math::TPoint3D(v.q_m.x(), v.q_m.y(), v.q_m.z()), range_m, yaw_rad, pitch_rad);
    const Eigen::Vector3d z = beacon_predict(v.q_m);
    EXPECT_NEAR(z(0), range_m, kHandTolerance * range_m) << v.q_m.transpose();
    EXPECT_NEAR(z(1), yaw_rad, kHandTolerance) << v.q_m.transpose();
    EXPECT_NEAR(z(2), -pitch_rad, kHandTolerance) << v.q_m.transpose();
    // MRPT itself against the hand values (pitch negated).
    EXPECT_NEAR(yaw_rad, v.azimuth_rad, kHandTolerance) << v.q_m.transpose();
    EXPECT_NEAR(-pitch_rad, v.elevation_rad, kHandTolerance) << v.q_m.transpose();
  }
}

TEST(BeaconJacobian, HandComputedAtAPointAboveTheArray) {
  // At q = (3, 4, 12): rho = 5, r = 13, from the header's rows:
  //   dr/dq  = q^T / r = (3, 4, 12) / 13
  //   daz/dq = (-y, x, 0) / rho^2 = (-4, 3, 0) / 25
  //   del/dq = (-x z / rho, -y z / rho, rho) / r^2 = (-36/5, -48/5, 5) / 169 = (-7.2, -9.6, 5) / 169
  Eigen::Matrix3d expected;
  expected << 3.0 / 13.0, 4.0 / 13.0, 12.0 / 13.0,  //
      -4.0 / 25.0, 3.0 / 25.0, 0.0,                 //
      -7.2 / 169.0, -9.6 / 169.0, 5.0 / 169.0;
  const Eigen::Matrix3d J = beacon_jacobian(Eigen::Vector3d(3.0, 4.0, 12.0));
  EXPECT_LT((J - expected).cwiseAbs().maxCoeff(), 1e-15) << J;
}

TEST(BeaconJacobian, TypicalRandomAndNearDegeneratePoints_MatchCentralDifferences) {
  for (const Eigen::Vector3d& q : test_points()) {
    const Eigen::MatrixXd numeric = numeric_jacobian(h_of, q, 1e-6, observation_diff);
    EXPECT_LT(jacobian_mismatch(beacon_jacobian(q), numeric), kJacobianTolerance) << "q = " << q.transpose();
  }
}

TEST(BeaconJacobian, DeliberatelyWrongJacobian_IsCaught) {
  // Two classic slips: a sign error in d(az)/dx, and rho / r instead of rho / r^2 in d(el)/dz.
  const Eigen::Vector3d q(1025.0, -25.0, 25.0);
  const Eigen::MatrixXd numeric = numeric_jacobian(h_of, q, 1e-6, observation_diff);
  Eigen::Matrix3d sign_slip = beacon_jacobian(q);
  sign_slip(1, 0) = -sign_slip(1, 0);
  EXPECT_GT(jacobian_mismatch(sign_slip, numeric), 1e3 * kJacobianTolerance);
  Eigen::Matrix3d power_slip = beacon_jacobian(q);
  power_slip(2, 2) *= q.norm();
  EXPECT_GT(jacobian_mismatch(power_slip, numeric), 1e3 * kJacobianTolerance);
}

TEST(BeaconInverse, Jacobian_MatchesCentralDifferencesAndInvertsJzq) {
  for (const Eigen::Vector3d& q : test_points()) {
    const Eigen::Vector3d z = beacon_predict(q);
    const auto g = [](const Eigen::VectorXd& zz) -> Eigen::VectorXd { return beacon_to_position(zz.head<3>()); };
    const Eigen::MatrixXd numeric = numeric_jacobian(g, z, 1e-7);
    const Eigen::Matrix3d J_q_z = beacon_to_position_jacobian(z);
    EXPECT_LT(jacobian_mismatch(J_q_z, numeric), kJacobianTolerance) << q.transpose();
    EXPECT_LT((J_q_z * beacon_jacobian(q) - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-9) << q.transpose();
  }
}

TEST(BeaconInverse, PredictThenInvert_ReturnsThePoint) {
  for (const Eigen::Vector3d& q : test_points()) {
    EXPECT_LT((beacon_to_position(beacon_predict(q)) - q).norm(), 1e-9 * (1.0 + q.norm()));
  }
}

TEST(WrapAngle, Values_LandInHalfOpenPiInterval) {
  EXPECT_DOUBLE_EQ(wrap_angle_rad(-kPi), kPi);
  EXPECT_NEAR(wrap_angle_rad(3.0 * kPi), kPi, 1e-12);
  EXPECT_NEAR(wrap_angle_rad(0.5 + 10.0 * kPi), 0.5, 1e-12);
  EXPECT_NEAR(wrap_angle_rad(-0.5 - 4.0 * kPi), -0.5, 1e-12);
}

TEST(WrapAngle, EveryValue_TheBitsOfRemainderFoldedToHalfOpenInterval) {
  // The reference: IEEE remainder by 2 pi, -pi folded to +pi.
  const auto reference = [](double a) {
    double r = std::remainder(a, 2.0 * kPi);
    if (r <= -kPi) r += 2.0 * kPi;
    return r;
  };
  std::vector<double> values = {0.0, -0.0, kPi, -kPi, 2.0 * kPi, -2.0 * kPi, 1e-300, 7.5, -7.5, 1e6, -1e6};
  for (const double edge : {kPi, -kPi}) {
    values.push_back(std::nextafter(edge, 0.0));
    values.push_back(std::nextafter(edge, 10.0 * edge));
  }
  for (int k = -2000; k <= 2000; ++k) values.push_back(0.0031 * k);
  for (const double a : values) {
    const double got = wrap_angle_rad(a);
    const double want = reference(a);
    EXPECT_EQ(std::memcmp(&got, &want, sizeof got), 0) << "angle " << a << ": " << got << " vs " << want;
    EXPECT_TRUE(got > -kPi && got <= kPi) << a;
  }
  EXPECT_TRUE(std::isnan(wrap_angle_rad(std::nan(""))));
}

TEST(BeaconInnovation, AzimuthAcrossPiCut_IsSmall) {
  const Eigen::Vector3d z_meas(1000.0, kPi - 1e-4, 0.0);
  const Eigen::Vector3d z_pred(1000.0, -kPi + 1e-4, 0.0);
  EXPECT_NEAR(beacon_innovation(z_meas, z_pred)(1), -2e-4, 1e-12);
}

TEST(BeaconFix, Covariance_MatchesMonteCarloAt1km) {
  // GIVEN: the default simulator at (1000, 20, 30) m; THEN the first-order fix covariance
  // matches the sample covariance of many beacon-only fixes, and is ~0.1 m per axis.
  constexpr int kSamples = 20000;
  constexpr double kRelTolerance = 0.05;  // ~5 sigma of a variance estimate from 20000 samples
  const SimulatorConfig config;
  SensorSimulator sim(config, 3);
  const Eigen::Vector3d q(1000.0, 20.0, 30.0);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  Belief fix;
  for (int i = 0; i < kSamples; ++i) {
    const auto z = sim.measure_beacon(q, i);
    ASSERT_TRUE(z.has_value());
    fix = beacon_fix(*z, config.sigma_range_m, config.sigma_angle_rad);
    const Eigen::Vector3d e = fix.mean_m - q;
    mean += e / kSamples;
    second += e * e.transpose() / kSamples;
  }
  const Eigen::Matrix3d sample_cov = second - mean * mean.transpose();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sample_cov(i, i), fix.cov_m2(i, i), kRelTolerance * fix.cov_m2(i, i));
    EXPECT_NEAR(std::sqrt(fix.cov_m2(i, i)), 0.1, 0.01);  // the documented default
  }
}

}  // namespace
}  // namespace losmimo::localization
