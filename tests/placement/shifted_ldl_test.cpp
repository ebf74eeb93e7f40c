// The kernels' shifted_ldl (kernels.h), the factorisation behind icn_below's proof, on every
// instruction-set build: against independent checks (L D L^H rebuilt with Eigen; where it
// fails, the leading minors' eigenvalues and the failing pivot against the Schur complement
// Eigen computes), against the scalar reference, and the same bits on every build.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "losmimo/placement/isa.h"
#include "losmimo/placement/kernels.h"

namespace lp = losmimo::placement;
namespace lk = losmimo::placement::kernels;

namespace {

// G = H^H H of a random complex nr x n H, in split planes padded to ld = padded(n).
struct Planes {
  int n = 0, ld = 0;
  Eigen::MatrixXcd G;
  std::vector<double> re, im;
  lk::GramPlanes view() const { return {n, ld, re.data(), im.data()}; }
};

Planes random_gram(int n, int nr, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  Eigen::MatrixXcd H(nr, n);
  for (Eigen::Index i = 0; i < H.size(); ++i) H(i) = {n01(rng), n01(rng)};
  Planes p;
  p.n = n;
  p.ld = lk::padded(n);
  p.G = H.adjoint() * H;
  p.re.assign(static_cast<std::size_t>(p.ld) * n, 0.0);
  p.im.assign(p.re.size(), 0.0);
  for (int k = 0; k < n; ++k) {
    for (int l = 0; l < n; ++l) {
      p.re[l + k * p.ld] = p.G(l, k).real();
      p.im[l + k * p.ld] = p.G(l, k).imag();
    }
  }
  return p;
}

struct Factor {
  int result = 0;
  std::vector<double> re, im;
};

Factor factor(const lk::Kernels& k, const Planes& p, double s) {
  Factor f;
  f.re.assign(p.re.size(), 0.0);
  f.im.assign(p.re.size(), 0.0);
  f.result = k.shifted_ldl(p.view(), s, f.re.data(), f.im.data());
  return f;
}

// The lower triangle of the first `cols` columns of the output (pivots on the diagonal).
Eigen::MatrixXcd lower(const Factor& f, int n, int ld, int cols) {
  Eigen::MatrixXcd L = Eigen::MatrixXcd::Zero(n, cols);
  for (int c = 0; c < cols; ++c) {
    for (int i = c; i < n; ++i) L(i, c) = {f.re[i + c * ld], f.im[i + c * ld]};
  }
  return L;
}

// L D L^H from the first `cols` columns: L unit lower, D the pivots.
Eigen::MatrixXcd ldl_product(const Factor& f, int n, int ld, int cols) {
  Eigen::MatrixXcd L = lower(f, n, ld, cols);
  const Eigen::VectorXd d = L.diagonal().real();
  L.diagonal().setOnes();
  return L * d.asDiagonal() * L.adjoint();
}

double smallest_eigenvalue(const Eigen::MatrixXcd& A) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd>(A, Eigen::EigenvaluesOnly).eigenvalues()(0);
}

}  // namespace

TEST(ShiftedLdl, BelowTheSpectrum_FactorsGMinusSI_OnEveryBuild_WithTheSameBits) {
  for (const int n : {16, 12, 64}) {
    const Planes p = random_gram(n, n + 4, 100 + n);
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd>(p.G).eigenvalues();
    const double s = 0.5 * eig(0);
    const Eigen::MatrixXcd A = p.G - s * Eigen::MatrixXcd::Identity(n, n);
    const Factor ref = factor(lk::reference_kernels(), p, s);
    ASSERT_EQ(ref.result, n);
    std::vector<double> first;
    for (const lp::Isa isa : lp::supported_isas()) {
      const Factor f = factor(lk::kernels_for(isa), p, s);
      ASSERT_EQ(f.result, n) << lp::to_string(isa);
      const Eigen::MatrixXcd L = lower(f, n, p.ld, n);
      EXPECT_LE((ldl_product(f, n, p.ld, n) - A).norm(), 1e-12 * A.norm()) << lp::to_string(isa) << " n " << n;
      for (int i = 0; i < n; ++i) {
        EXPECT_GT(L(i, i).real(), 0.0);
        EXPECT_EQ(L(i, i).imag(), 0.0);
      }
      const Eigen::MatrixXcd R = lower(ref, n, p.ld, n);
      EXPECT_LE((L - R).norm(), 1e-12 * R.norm()) << lp::to_string(isa);
      std::vector<double> bits;
      for (int c = 0; c < n; ++c) {
        for (int i = c; i < n; ++i) {
          bits.push_back(f.re[i + c * p.ld]);
          bits.push_back(f.im[i + c * p.ld]);
        }
      }
      if (first.empty()) first = bits;
      EXPECT_EQ(std::memcmp(bits.data(), first.data(), first.size() * sizeof(double)), 0) << lp::to_string(isa);
    }
  }
}

TEST(ShiftedLdl, InsideTheSpectrum_StopsAtTheFirstLeadingMinorThatIsNotPositiveDefinite) {
  for (const int n : {16, 12, 64}) {
    const Planes p = random_gram(n, n + 4, 200 + n);
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd>(p.G).eigenvalues();
    for (const double s : {0.5 * (eig(0) + eig(1)), 0.5 * (eig(n / 2) + eig(n / 2 + 1)), 2.0 * eig(n - 1)}) {
      const Eigen::MatrixXcd A = p.G - s * Eigen::MatrixXcd::Identity(n, n);
      const int expected = factor(lk::reference_kernels(), p, s).result;
      for (const lp::Isa isa : lp::supported_isas()) {
        const Factor f = factor(lk::kernels_for(isa), p, s);
        ASSERT_EQ(f.result, expected) << lp::to_string(isa);
        const int j = f.result;
        ASSERT_GE(j, 0);
        ASSERT_LT(j, n);
        // The leading j x j block is positive definite, the (j + 1) one is not (by its
        // eigenvalues, with a margin for rounding), and the complete columns factor the
        // leading block.
        const double tol = 1e-10 * A.norm();
        if (j > 0) {
          EXPECT_GT(smallest_eigenvalue(A.topLeftCorner(j, j)), -tol);
          EXPECT_LE((ldl_product(f, j, p.ld, j) - A.topLeftCorner(j, j)).norm(), 1e-12 * A.norm());
        }
        EXPECT_LT(smallest_eigenvalue(A.topLeftCorner(j + 1, j + 1)), tol);
        // icn_below's witness: z = (y, 1, 0 ...) with L11^H y = -l^H (l the unit L's row j) has
        // z^H A z = the Schur complement A_jj - a^H A11^-1 a <= 0, a = A's column j above row j.
        Eigen::VectorXcd z = Eigen::VectorXcd::Zero(n);
        z(j) = 1.0;
        if (j > 0) {
          Eigen::MatrixXcd L11 = lower(f, j, p.ld, j);
          L11.diagonal().setOnes();
          Eigen::VectorXcd l(j);
          for (int c = 0; c < j; ++c) l(c) = {f.re[j + c * p.ld], f.im[j + c * p.ld]};
          z.head(j) = L11.adjoint().triangularView<Eigen::Upper>().solve(-l.conjugate());
        }
        const Eigen::MatrixXcd A11 = A.topLeftCorner(j, j);
        const Eigen::VectorXcd a = A.col(j).head(j);
        const double schur = A(j, j).real() - (j > 0 ? (a.adjoint() * A11.ldlt().solve(a))(0).real() : 0.0);
        const double quotient = (z.adjoint() * A * z)(0).real();
        EXPECT_LE(schur, tol) << lp::to_string(isa);
        EXPECT_NEAR(quotient, schur, 1e-9 * A.norm() * z.squaredNorm()) << lp::to_string(isa);
      }
    }
  }
}

TEST(ShiftedLdl, ANaNInG_ReturnsMinusOne_NeverAColumn) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // A diagonal entry, one below the diagonal (the kernel reads only the lower triangle), the last.
  for (const int entry : {0, 5 + 3 * 16, 15 + 15 * 16}) {
    Planes p = random_gram(16, 20, 300);
    p.re[entry] = nan;
    for (const lp::Isa isa : lp::supported_isas()) {
      EXPECT_EQ(factor(lk::kernels_for(isa), p, 1e-3).result, -1) << lp::to_string(isa) << " entry " << entry;
    }
    EXPECT_EQ(factor(lk::reference_kernels(), p, 1e-3).result, -1);
  }
}

TEST(ShiftedLdl, TheUnrolledSixteenAndTheAnySizePath_GiveTheSameBits) {
  // Nt = 16 at ld = 16 takes the compile-time path; the same G at ld = 24 the any-size one.
  const Planes p = random_gram(16, 20, 400);
  Planes wide = p;
  wide.ld = 24;
  wide.re.assign(static_cast<std::size_t>(wide.ld) * 16, 0.0);
  wide.im.assign(wide.re.size(), 0.0);
  for (int k = 0; k < 16; ++k) {
    for (int l = 0; l < 16; ++l) {
      wide.re[l + k * wide.ld] = p.re[l + k * p.ld];
      wide.im[l + k * wide.ld] = p.im[l + k * p.ld];
    }
  }
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd>(p.G).eigenvalues();
  for (const double s : {0.5 * eig(0), 0.5 * (eig(7) + eig(8))}) {
    for (const lp::Isa isa : lp::supported_isas()) {
      const Factor a = factor(lk::kernels_for(isa), p, s), b = factor(lk::kernels_for(isa), wide, s);
      ASSERT_EQ(a.result, b.result) << lp::to_string(isa);
      const int cols = a.result == 16 ? 16 : a.result;
      for (int c = 0; c < cols; ++c) {
        for (int i = c; i < 16; ++i) {
          EXPECT_EQ(a.re[i + c * 16], b.re[i + c * 24]) << lp::to_string(isa) << " (" << i << ", " << c << ")";
          EXPECT_EQ(a.im[i + c * 16], b.im[i + c * 24]) << lp::to_string(isa) << " (" << i << ", " << c << ")";
        }
      }
    }
  }
}
