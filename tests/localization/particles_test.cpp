// The Liu-West jitter (particles.h) keeps a resampled cloud's mean and covariance: checked with
// many particles against the Monte Carlo error of the draws, from the identity a^2 + h^2 = 1
// (not from the function's own output); a jitter without the shrink inflates the covariance by
// 1 + h^2 and fails the same check.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <set>
#include <tuple>
#include <vector>

#include <mrpt/random/RandomGenerators.h>

#include "losmimo/localization/particles.h"

namespace losmimo::localization {
namespace {

struct Particle {
  Eigen::Vector3d d;
};

void moments(const std::vector<Particle>& cloud, Eigen::Vector3d& mean, Eigen::Matrix3d& cov) {
  mean.setZero();
  for (const Particle& p : cloud) mean += p.d;
  mean /= static_cast<double>(cloud.size());
  cov.setZero();
  for (const Particle& p : cloud) cov += (p.d - mean) * (p.d - mean).transpose();
  cov /= static_cast<double>(cloud.size());
}

// A resampled cloud: kBase skewed, correlated points (a two-component mixture), each kept kCopies
// times, as resampling leaves duplicates.
constexpr int kBase = 50000;
constexpr int kCopies = 4;
std::vector<Particle> resampled_cloud(mrpt::random::CRandomGenerator& rng) {
  Eigen::Matrix3d A;
  A << 0.3, 0.0, 0.0, 0.1, 0.05, 0.0, -0.2, 0.02, 0.01;  // strongly anisotropic, correlated
  std::vector<Particle> cloud;
  for (int i = 0; i < kBase; ++i) {
    Eigen::Vector3d n;
    for (int k = 0; k < 3; ++k) n(k) = rng.drawGaussian1D_normalized();
    const Eigen::Vector3d offset =
        rng.drawUniform(0.0, 1.0) < 0.3 ? Eigen::Vector3d(0.4, -0.1, 0.2) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d d = Eigen::Vector3d(1000.0, 2.0, -3.0) + offset + A * n;
    for (int c = 0; c < kCopies; ++c) cloud.push_back({d});
  }
  return cloud;
}

// Max over entries of |C' - C| / sqrt(C_jj C_kk): the covariance change in units of the entries'
// scale, and the mean change per axis in units of sqrt(C_kk).
std::pair<double, double> relative_changes(const Eigen::Vector3d& m0, const Eigen::Matrix3d& C0,
                                           const Eigen::Vector3d& m1, const Eigen::Matrix3d& C1) {
  double cov = 0.0, mean = 0.0;
  for (int j = 0; j < 3; ++j) {
    mean = std::max(mean, std::abs(m1(j) - m0(j)) / std::sqrt(C0(j, j)));
    for (int k = 0; k < 3; ++k) cov = std::max(cov, std::abs(C1(j, k) - C0(j, k)) / std::sqrt(C0(j, j) * C0(k, k)));
  }
  return {mean, cov};
}

TEST(LiuWestJitter, KeepsMeanAndCovarianceWithinMonteCarloError_AndMakesDuplicatesDistinct) {
  mrpt::random::CRandomGenerator rng(17);
  std::vector<Particle> cloud = resampled_cloud(rng);
  const double n = static_cast<double>(cloud.size());
  Eigen::Vector3d m0;
  Eigen::Matrix3d C0;
  moments(cloud, m0, C0);
  const Eigen::Matrix3d L = C0.llt().matrixL();
  constexpr double h = 0.2;
  std::vector<Particle> plain = cloud;  // the negative control: the jitter without its shrink
  liu_west_jitter(cloud, m0, L, h, rng);
  for (Particle& p : plain) {
    Eigen::Vector3d z;
    for (int k = 0; k < 3; ++k) z(k) = rng.drawGaussian1D_normalized();
    p.d += h * (L * z);
  }
  Eigen::Vector3d m1, mp;
  Eigen::Matrix3d C1, Cp;
  moments(cloud, m1, C1);
  moments(plain, mp, Cp);
  // Monte Carlo error: the mean moves by h L z-bar (per axis sd h / sqrt(N) in units of sqrt(C_kk));
  // a covariance entry by h^2 (S_z - I) and the cross terms a h (d - m) z^T, sd below
  // (h^2 sqrt(2) + 2 a h) / sqrt(N) in units of sqrt(C_jj C_kk). Six sd.
  const double a = std::sqrt(1.0 - h * h);
  const double mean_tol = 6.0 * h / std::sqrt(n);
  const double cov_tol = 6.0 * (h * h * std::sqrt(2.0) + 2.0 * a * h) / std::sqrt(n);
  const auto [mean_change, cov_change] = relative_changes(m0, C0, m1, C1);
  EXPECT_LT(mean_change, mean_tol);
  EXPECT_LT(cov_change, cov_tol) << "tolerance " << cov_tol;
  // THEN (negative control): without the shrink the covariance grows by h^2 = 4%, far outside.
  EXPECT_GT(relative_changes(m0, C0, mp, Cp).second, 5.0 * cov_tol);
  // THEN: the kCopies duplicates of every point are distinct particles now.
  std::set<std::tuple<double, double, double>> distinct;
  for (const Particle& p : cloud) distinct.insert({p.d(0), p.d(1), p.d(2)});
  EXPECT_EQ(distinct.size(), cloud.size());
}

TEST(LiuWestJitter, ShrinksTowardTheGivenMean_ByA) {
  // One particle at mean + e_x, with L = 0: it moves to mean + a e_x exactly (no noise reaches it).
  mrpt::random::CRandomGenerator rng(3);
  const Eigen::Vector3d mean(5.0, -1.0, 2.0);
  std::vector<Particle> one = {{mean + Eigen::Vector3d::UnitX()}};
  constexpr double h = 0.6;  // a = 0.8
  liu_west_jitter(one, mean, Eigen::Matrix3d::Zero(), h, rng);
  EXPECT_NEAR((one[0].d - (mean + 0.8 * Eigen::Vector3d::UnitX())).norm(), 0.0, 1e-15);
}

}  // namespace
}  // namespace losmimo::localization
