// The kernels' reorthogonalise (kernels.h), one Gram-Schmidt pass of the Lanczos: against the
// scalar reference, and bit for bit against the same pass written with fixed-size Eigen arrays
// (the form the Lanczos used before it became a kernel), on every instruction-set build.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <complex>
#include <cstring>
#include <random>
#include <vector>

#include "losmimo/placement/isa.h"
#include "losmimo/placement/kernels.h"

namespace lp = losmimo::placement;
namespace lk = losmimo::placement::kernels;

namespace {

using Lanes = Eigen::Array<double, lk::kLanes, 1>;
using ConstLanes = Eigen::Map<const Lanes>;

// The pass with Eigen arrays: c_j = v_j^H w, then w -= c_j v_j, then |w|^2.
double eigen_pass(const std::vector<double>& Vr, const std::vector<double>& Vi, int ld, int count,
                  std::vector<double>& wr, std::vector<double>& wi) {
  std::vector<std::complex<double>> c(count);
  for (int j = 0; j < count; ++j) {
    Lanes sr = Lanes::Zero(), si = Lanes::Zero();
    for (int l = 0; l < ld; l += lk::kLanes) {
      const ConstLanes a_re(&Vr[j * ld + l]), a_im(&Vi[j * ld + l]), b_re(&wr[l]), b_im(&wi[l]);
      sr += a_re * b_re + a_im * b_im;
      si += a_re * b_im - a_im * b_re;
    }
    c[j] = {sr.sum(), si.sum()};
  }
  for (int j = 0; j < count; ++j) {
    for (int l = 0; l < ld; ++l) {
      wr[l] -= c[j].real() * Vr[j * ld + l] - c[j].imag() * Vi[j * ld + l];
      wi[l] -= c[j].real() * Vi[j * ld + l] + c[j].imag() * Vr[j * ld + l];
    }
  }
  Lanes s = Lanes::Zero();
  for (int l = 0; l < ld; l += lk::kLanes) s += ConstLanes(&wr[l]).square() + ConstLanes(&wi[l]).square();
  return s.sum();
}

}  // namespace

TEST(Reorthogonalise, IsTheEigenArraysPassBitForBit_AndTheReferencePass_OnEveryBuild) {
  std::mt19937_64 rng(61);
  std::normal_distribution<double> n01;
  for (const int n : {16, 12, 64}) {
    const int ld = lk::padded(n);
    // Orthonormal columns (Eigen's QR of a random matrix), padded into split planes.
    Eigen::MatrixXcd A(n, n);
    for (Eigen::Index i = 0; i < A.size(); ++i) A(i) = {n01(rng), n01(rng)};
    const Eigen::MatrixXcd Q = Eigen::HouseholderQR<Eigen::MatrixXcd>(A).householderQ();
    for (const int count : {1, n / 2, n - 1}) {
      std::vector<double> Vr(static_cast<std::size_t>(ld) * count, 0.0), Vi(Vr.size(), 0.0);
      for (int j = 0; j < count; ++j) {
        for (int l = 0; l < n; ++l) {
          Vr[j * ld + l] = Q(l, j).real();
          Vi[j * ld + l] = Q(l, j).imag();
        }
      }
      std::vector<double> w0r(ld, 0.0), w0i(ld, 0.0);
      for (int l = 0; l < n; ++l) {
        w0r[l] = n01(rng);
        w0i[l] = n01(rng);
      }
      std::vector<double> er = w0r, ei = w0i;
      const double eigen_norm2 = eigen_pass(Vr, Vi, ld, count, er, ei);
      std::vector<double> rr = w0r, ri = w0i;
      const double ref_norm2 =
          lk::reference_kernels().reorthogonalise(Vr.data(), Vi.data(), ld, count, rr.data(), ri.data());
      for (const lp::Isa isa : lp::supported_isas()) {
        std::vector<double> wr = w0r, wi = w0i;
        const double norm2 =
            lk::kernels_for(isa).reorthogonalise(Vr.data(), Vi.data(), ld, count, wr.data(), wi.data());
        EXPECT_EQ(std::memcmp(&norm2, &eigen_norm2, sizeof norm2), 0) << lp::to_string(isa) << " n " << n;
        EXPECT_EQ(std::memcmp(wr.data(), er.data(), ld * sizeof(double)), 0) << lp::to_string(isa);
        EXPECT_EQ(std::memcmp(wi.data(), ei.data(), ld * sizeof(double)), 0) << lp::to_string(isa);
        EXPECT_NEAR(norm2, ref_norm2, 1e-12 * ref_norm2);
        // What is left is orthogonal to every v_j (to rounding), and its pads stay 0.
        for (int j = 0; j < count; ++j) {
          std::complex<double> d = 0.0;
          for (int l = 0; l < n; ++l) d += std::conj(Q(l, j)) * std::complex<double>(wr[l], wi[l]);
          EXPECT_LT(std::abs(d), 1e-13 * n) << "v_" << j;
        }
        for (int l = n; l < ld; ++l) EXPECT_EQ(wr[l], 0.0);
      }
    }
  }
}
