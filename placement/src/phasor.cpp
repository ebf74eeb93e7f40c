#include "losmimo/placement/phasor.h"

#include <cmath>

namespace losmimo::placement {

namespace {
constexpr double kTwoPi = 2.0 * M_PI;
// 2 pi (the double) = kHi + kLo with kHi of 26 significant bits.
constexpr double kHi = 6.2831852436065673828125;
constexpr double kLo = kTwoPi - kHi;
constexpr double kInvTwoPi = 1.0 / kTwoPi;
constexpr double kMaxAbs = 4.0e8;              // |n| < 2^26 = 6.7e7: n * kHi, n * kLo exact
constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52: q + kRound - kRound = rint(q)
// pi / 2 = kHalfPiHi + kHalfPiLo, kHalfPiHi with 33 significant bits: j * kHalfPiHi is exact
// for |j| <= 2, and the reduced argument's error is ~|j| 2^-53 ulp(kHalfPiLo) ~ 1e-27.
constexpr double kHalfPiHi = 1.5707963267341256141662597656250;
constexpr double kHalfPiLo = M_PI_2 - kHalfPiHi;

// The exact remainder of x by 2 pi when the fast path proves it (see remainder_two_pi);
// otherwise sets `ok` false.
inline double fast_remainder(double x, bool& ok) {
  // x * (1 / 2pi) may round differently from x / 2pi only when the quotient is within an ulp of
  // a half integer; a wrong n then gives |r| > pi, which `ok` rejects. Any n with |r| < pi is
  // the nearest one, so an accepted r is the exact IEEE remainder.
  const double n = (x * kInvTwoPi + kRound) - kRound;  // not reassociated without -ffast-math
  const double r = (x - n * kHi) - n * kLo;
  ok = std::abs(x) < kMaxAbs && std::abs(r) < 0.5 * kTwoPi;
  return r;
}

// cos and sin of r, |r| <= pi, by quadrant and Taylor series on |y| <= pi/4. Branch-free,
// so that a loop over it vectorises.
inline void sincos_reduced(double r, double& c, double& s) {
  const double j = (r * (2.0 / M_PI) + kRound) - kRound;  // -2 .. 2
  const double y = (r - j * kHalfPiHi) - j * kHalfPiLo;
  const double z = y * y;
  // sin y = y + y^3 (-1/3! + z (1/5! - z (1/7! - ...))), terms to y^15: truncation < 5e-17.
  const double ps =
      -1.0 / 6.0 +
      z * (1.0 / 120.0 +
           z * (-1.0 / 5040.0 +
                z * (1.0 / 362880.0 +
                     z * (-1.0 / 39916800.0 + z * (1.0 / 6227020800.0 + z * (-1.0 / 1307674368000.0))))));
  const double sin_y = y + (y * z) * ps;
  // cos y = 1 - z/2 + z^2 (1/4! - z (1/6! - ...)), terms to y^16: truncation < 3e-18. The
  // 1 - z/2 part is split (w + ((1 - w) - z/2)) so that its rounding error is kept.
  const double pc =
      1.0 / 24.0 +
      z * (-1.0 / 720.0 +
           z * (1.0 / 40320.0 +
                z * (-1.0 / 3628800.0 +
                     z * (1.0 / 479001600.0 + z * (-1.0 / 87178291200.0 + z * (1.0 / 20922789888000.0))))));
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  const double cos_y = w + (((1.0 - w) - hz) + (z * z) * pc);
  // Quadrant j: (cos, sin)(y + j pi/2) with C = cos(j pi/2) and S = sin(j pi/2) as exact
  // polynomials in j on {-2, ..., 2} (C, S in {-1, 0, 1}, so the products and sums are exact):
  // arithmetic instead of selects, so that the loop vectorises.
  const double jj = j * j;
  const double C = (6.0 - 7.0 * jj + jj * jj) / 6.0;
  const double S = j * (4.0 - jj) / 3.0;
  c = cos_y * C - sin_y * S;
  s = sin_y * C + cos_y * S;
}
}  // namespace

double remainder_two_pi(double x) {
  // x - n * 2pi with n = round-half-even(x / 2pi), the IEEE remainder, which is always exactly
  // representable. For |n| < 2^26 both n * kHi and n * kLo are exact; x - n * kHi is exact by
  // Sterbenz' lemma, and the last subtraction yields the exact remainder when n is the right
  // quotient, which |r| < pi confirms. Anything else (huge or non-finite x, a quotient next to
  // a half integer) goes to std::remainder. Bit-identical to std::remainder(x, 2pi), ~10x
  // cheaper than glibc's.
  bool ok = false;
  const double r = fast_remainder(x, ok);
  return ok ? r : std::remainder(x, kTwoPi);
}

// GCC on x86-64: an AVX2 clone (4 lanes) chosen at load time, and the baseline (SSE2, 2 lanes).
// Neither may contract into FMA (AVX2 does not imply it), so both give the same bits.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void unit_phasors(const double* __restrict phase_rad, double* __restrict c, double* __restrict s, int n) {
  // Two passes: the first, branch-free, vectorises; the second (scalar compares only) redoes
  // the rare phases the fast reduction refused (huge, non-finite, half-integer quotient).
  for (int k = 0; k < n; ++k) {
    bool ok = false;
    const double r = fast_remainder(phase_rad[k], ok);
    sincos_reduced(r, c[k], s[k]);
  }
  for (int k = 0; k < n; ++k) {
    bool ok = false;
    fast_remainder(phase_rad[k], ok);
    if (ok) continue;
    const double r = std::remainder(phase_rad[k], kTwoPi);
    if (std::abs(r) <= M_PI) {
      sincos_reduced(r, c[k], s[k]);
    } else {  // non-finite
      c[k] = std::cos(phase_rad[k]);
      s[k] = std::sin(phase_rad[k]);
    }
  }
}

}  // namespace losmimo::placement
