#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <Eigen/LU>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/run.h"
#include "losmimo/placement/ura.h"

namespace lp = losmimo::placement;

namespace {
constexpr double kMfSinrDb = 22.0412;  // 10 log10(Nr * SNR) = 10 log10(160)
}

TEST(ChannelModel, Row_MatchesTheClosedFormOfEquation1) {
  // GIVEN: a UAV off-axis and the exact-gain model (the paper's eq. 1 without approximation)
  lp::Scenario s;
  s.gain_model = lp::GainModel::kExact;
  const lp::ChannelModel model(s);
  const Eigen::Vector3d q(1012.3, -7.1, 4.4);
  const Eigen::VectorXcd x = model.row(q);
  const Eigen::Matrix3Xd p = lp::bs_antenna_positions_m(s);
  const double lambda = s.wavelength_m();
  for (int k = 0; k < s.num_bs_antennas(); ++k) {
    const double d = (q - p.col(k)).norm();
    const std::complex<double> h = lambda / (4 * M_PI * d) * std::exp(std::complex<double>(0, -2 * M_PI * d / lambda));
    // THEN: x = h / g_R
    EXPECT_NEAR(std::abs(x(k) * s.reference_gain() - h) / std::abs(h), 0.0, 1e-9) << k;
  }
}

TEST(ChannelModel, FarField_EntriesAreUnitModulus) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::VectorXcd x = model.row(Eigen::Vector3d(990, 3, -2));
  EXPECT_NEAR((x.cwiseAbs().array() - 1.0).abs().maxCoeff(), 0.0, 1e-12);
}

TEST(BsArray, AntennasFormACentredGridInTheYzPlane) {
  const lp::Scenario s;
  const Eigen::Matrix3Xd p = lp::bs_antenna_positions_m(s);
  EXPECT_EQ(p.cols(), 16);
  EXPECT_NEAR(p.row(0).cwiseAbs().maxCoeff(), 0.0, 0.0);
  EXPECT_NEAR(p.rowwise().mean().norm(), 0.0, 1e-12);
  EXPECT_NEAR((p.col(1) - p.col(0)).norm(), 0.25, 1e-12);
  EXPECT_NEAR((p.col(4) - p.col(0)).norm(), 0.25, 1e-12);
}

TEST(Metrics, OptimalUra_IsOrthogonalAndAllCombinersReachTheMfBound) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::MatrixXcd H = model.matrix(lp::optimal_ura_positions_m(s));
  const lp::LinkMetrics m = lp::evaluate_link(H, s.noise_variance());
  EXPECT_GT(m.icn, 0.999);
  for (int k = 0; k < 16; ++k) {
    EXPECT_NEAR(lp::to_db(m.sinr.mf(k)), kMfSinrDb, 0.05);
    EXPECT_NEAR(lp::to_db(m.sinr.nv(k)), kMfSinrDb, 0.05);
    EXPECT_NEAR(lp::to_db(m.sinr.zf(k)), kMfSinrDb, 0.05);
  }
}

TEST(Metrics, RandomStarts_AreIllConditioned) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(42);
  int below = 0;
  constexpr int kDraws = 200;
  for (int t = 0; t < kDraws; ++t) {
    below += lp::inverse_condition_number(model.matrix(lp::random_start_positions_m(s, rng))) < 0.1;
  }
  EXPECT_GE(below, 0.95 * kDraws);
}

TEST(Metrics, ObjectiveAndSinr_AgreeWithExplicitSums) {
  // GIVEN: a random complex 5 x 3 channel
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01;
  Eigen::MatrixXcd H(5, 3);
  for (Eigen::Index i = 0; i < H.size(); ++i) H(i) = {n01(rng), n01(rng)};
  const double psi2 = 0.3;
  // THEN: f is the double sum over l != k, NV and MF follow their definitions with w = h_k,
  // and ZF equals |w^H h_k|^2 / (|w|^2 psi^2) for w the projection of h_k off the others.
  double f = 0.0;
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k < 3; ++k)
      if (l != k) f += std::norm(H.col(l).dot(H.col(k)));
  EXPECT_NEAR(lp::objective(H), f, 1e-10 * f);
  const lp::StreamSinr sinr = lp::stream_sinr(H, psi2);
  for (int k = 0; k < 3; ++k) {
    const Eigen::VectorXcd hk = H.col(k);
    double interference = 0.0;
    Eigen::MatrixXcd others(5, 2);
    for (int m = 0, j = 0; m < 3; ++m) {
      if (m == k) continue;
      interference += std::norm(hk.dot(H.col(m)));
      others.col(j++) = H.col(m);
    }
    EXPECT_NEAR(sinr.nv(k), std::pow(hk.squaredNorm(), 2) / (interference + hk.squaredNorm() * psi2), 1e-9);
    EXPECT_NEAR(sinr.mf(k), hk.squaredNorm() / psi2, 1e-9);
    const Eigen::MatrixXcd gram = others.adjoint() * others;
    const Eigen::MatrixXcd P = others * gram.inverse() * others.adjoint();
    const Eigen::VectorXcd w = hk - P * hk;
    EXPECT_NEAR(sinr.zf(k), std::norm(w.dot(hk)) / (w.squaredNorm() * psi2), 1e-8 * sinr.zf(k));
  }
}

TEST(Metrics, FewerUavsThanAntennas_OneStreamPerUavAtTheUraSlots) {
  // Ten of the 16 URA slots: orthogonal rows, so ten streams at the single-user bound.
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  const Eigen::MatrixXcd H = model.matrix(lp::optimal_ura_positions_m(s).leftCols(10));
  const lp::LinkMetrics m = lp::evaluate_link(H, s.noise_variance());
  EXPECT_GT(m.icn, 0.99);
  ASSERT_EQ(m.sinr.zf.size(), 10);
  for (int n = 0; n < 10; ++n) EXPECT_NEAR(lp::to_db(m.sinr.zf(n)), lp::to_db(m.sinr.mf(n)), 0.05) << n;
}

TEST(Metrics, IcnFromGram_EqualsSvdIcn) {
  const lp::Scenario s;
  const lp::ChannelModel model(s);
  std::mt19937_64 rng(9);
  for (int t = 0; t < 20; ++t) {
    Eigen::Matrix3Xd q = lp::optimal_ura_positions_m(s);
    std::normal_distribution<double> jitter(0.0, 0.2 * t);
    for (Eigen::Index i = 0; i < q.size(); ++i) q(i) += jitter(rng);
    const Eigen::MatrixXcd H = model.matrix(q);
    const double svd_icn = lp::inverse_condition_number(H);
    EXPECT_NEAR(lp::icn_from_gram(H.adjoint() * H, 16), svd_icn, 1e-9 + 1e-7 * svd_icn);
  }
}
