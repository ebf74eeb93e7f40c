// CSI measurement model (fusion/csi.h): simulator, path difference, reference phase.
#include "losmimo/fusion/csi.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "losmimo/fusion/cost_functors.h"

namespace losmimo::fusion {
namespace {

constexpr double kTightTol = 1e-9;

placement::Scenario default_scenario() { return placement::Scenario{}; }

TEST(SimulateCsi, Noiseless_IsChannelRowTimesOneCommonPhase) {
  // GIVEN: the default 4x4 BS, a UAV 1 km out, no noise.
  const placement::ChannelModel model(default_scenario());
  const Eigen::Vector3d q_m(1003.0, -12.0, 7.5);
  std::mt19937_64 rng(11);
  // WHEN: two measurements are drawn.
  const CsiMeasurement a = simulate_csi(model, q_m, 0.0, rng);
  const CsiMeasurement b = simulate_csi(model, q_m, 0.0, rng);
  // THEN: each is the channel row rotated by one phase, and the phases differ.
  const Eigen::VectorXcd x = model.row(q_m);
  const std::complex<double> rot_a = a.y(0) / x(0);
  const std::complex<double> rot_b = b.y(0) / x(0);
  EXPECT_NEAR(std::abs(rot_a), 1.0, kTightTol);
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    EXPECT_NEAR(std::abs(a.y(k) - rot_a * x(k)), 0.0, kTightTol) << "antenna " << k;
    EXPECT_NEAR(std::abs(b.y(k) - rot_b * x(k)), 0.0, kTightTol) << "antenna " << k;
  }
  EXPECT_GT(std::abs(rot_a - rot_b), 1e-3);
}

TEST(SimulateCsi, Noise_HasTheScenarioVariancePerEntry) {
  const placement::Scenario scenario = default_scenario();
  const placement::ChannelModel model(scenario);
  const Eigen::Vector3d q_m(1000.0, 3.0, -4.0);
  const Eigen::VectorXcd x = model.row(q_m);
  std::mt19937_64 rng(12);
  constexpr int kDraws = 4000;
  double sum_sq = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const CsiMeasurement c = simulate_csi(model, q_m, scenario.noise_variance(), rng);
    // Remove the common phase with the noiseless row: the ML phase given x.
    const std::complex<double> rot = std::polar(1.0, std::arg(x.dot(c.y)));
    sum_sq += (c.y - rot * x).squaredNorm();
  }
  // Fitting one phase removes ~half a complex degree of freedom out of Nt.
  const double nt = static_cast<double>(x.size());
  const double per_entry = sum_sq / (kDraws * (nt - 0.5));
  EXPECT_NEAR(per_entry, scenario.noise_variance(), 0.03 * scenario.noise_variance());
}

TEST(SimulateCsi, NegativeNoiseVariance_Throws) {
  const placement::ChannelModel model(default_scenario());
  std::mt19937_64 rng(1);
  EXPECT_THROW(simulate_csi(model, Eigen::Vector3d(1000.0, 0.0, 0.0), -0.1, rng), std::invalid_argument);
}

TEST(CsiPathDifference, MatchesLongDoubleDirectDifference) {
  const placement::ChannelModel model(default_scenario());
  const Eigen::Vector3d q_m(987.654, 21.0, -13.25);
  const Eigen::VectorXd delta = csi_path_difference_m(model, q_m);
  for (int k = 0; k < model.num_antennas(); ++k) {
    long double d2 = 0.0L, r2 = 0.0L;
    for (int i = 0; i < 3; ++i) {
      const long double v = static_cast<long double>(q_m(i)) - model.antennas_m()(i, k);
      d2 += v * v;
      r2 += static_cast<long double>(q_m(i)) * q_m(i);
    }
    const double direct = static_cast<double>(std::sqrt(d2) - std::sqrt(r2));
    EXPECT_NEAR(delta(k), direct, 1e-11) << "antenna " << k;
  }
}

TEST(CsiReferencePhase, Noiseless_ExplainsEveryEntry) {
  // The phase model arg y_k = psi - kappa delta_k(q) must reproduce the channel's own phases.
  const placement::ChannelModel model(default_scenario());
  const Eigen::Vector3d q_m(1010.0, -20.0, 18.0);
  std::mt19937_64 rng(13);
  const CsiMeasurement c = simulate_csi(model, q_m, 0.0, rng);
  const double psi = csi_reference_phase_rad(model, c, q_m);
  const Eigen::VectorXd delta = csi_path_difference_m(model, q_m);
  for (int k = 0; k < model.num_antennas(); ++k) {
    const double predicted = psi - model.wavenumber_rad_per_m() * delta(k);
    EXPECT_NEAR(wrap_angle_rad(std::arg(c.y(k)) - predicted), 0.0, 1e-8) << "antenna " << k;
  }
}

TEST(CsiPhase, LateralMotion_TurnsEdgeToEdgePhaseAboutOneRadianPerMetre) {
  // ~1 rad per metre across the 0.75 m aperture at 1 km, 60 GHz; depth: far less.
  const placement::ChannelModel model(default_scenario());
  const Eigen::Vector3d q_m(1000.0, 0.0, 0.0);
  const int left = 0, right = 3;  // row 0, columns 0 and 3: 0.75 m apart along y
  auto edge_phase = [&](const Eigen::Vector3d& q) {
    const Eigen::VectorXd delta = csi_path_difference_m(model, q);
    return -model.wavenumber_rad_per_m() * (delta(right) - delta(left));
  };
  const double per_m_lateral = std::abs(edge_phase(q_m + Eigen::Vector3d(0.0, 0.1, 0.0)) - edge_phase(q_m)) / 0.1;
  const double per_m_depth =
      std::abs(edge_phase(q_m + Eigen::Vector3d(1.0, 5.0, 0.0)) - edge_phase(q_m + Eigen::Vector3d(0.0, 5.0, 0.0)));
  EXPECT_NEAR(per_m_lateral, 0.94, 0.02);
  EXPECT_LT(per_m_depth, 0.01);
}

}  // namespace
}  // namespace losmimo::fusion
