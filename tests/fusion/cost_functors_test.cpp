// Every Ceres residual (fusion/cost_functors.h, fusion/pose_cost_functors.h) evaluated at a
// chosen point against values worked out by hand from the formula above its functor; their
// derivatives, and those of the centralized penalty (fusion/centralized.h), against numeric
// differentiation; a wrong Jacobian must be caught.
#include "losmimo/fusion/cost_functors.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>

#include <cmath>
#include <complex>
#include <memory>
#include <random>
#include <vector>

#include "losmimo/fusion/centralized.h"
#include "losmimo/fusion/csi.h"
#include "losmimo/fusion/pose_cost_functors.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/ura.h"
#include "fusion/gradient_probe.h"

namespace losmimo::fusion {
namespace {

using test_support::probe;

constexpr int kNumPoints = 20;
constexpr double kNoiseVariance = 0.1;

Eigen::Vector3d random_uav_position(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-25.0, 25.0);
  return Eigen::Vector3d(1000.0 + u(rng), u(rng), u(rng));
}

// ---- Residual values by hand. Each case: the point, the formula's arithmetic in a comment, the
// residuals it gives. Every hand residual is at least kMinHandResidual in size and every sigma
// differs from 1, so a residual with its sign flipped (or the arguments swapped, or the
// 1/sigma dropped) misses by far more than kHandTolerance.
constexpr double kHandTolerance = 1e-10;  // absolute, on residuals of size 0.25 .. 33
constexpr double kMinHandResidual = 0.2;

// Largest |r_i - expected_i| of `cost` at `blocks`; also checks the residual count and that
// the hand values are large enough to tell a sign slip.
double hand_mismatch(const ceres::CostFunction& cost, const std::vector<const double*>& blocks,
                     const Eigen::VectorXd& expected) {
  EXPECT_EQ(cost.num_residuals(), expected.size());
  EXPECT_GE(expected.cwiseAbs().minCoeff(), kMinHandResidual) << expected.transpose();
  Eigen::VectorXd r(cost.num_residuals());
  EXPECT_TRUE(cost.Evaluate(blocks.data(), r.data(), nullptr));
  return (r - expected).cwiseAbs().maxCoeff();
}

TEST(HandResiduals, PositionPrior_WhitenedByTheInverseCholeskyFactor) {
  // cov = [4 2 0; 2 2 0; 0 0 1] = L L^T with L = [2 0 0; 1 1 0; 0 0 1]
  //   (L L^T: row 1 (2,0,0).(2,1,0) = 4, 2; row 2 (1,1,0).(1,1,0) = 2; z: 1),
  // S = L^-1 = [0.5 0 0; -0.5 1 0; 0 0 1] (S L = I).
  // q - mean = (1001, 3.5, -6) - (1000, 2, -3) = (1, 1.5, -3);
  // r = S (1, 1.5, -3) = (0.5 * 1, -0.5 * 1 + 1.5, -3) = (0.5, 1, -3).
  // (Any S' = U S with U orthogonal whitens as well and gives other residuals: the header fixes
  // S = L^-1.)
  const Eigen::Vector3d mean_m(1000.0, 2.0, -3.0);
  Eigen::Matrix3d cov_m2;
  cov_m2 << 4.0, 2.0, 0.0, 2.0, 2.0, 0.0, 0.0, 0.0, 1.0;
  const std::unique_ptr<ceres::CostFunction> cost(PositionPriorCost::Create(mean_m, cov_m2));
  const Eigen::Vector3d q_m(1001.0, 3.5, -6.0);
  EXPECT_LT(hand_mismatch(*cost, {q_m.data()}, Eigen::Vector3d(0.5, 1.0, -3.0)), kHandTolerance);
}

TEST(HandResiduals, Beacon_RangeAzimuthElevationOverTheirSigmas) {
  // q = (3, 4, 12): rho = 5, |q| = 13, atan2(4, 3) = 0.9272952180016122,
  // atan2(12, 5) = 1.176005207095135. Measured (12.5 m, 0.9 rad, 1.2 rad), sigma_range 0.25 m,
  // sigma_angle 0.01 rad:
  //   r0 = (13 - 12.5) / 0.25 = 2
  //   r1 = (0.9272952180016122 - 0.9) / 0.01 = 2.7295218001612165
  //   r2 = (1.176005207095135 - 1.2) / 0.01 = -2.3994792904864948
  const Eigen::Vector3d q_m(3.0, 4.0, 12.0);
  const Eigen::Vector3d expected(2.0, 2.7295218001612165, -2.3994792904864948);
  const std::unique_ptr<ceres::CostFunction> cost(BeaconCost::Create(12.5, 0.9, 1.2, 0.25, 0.01));
  EXPECT_LT(hand_mismatch(*cost, {q_m.data()}, expected), kHandTolerance);
  // The elevation wraps too: measured 1.2 - 2 pi = -5.083185307179586 rad is the same
  // direction; 1.176005207095135 + 5.083185307179586 = 6.259190514274721, wrapped
  // 6.259190514274721 - 2 pi = -0.0239947929048649: the same residuals.
  const std::unique_ptr<ceres::CostFunction> wrapped(BeaconCost::Create(12.5, 0.9, -5.083185307179586, 0.25, 0.01));
  EXPECT_LT(hand_mismatch(*wrapped, {q_m.data()}, expected), kHandTolerance);
}

TEST(HandResiduals, Displacement_FromAToBMinusTheMeasuredOverSigma) {
  // q_b - q_a = (1001.5, 0.5, 2.25) - (1000, 1, 2) = (1.5, -0.5, 0.25); minus d = (1, -0.25,
  // 0.5): (0.5, -0.25, -0.25); over sigma 0.25 m: (2, -1, -1). (a and b swapped would give
  // (-1.5 - 1, 0.5 + 0.25, -0.25 - 0.5) / 0.25 = (-10, 3, -3).)
  const Eigen::Vector3d q_a_m(1000.0, 1.0, 2.0);
  const Eigen::Vector3d q_b_m(1001.5, 0.5, 2.25);
  const std::unique_ptr<ceres::CostFunction> cost(DisplacementCost::Create(Eigen::Vector3d(1.0, -0.25, 0.5), 0.25));
  EXPECT_LT(hand_mismatch(*cost, {q_a_m.data(), q_b_m.data()}, Eigen::Vector3d(2.0, -1.0, -1.0)), kHandTolerance);
}

TEST(HandResiduals, CsiPhase_PathDifferenceTimesWavenumberWrapped) {
  // q = (4, 0, 3), |q| = 5. delta_k = (|p_k|^2 - 2 p_k . q) / (|q - p_k| + |q|), which equals
  // |q - p_k| - |q| (multiply by |q - p_k| + |q|: |q - p_k|^2 - |q|^2 = |p_k|^2 - 2 p_k . q):
  //   p0 = (0, 0, 0): (0 - 0) / (5 + 5) = 0
  //   p1 = (0, 0, 3): |p|^2 = 9, p.q = 9, |q - p| = |(4, 0, 0)| = 4: (9 - 18) / 9 = -1 = 4 - 5
  //   p2 = (4, 0, 0): |p|^2 = 16, p.q = 16, |q - p| = |(0, 0, 3)| = 3: (16 - 32) / 8 = -2 = 3 - 5
  //   p3 = (4, 3, 3): |p|^2 = 34, p.q = 25, |q - p| = |(0, -3, 0)| = 3: (34 - 50) / 8 = -2
  // kappa = 0.3 rad/m, psi = 0.2 rad, arg y = (0.5, 1.0, -3.0, 2.9) rad, sigma 0.1 rad:
  //   r0 = (0.5 + 0 - 0.2) / 0.1 = 3
  //   r1 = (1.0 - 0.3 - 0.2) / 0.1 = 5
  //   r2 = wrap(-3.0 - 0.6 - 0.2) / 0.1 = (-3.8 + 2 pi) / 0.1 = 2.4831853071795864 / 0.1
  //      = 24.831853071795862
  //   r3 = (2.9 - 0.6 - 0.2) / 0.1 = 21
  Eigen::Matrix3Xd antennas_m(3, 4);
  antennas_m << 0.0, 0.0, 4.0, 4.0,  //
      0.0, 0.0, 0.0, 3.0,            //
      0.0, 3.0, 0.0, 3.0;
  const Eigen::Vector4d measured_phase_rad(0.5, 1.0, -3.0, 2.9);
  const std::unique_ptr<ceres::CostFunction> cost(CsiPhaseCost::Create(measured_phase_rad, antennas_m, 0.3, 0.1));
  const Eigen::Vector3d q_m(4.0, 0.0, 3.0);
  const double psi_rad = 0.2;
  EXPECT_LT(hand_mismatch(*cost, {q_m.data(), &psi_rad}, Eigen::Vector4d(3.0, 5.0, 24.831853071795862, 21.0)),
            kHandTolerance);
}

TEST(HandResiduals, PosePrior_YawDifferenceWrapped) {
  // cov = diag(0.25, 4, 1, 0.01): S = diag(2, 0.5, 1, 10).
  // pose - mean = (1.5, 0, 3.25, -3.0) - (1, 2, 3, 3.0) = (0.5, -2, 0.25, -6.0);
  // wrap(-6.0) = -6.0 + 2 pi = 0.28318530717958623;
  // r = (2 * 0.5, 0.5 * -2, 1 * 0.25, 10 * 0.28318530717958623) = (1, -1, 0.25, 2.8318530717958623).
  const Eigen::Vector4d mean(1.0, 2.0, 3.0, 3.0);
  const Eigen::Matrix4d cov = Eigen::Vector4d(0.25, 4.0, 1.0, 0.01).asDiagonal();
  const std::unique_ptr<ceres::CostFunction> cost(PosePriorCost::Create(mean, cov));
  const Eigen::Vector4d pose(1.5, 0.0, 3.25, -3.0);
  EXPECT_LT(hand_mismatch(*cost, {pose.data()}, Eigen::Vector4d(1.0, -1.0, 0.25, 2.8318530717958623)), kHandTolerance);
}

TEST(HandResiduals, Odometry_DisplacementInTheFrameOfA) {
  // a = (1, 2, 0.5, yaw pi/2), b = (0, 4, 1.5, yaw -3.0): (dx, dy) = (-1, 2);
  // Rz(-pi/2) (dx, dy) = (cos dx + sin dy, -sin dx + cos dy) = (0 + 2, 1 + 0) = (2, 1).
  // u = (1.5, 1.25, 0.75, 0.1):
  //   e = (2 - 1.5, 1 - 1.25, (1.5 - 0.5) - 0.75, wrap(-3.0 - pi/2 - 0.1))
  //     = (0.5, -0.25, 0.25, wrap(-4.670796326794896) = -4.670796326794896 + 2 pi = 1.61238898038469).
  // cov = diag(0.01, 0.04, 0.25, 0.0025): S = diag(10, 5, 2, 20):
  //   r = (5, -1.25, 0.5, 32.2477796076938).
  // (The world-frame displacement, unrotated, would give e0 = -1 - 1.5 = -2.5.)
  const Eigen::Vector4d a(1.0, 2.0, 0.5, M_PI / 2.0);
  const Eigen::Vector4d b(0.0, 4.0, 1.5, -3.0);
  const Eigen::Matrix4d cov = Eigen::Vector4d(0.01, 0.04, 0.25, 0.0025).asDiagonal();
  const std::unique_ptr<ceres::CostFunction> cost(OdometryCost::Create(Eigen::Vector4d(1.5, 1.25, 0.75, 0.1), cov));
  EXPECT_LT(hand_mismatch(*cost, {a.data(), b.data()}, Eigen::Vector4d(5.0, -1.25, 0.5, 32.2477796076938)),
            kHandTolerance);
}

TEST(HandResiduals, Range_FromTheSensorRotatedWithTheRobot) {
  // pose (1, 2, 0.5, yaw pi/2), sensor s = (0.5, 0, 0.25) on the robot: Rz(pi/2) s = (0, 0.5,
  // 0.25), c = (1, 2.5, 0.75); beacon (4, 6.5, 0.75): c - b = (-3, -4, 0), |c - b| = 5;
  // range 4.8 m, sigma 0.1 m: r = (5 - 4.8) / 0.1 = 2. (The sensor unrotated, c = (1.5, 2,
  // 0.75), gives |(-2.5, -4.5, 0)| = 5.148 and r = 3.48.)
  const std::unique_ptr<ceres::CostFunction> cost(
      RangeCost::Create(4.8, Eigen::Vector3d(0.5, 0.0, 0.25), Eigen::Vector3d(4.0, 6.5, 0.75), 0.1));
  const Eigen::Vector4d pose(1.0, 2.0, 0.5, M_PI / 2.0);
  Eigen::VectorXd expected(1);
  expected << 2.0;
  EXPECT_LT(hand_mismatch(*cost, {pose.data()}, expected), kHandTolerance);
}

TEST(HandResiduals, SignFlippedExpectation_IsCaught) {
  // Negative control of the comparison itself: the beacon case with every hand value negated
  // (what a cost with the sign flipped would return) misses by 2 |r| >= 2 kMinHandResidual.
  const Eigen::Vector3d q_m(3.0, 4.0, 12.0);
  const std::unique_ptr<ceres::CostFunction> cost(BeaconCost::Create(12.5, 0.9, 1.2, 0.25, 0.01));
  const Eigen::Vector3d flipped = -Eigen::Vector3d(2.0, 2.7295218001612165, -2.3994792904864948);
  EXPECT_GT(hand_mismatch(*cost, {q_m.data()}, flipped), 2.0 * kMinHandResidual);
}

TEST(PositionPriorCost, Jacobian_MatchesNumericAtRandomPoints) {
  std::mt19937_64 rng(21);
  std::normal_distribution<double> n01;
  for (int i = 0; i < kNumPoints; ++i) {
    Eigen::Matrix3d A;
    for (int k = 0; k < 9; ++k) A(k) = n01(rng);
    const Eigen::Matrix3d cov = A * A.transpose() + 0.01 * Eigen::Matrix3d::Identity();
    const std::unique_ptr<ceres::CostFunction> cost(PositionPriorCost::Create(random_uav_position(rng), cov));
    Eigen::Vector3d q = random_uav_position(rng);
    std::string log;
    EXPECT_TRUE(probe(*cost, {q.data()}, &log)) << log;
  }
}

TEST(PositionPriorCost, SquaredResidual_IsMahalanobisDistance) {
  const Eigen::Vector3d mean(1000.0, 1.0, -2.0);
  Eigen::Matrix3d cov;
  cov << 0.5, 0.1, 0.0, 0.1, 0.04, 0.01, 0.0, 0.01, 0.09;
  const std::unique_ptr<ceres::CostFunction> cost(PositionPriorCost::Create(mean, cov));
  const Eigen::Vector3d q(1000.3, 1.2, -2.1);
  Eigen::Vector3d r;
  const std::vector<const double*> blocks = {q.data()};
  ASSERT_TRUE(cost->Evaluate(blocks.data(), r.data(), nullptr));
  const Eigen::Vector3d e = q - mean;
  EXPECT_NEAR(r.squaredNorm(), e.dot(cov.inverse() * e), 1e-9);
}

TEST(PositionPriorCost, IndefiniteCovariance_Throws) {
  const Eigen::Matrix3d bad = Eigen::Vector3d(1.0, -1.0, 1.0).asDiagonal();
  EXPECT_THROW(PositionPriorCost::Create(Eigen::Vector3d::Zero(), bad), std::invalid_argument);
}

TEST(BeaconCost, Jacobian_MatchesNumericAtRandomPoints) {
  std::mt19937_64 rng(22);
  for (int i = 0; i < kNumPoints; ++i) {
    const Eigen::Vector3d q_meas = random_uav_position(rng);
    const std::unique_ptr<ceres::CostFunction> cost(
        BeaconCost::Create(q_meas.norm(), std::atan2(q_meas.y(), q_meas.x()),
                           std::atan2(q_meas.z(), q_meas.head<2>().norm()), 0.5, 1.8e-4));
    Eigen::Vector3d q = q_meas + Eigen::Vector3d(0.3, -0.2, 0.1);
    std::string log;
    EXPECT_TRUE(probe(*cost, {q.data()}, &log)) << log;
  }
}

TEST(BeaconCost, AzimuthAcrossTheCut_ResidualIsWrapped) {
  // A UAV behind the array near azimuth +-pi: measured -pi + 1e-4, true +pi - 1e-4.
  const double az_true = M_PI - 1e-4;
  const Eigen::Vector3d q(100.0 * std::cos(az_true), 100.0 * std::sin(az_true), 0.0);
  const std::unique_ptr<ceres::CostFunction> cost(BeaconCost::Create(100.0, -M_PI + 1e-4, 0.0, 1.0, 1e-3));
  Eigen::Vector3d r;
  const std::vector<const double*> blocks = {q.data()};
  ASSERT_TRUE(cost->Evaluate(blocks.data(), r.data(), nullptr));
  EXPECT_NEAR(r(1), -2e-4 / 1e-3, 1e-6);
}

TEST(DisplacementCost, Jacobian_MatchesNumericAtRandomPoints) {
  std::mt19937_64 rng(23);
  std::normal_distribution<double> n01;
  for (int i = 0; i < kNumPoints; ++i) {
    const Eigen::Vector3d d(n01(rng), n01(rng), n01(rng));
    const std::unique_ptr<ceres::CostFunction> cost(DisplacementCost::Create(d, 0.07));
    Eigen::Vector3d a = random_uav_position(rng);
    Eigen::Vector3d b = random_uav_position(rng);
    std::string log;
    EXPECT_TRUE(probe(*cost, {a.data(), b.data()}, &log)) << log;
  }
}

Eigen::VectorXd phases_of(const CsiMeasurement& c) {
  Eigen::VectorXd phase(c.y.size());
  for (Eigen::Index k = 0; k < c.y.size(); ++k) phase(k) = std::arg(c.y(k));
  return phase;
}

TEST(CsiPhaseCost, Jacobian_MatchesNumericAtRandomPoints) {
  const placement::ChannelModel model(placement::Scenario{});
  std::mt19937_64 rng(24);
  const double sigma = csi_phase_sigma_rad(kNoiseVariance);
  for (int i = 0; i < kNumPoints; ++i) {
    const Eigen::Vector3d q_true = random_uav_position(rng);
    const CsiMeasurement c = simulate_csi(model, q_true, kNoiseVariance, rng);
    const std::unique_ptr<ceres::CostFunction> cost(
        CsiPhaseCost::Create(phases_of(c), model.antennas_m(), model.wavenumber_rad_per_m(), sigma));
    // Near the truth (the residuals stay away from the wrap cut).
    Eigen::Vector3d q = q_true + Eigen::Vector3d(0.5, 0.1, -0.1);
    double psi = csi_reference_phase_rad(model, c, q);
    std::string log;
    EXPECT_TRUE(probe(*cost, {q.data(), &psi}, &log)) << log;
  }
}

TEST(CsiPhaseCost, Residual_MatchesChannelModelPhases) {
  // Independent of the delta_k formula: sigma r_k = wrap(arg y_k - arg(x_k(q) e^{j phi})),
  // phi = psi + kappa |q|, x from placement::ChannelModel::row.
  const placement::ChannelModel model(placement::Scenario{});
  std::mt19937_64 rng(25);
  const Eigen::Vector3d q_true = random_uav_position(rng);
  const CsiMeasurement c = simulate_csi(model, q_true, kNoiseVariance, rng);
  const double sigma = csi_phase_sigma_rad(kNoiseVariance);
  const std::unique_ptr<ceres::CostFunction> cost(
      CsiPhaseCost::Create(phases_of(c), model.antennas_m(), model.wavenumber_rad_per_m(), sigma));
  const Eigen::Vector3d q = q_true + Eigen::Vector3d(0.2, 0.4, -0.3);
  const double psi = 0.7;
  Eigen::VectorXd r(model.num_antennas());
  const std::vector<const double*> blocks = {q.data(), &psi};
  ASSERT_TRUE(cost->Evaluate(blocks.data(), r.data(), nullptr));
  const double phi = psi + std::remainder(model.wavenumber_rad_per_m() * q.norm(), 2.0 * M_PI);
  const Eigen::VectorXcd x = model.row(q);
  for (int k = 0; k < model.num_antennas(); ++k) {
    const double expected = std::arg(c.y(k) * std::conj(x(k) * std::polar(1.0, phi)));
    EXPECT_NEAR(sigma * r(k), expected, 1e-6) << "antenna " << k;
  }
}

// Central differences of a scalar function of the stacked positions.
Eigen::Matrix3Xd numeric_gradient(const placement::ChannelModel& model, const Eigen::Matrix3Xd& start, double mu,
                                  const Eigen::Matrix3Xd& q, double step_m) {
  Eigen::Matrix3Xd g(3, q.cols());
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    Eigen::Matrix3Xd plus = q, minus = q;
    plus(i) += step_m;
    minus(i) -= step_m;
    g(i) = (penalized_travel_cost(model, start, mu, plus, nullptr) -
            penalized_travel_cost(model, start, mu, minus, nullptr)) /
           (2.0 * step_m);
  }
  return g;
}

TEST(PenalizedTravelCost, ValueAndGradient_MatchIndependentComputation) {
  placement::Scenario scenario;
  const placement::ChannelModel model(scenario);
  std::mt19937_64 rng(27);
  constexpr double kMu = 1e-3;
  constexpr double kStep_m = 1e-5;
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::Matrix3Xd start = placement::random_start_positions_m(scenario, rng);
    const Eigen::Matrix3Xd q = placement::random_start_positions_m(scenario, rng);
    Eigen::Matrix3Xd grad;
    const double cost = penalized_travel_cost(model, start, kMu, q, &grad);
    // Value: travel + mu f with f from the full recompute in placement/metrics.h.
    const double expected = (q - start).squaredNorm() + kMu * placement::objective(model.matrix(q));
    EXPECT_NEAR(cost, expected, 1e-8 * expected);
    const Eigen::Matrix3Xd numeric = numeric_gradient(model, start, kMu, q, kStep_m);
    EXPECT_LT((grad - numeric).norm(), 1e-5 * numeric.norm()) << "analytic\n" << grad << "\nnumeric\n" << numeric;
  }
}

TEST(BarrierTravelCost, ValueAndGradient_MatchIndependentComputation) {
  // Near a feasible placement (the rigid URA, ICN ~1, moved a little): B_t is finite, its value
  // matches the ICN from placement's SVD, and its gradient matches central differences.
  placement::Scenario scenario;
  const placement::ChannelModel model(scenario);
  std::mt19937_64 rng(28);
  std::normal_distribution<double> n01;
  constexpr double kAlpha = 0.9;
  constexpr double kT_m2 = 0.5;
  constexpr double kStep_m = 1e-6;
  const Eigen::Matrix3Xd slots = placement::optimal_ura_positions_m(scenario);
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::Matrix3Xd q = slots;
    for (Eigen::Index i = 0; i < q.size(); ++i) q(i) += 0.05 * n01(rng);
    const Eigen::Matrix3Xd start = placement::random_start_positions_m(scenario, rng);
    Eigen::Matrix3Xd grad;
    const double cost = barrier_travel_cost(model, start, kAlpha, kT_m2, q, &grad);
    ASSERT_TRUE(std::isfinite(cost));
    // lambda_min - alpha^2 lambda_max = lambda_max (ICN^2 - alpha^2), lambda_max = sigma_max^2.
    const Eigen::MatrixXcd H = model.matrix(q);
    const double icn = placement::inverse_condition_number(H);
    const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXcd>(H).singularValues();
    const double g = sv(0) * sv(0) * (icn * icn - kAlpha * kAlpha);
    EXPECT_NEAR(cost, (q - start).squaredNorm() - kT_m2 * std::log(g), 1e-8 * std::abs(cost));
    Eigen::Matrix3Xd numeric(3, q.cols());
    for (Eigen::Index i = 0; i < q.size(); ++i) {
      Eigen::Matrix3Xd plus = q, minus = q;
      plus(i) += kStep_m;
      minus(i) -= kStep_m;
      numeric(i) = (barrier_travel_cost(model, start, kAlpha, kT_m2, plus, nullptr) -
                    barrier_travel_cost(model, start, kAlpha, kT_m2, minus, nullptr)) /
                   (2.0 * kStep_m);
    }
    EXPECT_LT((grad - numeric).norm(), 1e-5 * numeric.norm()) << "analytic\n" << grad << "\nnumeric\n" << numeric;
  }
}

TEST(BarrierTravelCost, InfeasiblePlacement_IsInfinite) {
  placement::Scenario scenario;
  const placement::ChannelModel model(scenario);
  std::mt19937_64 rng(29);
  const Eigen::Matrix3Xd q = placement::random_start_positions_m(scenario, rng);  // ICN ~0.1
  ASSERT_LT(placement::inverse_condition_number(model.matrix(q)), 0.5);
  EXPECT_TRUE(std::isinf(barrier_travel_cost(model, q, 0.5, 1.0, q, nullptr)));
}

}  // namespace
}  // namespace losmimo::fusion
