#pragma once
// Central differences, the independent reference for every analytic derivative in the tests.
//   central_gradient:  g(i) = (f(x + h e_i) - f(x - h e_i)) / (2 h), absolute step h
//   numeric_jacobian:  J(:, j) = diff(f(x + h e_j), f(x - h e_j)) / (2 h),
//                      h = step * max(1, |x_j|); diff defaults to a - b (pass an angle-aware
//                      difference for outputs that wrap)

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>

namespace losmimo::test_support {

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

using VectorFn = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;
using DiffFn = std::function<Eigen::VectorXd(const Eigen::VectorXd&, const Eigen::VectorXd&)>;

inline Eigen::MatrixXd numeric_jacobian(const VectorFn& f, const Eigen::VectorXd& x, double step = 1e-6,
                                        const DiffFn& diff = nullptr) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const double h = step * std::max(1.0, std::abs(x(j)));
    Eigen::VectorXd xp = x;
    Eigen::VectorXd xm = x;
    xp(j) += h;
    xm(j) -= h;
    const Eigen::VectorXd fp = f(xp);
    const Eigen::VectorXd fm = f(xm);
    J.col(j) = (diff ? diff(fp, fm) : Eigen::VectorXd(fp - fm)) / (2.0 * h);
  }
  return J;
}

// Largest error of any row relative to that row's scale, max_i |A_i - N_i|_max / max(|N_i|_max,
// floor): rows are outputs with their own units (metres, radians), so each is judged on its own.
inline double jacobian_mismatch(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& numeric,
                                double scale_floor = 1e-12) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < numeric.rows(); ++i) {
    const double scale = std::max(numeric.row(i).cwiseAbs().maxCoeff(), scale_floor);
    worst = std::max(worst, (analytic.row(i) - numeric.row(i)).cwiseAbs().maxCoeff() / scale);
  }
  return worst;
}

}  // namespace losmimo::test_support
