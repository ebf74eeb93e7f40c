#pragma once
// Lanczos with full reorthogonalisation on a Hermitian matrix (internal to the placement
// library): the ICN test's Ritz values (icn_below.cpp) and the smallest eigenvector behind the
// UAVs' redundancy order (stall.cpp).

#include <Eigen/Core>
#include <vector>

#include "losmimo/placement/kernels.h"

namespace losmimo::placement::detail {

// The Lanczos vectors in split planes (kernels.h): vector j is (re + j ld, im + j ld), ld
// entries, pads 0. T = V^H G V is real tridiagonal: diagonal alpha (k), subdiagonal beta (k - 1).
struct LanczosBasis {
  int ld = 0;
  std::vector<double> re, im;
  Eigen::VectorXd alpha, beta;
};

// Up to `steps` Lanczos steps on G (n x n Hermitian, split planes) from G's heaviest column,
// the products G v by the kernels' hermitian_matvec. Returns k, fewer than `steps` when the
// Krylov space is invariant (then T's eigenvalues are eigenvalues of G) and 0 for a zero G.
// Each new vector is orthogonalised against all earlier ones (twice where the first pass
// cancels most of it), so V stays orthonormal to rounding.
Eigen::Index lanczos(const kernels::Kernels& kern, const kernels::GramPlanes& G, Eigen::Index steps,
                     LanczosBasis& basis);

// V s (n entries) for the Lanczos vectors of `basis` and real coefficients s (one per vector).
Eigen::VectorXcd combine(const LanczosBasis& basis, int n, const Eigen::VectorXd& s);

// A dense Hermitian matrix copied into split planes (ld = kernels::padded(n)), for the
// Lanczos of a matrix a swarm does not keep as planes.
class DensePlanes {
 public:
  explicit DensePlanes(const Eigen::MatrixXcd& G);
  kernels::GramPlanes planes() const { return {n_, ld_, re_.data(), im_.data()}; }

 private:
  int n_, ld_;
  std::vector<double> re_, im_;
};

// The smallest eigenvalue of the real symmetric tridiagonal T (diagonal alpha, subdiagonal
// beta) by Sturm-sequence bisection to 1e-7 ||T|| (*lambda, if given), and its unit
// eigenvector by inverse iteration: five solves, rounding-exact unless the two smallest
// eigenvalues lie within ~1e-4 ||T|| of each other. Eigen's tridiagonal QR takes ~8 us for 16 x 16 even without
// vectors; this takes well under one.
Eigen::VectorXd smallest_tridiagonal_eigenvector(const Eigen::VectorXd& alpha, const Eigen::VectorXd& beta,
                                                 double* lambda = nullptr);

}  // namespace losmimo::placement::detail
