// The particle filters' proposal (optimal_proposal.h) on a linear-Gaussian measurement, where
// both halves have closed forms: the samples follow the Kalman posterior of each particle, and
// the weight increments differ between particles exactly as the predictive likelihoods
// N(z; H xbar, H Q H^T + R) do.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <random>
#include <vector>

#include "losmimo/localization/optimal_proposal.h"

namespace losmimo::localization {
namespace {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// z = H x + v, v ~ N(0, R), R diagonal; whitened as the concept requires.
struct LinearMeasurement {
  Eigen::Matrix<double, 2, 3> H;
  Eigen::Vector2d z;
  Eigen::Vector2d sigma;

  double accumulate(const Vec3& x, Mat3* AtA, Vec3* Atr) const {
    const Eigen::Vector2d r = (z - H * x).cwiseQuotient(sigma);
    if (AtA != nullptr) {
      const Eigen::Matrix<double, 2, 3> A = sigma.cwiseInverse().asDiagonal() * H;
      *AtA += A.transpose() * A;
      *Atr += A.transpose() * r;
    }
    return r.squaredNorm();
  }

  void rows(const Vec3& /*x*/, std::vector<Vec3>& a) const {
    a.clear();
    for (int k = 0; k < 2; ++k) a.push_back(H.row(k).transpose() / sigma(k));
  }

  double project(const Vec3& x, const std::vector<Vec3>& a, Vec3& Atr) const {
    const Eigen::Vector2d r = (z - H * x).cwiseQuotient(sigma);
    Atr.setZero();
    for (std::size_t k = 0; k < a.size(); ++k) Atr += a[k] * r(static_cast<Eigen::Index>(k));
    return r.squaredNorm();
  }
};

// Both entry points: the per-particle Gauss-Newton and the epoch-shared linearisation (with a
// linear h they are the same proposal).
enum class Entry { kPerParticle, kShared };

double draw(Entry entry, const LinearMeasurement& h, const Vec3& x_bar, const Mat3& W, const Vec3& eps, Vec3& x) {
  if (entry == Entry::kPerParticle) return sample_optimal_proposal<3>(x_bar, W, h, eps, x);
  const OptimalProposal<3, LinearMeasurement> proposal(h, Vec3(0.1, 0.1, 0.1), W);  // any xhat: h is linear
  return proposal.sample(x_bar, W, eps, x);
}

LinearMeasurement measurement() {
  LinearMeasurement m;
  m.H << 1.0, 0.5, 0.0, 0.0, -0.3, 2.0;
  m.z << 1.2, -0.4;
  m.sigma << 0.05, 0.2;
  return m;
}

const Mat3 kQ = (Mat3() << 0.09, 0.01, 0.0, 0.01, 0.04, 0.005, 0.0, 0.005, 0.16).finished();

class OptimalProposalTest : public ::testing::TestWithParam<Entry> {};

TEST_P(OptimalProposalTest, LinearGaussian_SamplesFollowTheKalmanPosterior) {
  constexpr int kDraws = 100000;
  const LinearMeasurement h = measurement();
  const Vec3 x_bar(0.7, 0.2, -0.1);
  const Mat3 W = kQ.inverse();
  // Kalman posterior (independent formula: gain form).
  const Eigen::Matrix2d R = h.sigma.cwiseAbs2().asDiagonal();
  const Eigen::Matrix2d S = h.H * kQ * h.H.transpose() + R;
  const Eigen::Matrix<double, 3, 2> K = kQ * h.H.transpose() * S.inverse();
  const Vec3 post_mean = x_bar + K * (h.z - h.H * x_bar);
  const Mat3 post_cov = (Mat3::Identity() - K * h.H) * kQ;

  std::mt19937_64 rng(41);
  std::normal_distribution<double> n(0.0, 1.0);
  Vec3 sum = Vec3::Zero();
  Mat3 sum_sq = Mat3::Zero();
  for (int k = 0; k < kDraws; ++k) {
    const Vec3 eps(n(rng), n(rng), n(rng));
    Vec3 x;
    draw(GetParam(), h, x_bar, W, eps, x);
    sum += x;
    sum_sq += x * x.transpose();
  }
  const Vec3 mean = sum / kDraws;
  const Mat3 cov = sum_sq / kDraws - mean * mean.transpose();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(mean(i), post_mean(i), 4.0 * std::sqrt(post_cov(i, i) / kDraws)) << i;
    EXPECT_NEAR(cov(i, i), post_cov(i, i), 0.02 * post_cov(i, i)) << i;
  }
}

TEST_P(OptimalProposalTest, LinearGaussian_WeightsDifferAsThePredictiveLikelihoods) {
  const LinearMeasurement h = measurement();
  const Mat3 W = kQ.inverse();
  const Eigen::Matrix2d S = h.H * kQ * h.H.transpose() + Eigen::Matrix2d(h.sigma.cwiseAbs2().asDiagonal());
  const auto log_predictive = [&](const Vec3& x_bar) {
    const Eigen::Vector2d y = h.z - h.H * x_bar;
    return -0.5 * y.dot(S.llt().solve(y));
  };
  // Any eps: with a linear h the weight does not depend on where the particle lands.
  const Vec3 a(0.7, 0.2, -0.1), b(-0.3, 0.9, 0.4);
  Vec3 x;
  const double wa1 = draw(GetParam(), h, a, W, Vec3(0.3, -1.2, 0.5), x);
  const double wa2 = draw(GetParam(), h, a, W, Vec3(-2.0, 0.1, 1.5), x);
  const double wb = draw(GetParam(), h, b, W, Vec3(0.8, 0.8, -0.4), x);
  EXPECT_NEAR(wa1, wa2, 1e-9);
  EXPECT_NEAR(wa1 - wb, log_predictive(a) - log_predictive(b), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(BothEntries, OptimalProposalTest, ::testing::Values(Entry::kPerParticle, Entry::kShared),
                         [](const auto& info) { return info.param == Entry::kShared ? "shared" : "per_particle"; });

}  // namespace
}  // namespace losmimo::localization
