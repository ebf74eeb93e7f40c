#pragma once
// Central differences, the independent reference for every analytic derivative in the tests.

#include <Eigen/Core>
#include <functional>

namespace losmimo::test {

// d f / d x at x by central differences with step h per coordinate.
template <int N>
Eigen::Matrix<double, N, 1> central_gradient(const std::function<double(const Eigen::Matrix<double, N, 1>&)>& f,
                                             const Eigen::Matrix<double, N, 1>& x, double h) {
  Eigen::Matrix<double, N, 1> g(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Eigen::Matrix<double, N, 1> xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    g(i) = (f(xp) - f(xm)) / (2.0 * h);
  }
  return g;
}

// Jacobian of a vector function by central differences.
inline Eigen::MatrixXd central_jacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                        const Eigen::VectorXd& x, double h) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    J.col(i) = (f(xp) - f(xm)) / (2.0 * h);
  }
  return J;
}

}  // namespace losmimo::test
