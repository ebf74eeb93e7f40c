// Resampling with the caller's generator: unbiased copy counts, the low-variance properties of
// systematic and residual resampling, and the degenerate cases.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "losmimo/localization/resampling.h"

namespace losmimo::localization {
namespace {

const std::vector<ResamplingMethod> kAllMethods = {ResamplingMethod::kMultinomial, ResamplingMethod::kResidual,
                                                   ResamplingMethod::kStratified, ResamplingMethod::kSystematic};

std::vector<double> log_of(const std::vector<double>& w) {
  std::vector<double> out;
  for (const double x : w) out.push_back(std::log(x) + 7.0);  // arbitrary offset
  return out;
}

std::vector<int> copies(const std::vector<std::size_t>& idx, std::size_t n) {
  std::vector<int> c(n, 0);
  for (const std::size_t i : idx) ++c[i];
  return c;
}

class Resampling : public ::testing::TestWithParam<ResamplingMethod> {};

TEST_P(Resampling, AllWeightOnOneParticle_CopiesOnlyThatOne) {
  mrpt::random::CRandomGenerator rng(1);
  std::vector<double> log_w(50, -1e300);
  log_w[17] = 0.0;
  const auto idx = resampling_indices(GetParam(), log_w, rng);
  ASSERT_EQ(idx.size(), log_w.size());
  for (const std::size_t i : idx) EXPECT_EQ(i, 17u);
}

TEST_P(Resampling, ManyDraws_MeanCopiesEqualNTimesWeight) {
  // Unbiasedness: the average number of copies of i over kReps draws is N w_i within 5 of its
  // standard errors (multinomial variance N w (1 - w) bounds the other methods').
  constexpr int kReps = 4000;
  const std::vector<double> w = {0.05, 0.30, 0.01, 0.14, 0.20, 0.10, 0.02, 0.08, 0.06, 0.04};
  const std::size_t n = w.size();
  mrpt::random::CRandomGenerator rng(2);
  std::vector<double> mean(n, 0.0);
  for (int r = 0; r < kReps; ++r) {
    const auto idx = resampling_indices(GetParam(), log_of(w), rng);
    ASSERT_TRUE(std::is_sorted(idx.begin(), idx.end()));
    const auto c = copies(idx, n);
    for (std::size_t i = 0; i < n; ++i) mean[i] += static_cast<double>(c[i]) / kReps;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double nw = static_cast<double>(n) * w[i];
    const double standard_error = std::sqrt(nw * (1.0 - w[i]) / kReps);
    EXPECT_NEAR(mean[i], nw, 5.0 * standard_error + 1e-12) << "particle " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(AllMethods, Resampling, ::testing::ValuesIn(kAllMethods),
                         [](const auto& info) { return to_string(info.param); });

TEST(Resampling, SystematicAndResidual_CopiesBracketNTimesWeight) {
  const std::vector<double> w = {0.05, 0.30, 0.01, 0.14, 0.20, 0.10, 0.02, 0.08, 0.06, 0.04};
  const double n = static_cast<double>(w.size());
  mrpt::random::CRandomGenerator rng(3);
  for (int r = 0; r < 200; ++r) {
    const auto sys = copies(resampling_indices(ResamplingMethod::kSystematic, log_of(w), rng), w.size());
    const auto res = copies(resampling_indices(ResamplingMethod::kResidual, log_of(w), rng), w.size());
    for (std::size_t i = 0; i < w.size(); ++i) {
      EXPECT_GE(sys[i], std::floor(n * w[i] - 1e-9));
      EXPECT_LE(sys[i], std::ceil(n * w[i] + 1e-9));
      EXPECT_GE(res[i], std::floor(n * w[i] - 1e-9));
    }
  }
}

TEST(Resampling, SameSeed_SameIndices) {
  std::vector<double> log_w;
  for (int i = 0; i < 100; ++i) log_w.push_back(std::sin(0.3 * i));
  mrpt::random::CRandomGenerator a(5);
  mrpt::random::CRandomGenerator b(5);
  EXPECT_EQ(resampling_indices(ResamplingMethod::kMultinomial, log_w, a),
            resampling_indices(ResamplingMethod::kMultinomial, log_w, b));
}

TEST(Resampling, EmptyInput_Throws) {
  mrpt::random::CRandomGenerator rng(1);
  EXPECT_THROW(resampling_indices(ResamplingMethod::kSystematic, {}, rng), std::invalid_argument);
}

TEST(NormalizedEss, UniformIsOne_DegenerateIsOneOverN) {
  EXPECT_NEAR(normalized_ess(std::vector<double>(20, -3.0)), 1.0, 1e-12);
  std::vector<double> log_w(20, -1e300);
  log_w[3] = 0.0;
  EXPECT_NEAR(normalized_ess(log_w), 1.0 / 20.0, 1e-12);
}

}  // namespace
}  // namespace losmimo::localization
