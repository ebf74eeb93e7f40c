// The capacity planner (placement/capacity.h): its gradient against central differences of C
// recomputed from scratch (Eigen's log-determinant of the full matrix; for water-filling an
// independent bisection on the water level over the singular values), with negative controls;
// capacity never decreasing per accepted step; the capacity reached from random starts against
// the orthogonal-rows bound.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <random>

#include "losmimo/placement/capacity.h"
#include "losmimo/placement/metrics.h"
#include "support/numdiff.h"

namespace lp = losmimo::placement;

namespace {

constexpr double kStep_m = 1e-5;
// Central differences err by ~(k h)^2 / 6 relative (k h = 0.013 at 60 GHz: 3e-5) plus the
// rounding of phases ~1e6 rad; a wrong formula errs by O(1).
constexpr double kGradTolerance = 1e-3;
constexpr double kNegativeControlMinError = 0.1;

// C from scratch. Equal power: log2 det(I + a H H^H) by a QR's log-determinant.
double reference_capacity_equal(const Eigen::MatrixXcd& H, double a) {
  const Eigen::MatrixXcd A = Eigen::MatrixXcd::Identity(H.rows(), H.rows()) + a * H * H.adjoint();
  return Eigen::HouseholderQR<Eigen::MatrixXcd>(A).logAbsDeterminant() / std::log(2.0);
}

// Water-filling over the singular values of H with total power Nt: the water level by bisection.
double reference_capacity_waterfill(const Eigen::MatrixXcd& H, double a) {
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXcd>(H).singularValues();
  const Eigen::ArrayXd g = a * s.array().square();
  const double total = static_cast<double>(H.cols());
  double lo = 0.0, hi = total + (1.0 / g.maxCoeff()) + 1e3;
  for (int it = 0; it < 200; ++it) {
    const double mu = 0.5 * (lo + hi);
    double used = 0.0;
    for (Eigen::Index i = 0; i < g.size(); ++i) used += g(i) > 0.0 ? std::max(0.0, mu - 1.0 / g(i)) : 0.0;
    (used > total ? hi : lo) = mu;
  }
  const double mu = 0.5 * (lo + hi);
  double c = 0.0;
  for (Eigen::Index i = 0; i < g.size(); ++i) {
    if (g(i) > 0.0) c += std::log2(1.0 + std::max(0.0, mu - 1.0 / g(i)) * g(i));
  }
  return c;
}

double reference_capacity(const Eigen::MatrixXcd& H, double noise_variance, lp::CapPower power) {
  const double a = 1.0 / noise_variance;
  return power == lp::CapPower::kEqual ? reference_capacity_equal(H, a) : reference_capacity_waterfill(H, a);
}

struct GradientCheck {
  double error = 0.0;          // |analytic - numeric| / |numeric|
  double error_half = 0.0;     // the negative controls: the factor 2 of 2 Re dropped,
  double error_flipped = 0.0;  // the sign flipped (descent instead of ascent)
};

GradientCheck check_gradient(const lp::Scenario& s, const Eigen::Matrix3Xd& q, int m, lp::CapPower power) {
  const lp::ChannelModel model(s);
  const double noise = s.noise_variance();
  const lp::UavCapacity view(model, model.matrix(q), m, noise, power);
  double c = 0.0;
  const Eigen::Vector3d analytic = view.gradient_at(q.col(m), &c);
  const std::function<double(const Eigen::Vector3d&)> f = [&](const Eigen::Vector3d& qm) {
    Eigen::Matrix3Xd moved = q;
    moved.col(m) = qm;
    return reference_capacity(model.matrix(moved), noise, power);
  };
  EXPECT_NEAR(c, f(q.col(m)), 1e-9 * std::abs(c)) << "capacity";
  const Eigen::Vector3d numeric = losmimo::test_support::central_gradient<3>(f, q.col(m), kStep_m);
  const double scale = numeric.norm();
  return {(analytic - numeric).norm() / scale, (0.5 * analytic - numeric).norm() / scale,
          (-analytic - numeric).norm() / scale};
}

lp::Scenario scenario(int rows, int cols, int uavs, lp::GainModel gain) {
  lp::Scenario s;
  s.bs_rows = rows;
  s.bs_cols = cols;
  s.num_uavs = uavs;
  s.gain_model = gain;
  return s;
}

Eigen::Matrix3Xd random_start(const lp::Scenario& s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return lp::random_start_positions_m(s, rng);
}

}  // namespace

TEST(CapacityGradient, RandomAndNearDegeneratePoints_MatchCentralDifferencesOfFullRecompute) {
  double worst = 0.0, best_half = 1e300, best_flipped = 1e300;
  int checks = 0;
  // GIVEN: Nr = Nt, Nr < Nt (the bs_antennas sweep), Nr > Nt; both gain models; both powers
  const struct { int rows, cols, uavs; } shapes[] = {{4, 4, 16}, {4, 4, 4}, {2, 2, 9}, {1, 3, 2}};
  for (const auto& shape : shapes) {
    for (const lp::GainModel gain : {lp::GainModel::kFarField, lp::GainModel::kExact}) {
      for (const lp::CapPower power : {lp::CapPower::kEqual, lp::CapPower::kWaterfill}) {
        const lp::Scenario s = scenario(shape.rows, shape.cols, shape.uavs, gain);
        for (int seed = 0; seed < 3; ++seed) {
          Eigen::Matrix3Xd q = random_start(s, 100 * seed + shape.uavs);
          const int m = seed % s.num_uavs;
          std::vector<Eigen::Matrix3Xd> points = {q};
          if (s.num_uavs > 1) {
            // Near-degenerate: UAV m 1 mm from another UAV (two nearly equal rows).
            Eigen::Matrix3Xd close = q;
            close.col(m) = q.col((m + 1) % s.num_uavs) + Eigen::Vector3d(0.0, 1e-3, 0.0);
            points.push_back(close);
          }
          for (const Eigen::Matrix3Xd& point : points) {
            // WHEN: UAV m's analytic gradient is compared with central differences
            const GradientCheck g = check_gradient(s, point, m, power);
            // THEN: it agrees; the wrong gradients do not
            EXPECT_LT(g.error, kGradTolerance) << shape.uavs << "x" << shape.rows * shape.cols << " " << to_string(gain)
                                               << " " << to_string(power) << " seed " << seed;
            EXPECT_GT(g.error_half, kNegativeControlMinError);
            EXPECT_GT(g.error_flipped, kNegativeControlMinError);
            worst = std::max(worst, g.error);
            best_half = std::min(best_half, g.error_half);
            best_flipped = std::min(best_flipped, g.error_flipped);
            ++checks;
          }
        }
      }
    }
  }
  std::printf(
      "capacity gradient: %d checks, max relative error %.2e; negative controls: halved >= %.3f, "
      "flipped >= %.3f\n",
      checks, worst, best_half, best_flipped);
}

TEST(CapacityGradient, NearOrthogonalRows_MatchCentralDifferences) {
  // GIVEN: a 4 x 4 BS and 16 UAVs near the optimal URA (equal eigenvalues: the water-filling
  // powers are all on and the eigenvectors degenerate), slots lambda R / (4 d) apart
  for (const lp::CapPower power : {lp::CapPower::kEqual, lp::CapPower::kWaterfill}) {
    const lp::Scenario s = scenario(4, 4, 16, lp::GainModel::kFarField);
    const double slot_m = s.wavelength_m() * s.range_m() / (4.0 * s.bs_spacing_m);
    Eigen::Matrix3Xd q(3, 16);
    std::mt19937_64 rng(7);
    std::normal_distribution<double> jitter(0.0, 0.05);
    for (int i = 0; i < 16; ++i) {
      q.col(i) =
          Eigen::Vector3d(s.range_m(), (i % 4 - 1.5) * slot_m + jitter(rng), (i / 4 - 1.5) * slot_m + jitter(rng));
    }
    EXPECT_GT(lp::inverse_condition_number(lp::ChannelModel(s).matrix(q)), 0.8);
    for (const int m : {0, 5, 15}) {
      const GradientCheck g = check_gradient(s, q, m, power);
      EXPECT_LT(g.error, kGradTolerance) << to_string(power) << " UAV " << m;
      EXPECT_GT(g.error_half, kNegativeControlMinError);
    }
  }
}

TEST(Waterfill, Powers_SumToTheTotalAndLevelTheWater) {
  const Eigen::VectorXd gains = (Eigen::VectorXd(4) << 10.0, 0.05, 2.0, 0.0).finished();
  const Eigen::VectorXd p = lp::waterfill_powers(gains, 3.0);
  EXPECT_NEAR(p.sum(), 3.0, 1e-12);
  EXPECT_EQ(p(1), 0.0);  // 1 / 0.05 = 20 is above the water level
  EXPECT_EQ(p(3), 0.0);
  EXPECT_NEAR(p(0) + 1.0 / gains(0), p(2) + 1.0 / gains(2), 1e-12);
}

TEST(CapacityBound, OrthogonalRows_GiveTheBoundAndTheZfSumRate) {
  // GIVEN: H with orthogonal unit-modulus rows (a DFT matrix), Nr <= Nt
  for (const int nr : {4, 2}) {
    const int nt = 4;
    Eigen::MatrixXcd H(nr, nt);
    for (int r = 0; r < nr; ++r) {
      for (int c = 0; c < nt; ++c) H(r, c) = std::polar(1.0, 2.0 * M_PI * r * c / nt);
    }
    const double noise = 0.1;
    // THEN: C equals the bound, and with equal power metrics.h's ZF sum rate
    EXPECT_NEAR(lp::capacity_bps_hz(H, noise, lp::CapPower::kEqual),
                lp::orthogonal_capacity_bps_hz(nr, nt, noise, lp::CapPower::kEqual), 1e-9);
    EXPECT_NEAR(lp::capacity_bps_hz(H, noise, lp::CapPower::kWaterfill),
                lp::orthogonal_capacity_bps_hz(nr, nt, noise, lp::CapPower::kWaterfill), 1e-9);
    EXPECT_NEAR(lp::capacity_bps_hz(H, noise, lp::CapPower::kEqual), lp::evaluate_link(H, noise).sum_rate_zf_bps_hz,
                1e-9);
  }
  EXPECT_NEAR(lp::orthogonal_capacity_bps_hz(16, 16, 0.1, lp::CapPower::kEqual), 16.0 * std::log2(161.0), 1e-12);
}

TEST(CapacityPlanner, SmallSwarm_NeverDecreasesCapacityPerAcceptedStep) {
  for (const lp::CapPower power : {lp::CapPower::kEqual, lp::CapPower::kWaterfill}) {
    // GIVEN: a 2 x 2 BS, 4 UAVs, no errors (the UAV's model is the true channel)
    const lp::Scenario s = scenario(2, 2, 4, lp::GainModel::kExact);
    const lp::ChannelModel model(s);
    lp::CapOptions options;
    options.power = power;
    const lp::CapacityPlanner planner(s, options);
    for (int seed = 0; seed < 5; ++seed) {
      lp::Swarm swarm(model, random_start(s, seed), lp::ErrorModel{}, seed);
      double c = lp::capacity_bps_hz(swarm.channel().H(), s.noise_variance(), power);
      const double c_start = c;
      for (int iteration = 1; iteration <= 30; ++iteration) {
        for (int m = 0; m < swarm.num_uavs(); ++m) {
          // WHEN: each UAV takes its step
          swarm.move(m, planner.plan_step(swarm, m, swarm.true_positions_m().col(m), options.step),
                     lp::MotionKind::kPlacement);
          // THEN: the capacity does not decrease
          const double after = lp::capacity_bps_hz(swarm.channel().H(), s.noise_variance(), power);
          ASSERT_GE(after, c - 1e-9 * c) << "seed " << seed << " iteration " << iteration << " UAV " << m;
          c = after;
        }
      }
      EXPECT_GT(c, c_start);
    }
  }
}

TEST(CapacityPlanner, PaperScenario_ReachesTheOrthogonalBoundFromRandomStarts) {
  // GIVEN: the paper's scenario (4 x 4 BS, 16 UAVs, 10 dB), random starts, no errors
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const double bound = lp::orthogonal_capacity_bps_hz(16, 16, s.noise_variance(), lp::CapPower::kEqual);
  for (int seed = 1; seed <= 3; ++seed) {
    lp::CapacityPlanner planner(s, lp::CapOptions{});
    lp::Swarm swarm(model, random_start(s, seed), lp::ErrorModel{}, seed);
    const double c_start = lp::capacity_bps_hz(swarm.channel().H(), s.noise_variance(), lp::CapPower::kEqual);
    // WHEN: it runs to the master's ICN target 0.95
    const lp::RunResult r = lp::run_placement(planner, swarm, lp::RunOptions{});
    // THEN: it converges and its capacity is within 5 % of the bound
    const double c = lp::capacity_bps_hz(model.matrix(r.final_m), s.noise_variance(), lp::CapPower::kEqual);
    std::printf("cap seed %d: %d iterations, %s, C %.2f -> %.2f bit/s/Hz, bound %.2f (%.4f), planner %.2f\n", seed,
                r.iterations, to_string(r.status).c_str(), c_start, c, bound, c / bound, planner.capacity_bps_hz());
    EXPECT_TRUE(r.converged()) << "seed " << seed;
    EXPECT_GT(c / bound, 0.95) << "seed " << seed;
    EXPECT_NEAR(planner.capacity_bps_hz(), c, 1e-9 * c);
  }
}
