// Derivatives of every Ceres residual (fusion/cost_functors.h) and of the centralized penalty
// (fusion/centralized.h) against numeric differentiation; a wrong Jacobian must be caught.
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

TEST(PositionPriorCost, Jacobian_MatchesNumericAtRandomPoints) {
  std::mt19937_64 rng(21);
  std::normal_distribution<double> n01;
  for (int i = 0; i < kNumPoints; ++i) {
    Eigen::Matrix3d A;
    for (int k = 0; k < 9; ++k) A(k) = n01(rng);
    const Eigen::Matrix3d cov = A * A.transpose() + 0.01 * Eigen::Matrix3d::Identity();
    const std::unique_ptr<ceres::CostFunction> cost(
        PositionPriorCost::Create(random_uav_position(rng), cov));
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
    const std::unique_ptr<ceres::CostFunction> cost(BeaconCost::Create(
        q_meas.norm(), std::atan2(q_meas.y(), q_meas.x()),
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
  const std::unique_ptr<ceres::CostFunction> cost(
      BeaconCost::Create(100.0, -M_PI + 1e-4, 0.0, 1.0, 1e-3));
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
    const std::unique_ptr<ceres::CostFunction> cost(CsiPhaseCost::Create(
        phases_of(c), model.antennas_m(), model.wavenumber_rad_per_m(), sigma));
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
  const std::unique_ptr<ceres::CostFunction> cost(CsiPhaseCost::Create(
      phases_of(c), model.antennas_m(), model.wavenumber_rad_per_m(), sigma));
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
Eigen::Matrix3Xd numeric_gradient(const placement::ChannelModel& model,
                                  const Eigen::Matrix3Xd& start, double mu,
                                  const Eigen::Matrix3Xd& q, double step_m) {
  Eigen::Matrix3Xd g(3, q.cols());
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    Eigen::Matrix3Xd plus = q, minus = q;
    plus(i) += step_m;
    minus(i) -= step_m;
    g(i) = (penalized_travel_cost(model, start, mu, plus, nullptr) -
            penalized_travel_cost(model, start, mu, minus, nullptr)) / (2.0 * step_m);
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
    const double expected =
        (q - start).squaredNorm() + kMu * placement::objective(model.matrix(q));
    EXPECT_NEAR(cost, expected, 1e-8 * expected);
    const Eigen::Matrix3Xd numeric = numeric_gradient(model, start, kMu, q, kStep_m);
    EXPECT_LT((grad - numeric).norm(), 1e-5 * numeric.norm())
        << "analytic\n" << grad << "\nnumeric\n" << numeric;
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
    EXPECT_LT((grad - numeric).norm(), 1e-5 * numeric.norm())
        << "analytic\n" << grad << "\nnumeric\n" << numeric;
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
