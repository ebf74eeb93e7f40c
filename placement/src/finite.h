#pragma once
// Finiteness checks of whole arrays (internal to the placement library): the health check after
// every iteration (run.cpp) and the Gram planes' (swarm_channel.cpp).

#include <Eigen/Core>
#include <complex>

namespace losmimo::placement::detail {

// Every one of the n values finite: the sum of x * 0 is 0 when every x is finite and NaN
// otherwise (inf * 0 is NaN), a reduction Eigen vectorises. (A test that stops at the first
// bad entry, like Eigen's allFinite, branches on every one.)
inline bool all_finite(const double* values, Eigen::Index n) {
  return (Eigen::Map<const Eigen::ArrayXd>(values, n) * 0.0).sum() == 0.0;
}

// The same for a dense matrix of doubles or of complex numbers (their real and imaginary parts).
template <typename Scalar, int Rows, int Cols, int Options, int MaxRows, int MaxCols>
bool all_finite(const Eigen::Matrix<Scalar, Rows, Cols, Options, MaxRows, MaxCols>& m) {
  constexpr Eigen::Index kDoubles = sizeof(Scalar) / sizeof(double);
  static_assert(sizeof(Scalar) == kDoubles * sizeof(double), "a matrix of doubles or std::complex<double>");
  return all_finite(reinterpret_cast<const double*>(m.data()), kDoubles * m.size());
}

}  // namespace losmimo::placement::detail
