// The channel rows' sincos (phasor.h), as this process runs it, against glibc's std::cos and
// std::sin: an independent implementation of the same functions. kernels_test.cpp checks
// every instruction set's build the same way.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "losmimo/placement/phasor.h"

namespace lp = losmimo::placement;

namespace {
constexpr double kEps = std::numeric_limits<double>::epsilon();

// Worst absolute error against glibc in units of eps (|cos|, |sin| <= 1, so an absolute bound
// is the meaningful one for a phasor).
double worst_error_eps(const std::vector<double>& phase) {
  const int n = static_cast<int>(phase.size());
  std::vector<double> c(n), s(n);
  lp::unit_phasors(phase.data(), c.data(), s.data(), n);
  double worst = 0.0;
  for (int k = 0; k < n; ++k) {
    worst = std::max({worst, std::abs(c[k] - std::cos(phase[k])) / kEps, std::abs(s[k] - std::sin(phase[k])) / kEps});
  }
  return worst;
}
}  // namespace

TEST(Phasor, SmallPhases_AgreeWithGlibcToOneUlp) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::vector<double> phase(100000);
  for (double& p : phase) p = u(rng);
  EXPECT_LE(worst_error_eps(phase), 1.0);
}

TEST(Phasor, ChannelSizedPhases_AgreeWithGlibcToOneUlp) {
  // GIVEN: phases of a channel row at 1 km and 60 GHz (-2 pi d / lambda, ~1.26e6 rad)
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1.4e6, -1.1e6);
  std::vector<double> phase(100000);
  for (double& p : phase) p = u(rng);
  // THEN: the three-part reduction keeps the error at the level of the polynomial
  EXPECT_LE(worst_error_eps(phase), 1.0);
}

TEST(Phasor, QuadrantBoundariesAndSpecialPoints_AreAccurate) {
  std::vector<double> phase;
  for (int j = -8; j <= 8; ++j) {
    const double b = j * M_PI_4;
    phase.insert(phase.end(), {b, std::nextafter(b, 10.0), std::nextafter(b, -10.0)});
  }
  phase.insert(phase.end(), {0.0, -0.0, 1e-300, M_PI, -M_PI, 2 * M_PI, 1.99e8, -1.99e8});
  EXPECT_LE(worst_error_eps(phase), 1.0);
}

TEST(Phasor, HugeAndNonFinitePhases_TakeTheLibraryPathInsideABlock) {
  // GIVEN: a block that mixes ordinary phases with ones the fast reduction refuses
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> phase = {1.0, 1e12, -7.3e15, 2.0, std::nan(""), inf, -inf, 3.0};
  std::vector<double> c(phase.size()), s(phase.size());
  lp::unit_phasors(phase.data(), c.data(), s.data(), static_cast<int>(phase.size()));
  for (std::size_t k : {0, 1, 2, 3, 7}) {
    EXPECT_NEAR(c[k], std::cos(phase[k]), kEps) << k;
    EXPECT_NEAR(s[k], std::sin(phase[k]), kEps) << k;
  }
  // THEN: non-finite phases give NaN, as std::cos does
  for (std::size_t k : {4, 5, 6}) {
    EXPECT_TRUE(std::isnan(c[k]) && std::isnan(s[k])) << k;
  }
}

TEST(Phasor, EveryLaneGivesTheSameBitsAsTheTail) {
  // GIVEN: a block of phases (vector lanes) and the same phases one at a time (the tail path)
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1.4e6, 1.4e6);
  std::vector<double> phase(37);
  for (double& p : phase) p = u(rng);
  std::vector<double> c(phase.size()), s(phase.size());
  lp::unit_phasors(phase.data(), c.data(), s.data(), static_cast<int>(phase.size()));
  for (std::size_t k = 0; k < phase.size(); ++k) {
    double c1 = 0.0, s1 = 0.0;
    lp::unit_phasors(&phase[k], &c1, &s1, 1);
    // THEN: results do not depend on where a phase sits in a block
    EXPECT_EQ(std::memcmp(&c1, &c[k], sizeof c1), 0) << k;
    EXPECT_EQ(std::memcmp(&s1, &s[k], sizeof s1), 0) << k;
  }
}
