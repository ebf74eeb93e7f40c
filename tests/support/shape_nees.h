#pragma once
// The shape residual's NEES per degree of freedom computed a second way, for tests of
// placement::shape_nees_per_dof: with the projector P = I - A (A^T A)^-1 A^T removing the common
// lateral translation and the rotation about boresight (A's three columns), the Moore-Penrose
// pseudo-inverse of P S P (eigen-decomposition, eigenvalues below 1e-9 of the largest dropped):
//   (P e)^T (P S P)^+ (P e) / rank(P S P).
// Lateral errors stacked as (y0, z0, y1, z1, ...), BS frame (x boresight), metres.

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <vector>

namespace losmimo::test_support {

inline double shape_nees_by_pseudo_inverse(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m,
                                           const std::vector<Eigen::Matrix2d>& lateral_cov_m2) {
  const Eigen::Index n = truth_m.cols();
  const Eigen::Vector2d centroid = truth_m.bottomRows<2>().rowwise().mean();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 3);
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  Eigen::VectorXd e(2 * n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Vector2d r = truth_m.col(k).tail<2>() - centroid;
    a(2 * k, 0) = 1.0;
    a(2 * k + 1, 1) = 1.0;
    a(2 * k, 2) = -r.y();
    a(2 * k + 1, 2) = r.x();
    s.block<2, 2>(2 * k, 2 * k) = lateral_cov_m2[static_cast<std::size_t>(k)];
    e.segment<2>(2 * k) = (estimate_m.col(k) - truth_m.col(k)).tail<2>();
  }
  const Eigen::MatrixXd p = Eigen::MatrixXd::Identity(2 * n, 2 * n) - a * (a.transpose() * a).inverse() * a.transpose();
  const Eigen::MatrixXd c = p * s * p;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (c + c.transpose()));
  const double top = eig.eigenvalues().maxCoeff();
  const Eigen::VectorXd pe = p * e;
  double nees = 0.0;
  int rank = 0;
  for (Eigen::Index i = 0; i < eig.eigenvalues().size(); ++i) {
    if (eig.eigenvalues()(i) <= 1e-9 * top) continue;
    const double proj = eig.eigenvectors().col(i).dot(pe);
    nees += proj * proj / eig.eigenvalues()(i);
    ++rank;
  }
  return nees / rank;
}

}  // namespace losmimo::test_support
