#include "losmimo/placement/channel.h"

#include <cmath>
#include <complex>

namespace losmimo::placement {

double remainder_two_pi(double x) {
  // x - n * 2pi with n = round-half-even(x / 2pi), the IEEE remainder, which is always exactly
  // representable. 2pi (the double) = kHi + kLo with kHi of 26 significant bits, so for
  // |n| < 2^26 both n * kHi and n * kLo are exact; x - n * kHi is exact by Sterbenz' lemma, and
  // the last subtraction yields the exact remainder when n is the right quotient, which
  // |r| < pi confirms. Anything else (huge or non-finite x, a quotient next to a half
  // integer) goes to std::remainder. The result is bit-identical to std::remainder(x, 2pi),
  // about 10x cheaper than glibc's.
  constexpr double kTwoPi = 2.0 * M_PI;
  constexpr double kHi = 6.2831852436065673828125;  // kTwoPi with its low 27 bits cleared
  constexpr double kLo = kTwoPi - kHi;
  constexpr double kMaxAbs = 4.0e8;               // |n| < 2^26 = 6.7e7
  constexpr double kRound = 6755399441055744.0;   // 1.5 * 2^52: q + kRound - kRound = rint(q)
  if (!(std::abs(x) < kMaxAbs)) return std::remainder(x, kTwoPi);
  const double n = (x / kTwoPi + kRound) - kRound;  // not reassociated without -ffast-math
  const double r = (x - n * kHi) - n * kLo;
  if (std::abs(r) < 0.5 * kTwoPi) return r;
  return std::remainder(x, kTwoPi);
}

ChannelModel::ChannelModel(const Scenario& scenario)
    : antennas_m_(bs_antenna_positions_m(scenario)),
      wavenumber_rad_per_m_(2.0 * M_PI / scenario.wavelength_m()),
      range_m_(scenario.range_m()),
      gain_model_(scenario.gain_model) {}

Eigen::VectorXcd ChannelModel::row(const Eigen::Vector3d& q_m) const {
  Eigen::VectorXcd x;
  row(q_m, x);
  return x;
}

void ChannelModel::row(const Eigen::Vector3d& q_m, Eigen::VectorXcd& x) const {
  const int nt = num_antennas();
  x.resize(nt);
  for (int k = 0; k < nt; ++k) {
    const double d_m = (q_m - antennas_m_.col(k)).norm();
    // Reduce the phase before sincos: d / lambda is ~2e5 cycles at 1 km and 60 GHz.
    const double phase_rad = -wavenumber_rad_per_m_ * d_m;
    const double amplitude = gain_model_ == GainModel::kExact ? range_m_ / d_m : 1.0;
    x(k) = std::polar(amplitude, remainder_two_pi(phase_rad));
  }
}

Eigen::MatrixXcd ChannelModel::matrix(const Eigen::Matrix3Xd& q_m) const {
  Eigen::MatrixXcd H(q_m.cols(), num_antennas());
  for (Eigen::Index n = 0; n < q_m.cols(); ++n) H.row(n) = row(q_m.col(n)).transpose();
  return H;
}

void ChannelModel::row_derivative_terms(const Eigen::Vector3d& q_m, Eigen::VectorXcd& s,
                                        Eigen::Matrix3Xd& U) const {
  const int nt = num_antennas();
  s.resize(nt);
  U.resize(3, nt);
  for (int k = 0; k < nt; ++k) {
    const Eigen::Vector3d v = q_m - antennas_m_.col(k);
    const double d_m = v.norm();
    U.col(k) = v / d_m;
    const double radial = gain_model_ == GainModel::kExact ? -1.0 / d_m : 0.0;
    s(k) = std::complex<double>(radial, -wavenumber_rad_per_m_);
  }
}

}  // namespace losmimo::placement
