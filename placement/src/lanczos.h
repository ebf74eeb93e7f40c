#pragma once
// Lanczos with full reorthogonalisation on a Hermitian matrix (internal to the placement
// library): the ICN test's Ritz values (run.cpp) and the smallest eigenvector behind the UAVs'
// redundancy order (stall.cpp).

#include <Eigen/Core>

namespace losmimo::placement::detail {

// Up to `steps` Lanczos steps on G (n x n Hermitian) from G's heaviest column: V (n x k)
// orthonormal, T = V^H G V real tridiagonal with diagonal alpha (k) and subdiagonal beta (k - 1).
// Returns k, fewer than `steps` when the Krylov space is invariant (then T's eigenvalues are
// eigenvalues of G) and 0 for a zero G. Each new vector is orthogonalised against all earlier
// ones (twice where the first pass cancels most of it), so V stays orthonormal to rounding.
Eigen::Index lanczos(const Eigen::MatrixXcd& G, Eigen::Index steps, Eigen::MatrixXcd& V, Eigen::VectorXd& alpha,
                     Eigen::VectorXd& beta);

// The smallest eigenvalue of the real symmetric tridiagonal T (diagonal alpha, subdiagonal
// beta) by Sturm-sequence bisection to 1e-7 ||T|| (*lambda, if given), and its unit
// eigenvector by inverse iteration: five solves, rounding-exact unless the two smallest
// eigenvalues lie within ~1e-4 ||T|| of each other. Eigen's tridiagonal QR takes ~8 us for 16 x 16 even without
// vectors; this takes well under one.
Eigen::VectorXd smallest_tridiagonal_eigenvector(const Eigen::VectorXd& alpha, const Eigen::VectorXd& beta,
                                                 double* lambda = nullptr);

}  // namespace losmimo::placement::detail
