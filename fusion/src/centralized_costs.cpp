// The two smooth costs of the centralized solver (centralized.h): the penalty J_mu on f and
// the log barrier B_t on the ICN constraint, with their gradients.
#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <limits>

#include "losmimo/fusion/centralized.h"
#include "losmimo/placement/swarm_channel.h"

namespace losmimo::fusion {

double penalized_travel_cost(const placement::ChannelModel& model, const Eigen::Matrix3Xd& start_m, double mu,
                             const Eigen::Matrix3Xd& q_m, Eigen::Matrix3Xd* gradient) {
  const placement::SwarmChannel swarm(model, q_m);
  const double cost = (q_m - start_m).squaredNorm() + mu * swarm.objective();
  if (gradient != nullptr) {
    gradient->resize(3, q_m.cols());
    for (Eigen::Index m = 0; m < q_m.cols(); ++m) {
      const placement::UavObjective uav(swarm, static_cast<int>(m));
      gradient->col(m) = 2.0 * (q_m.col(m) - start_m.col(m)) + mu * uav.gradient_at(q_m.col(m));
    }
  }
  return cost;
}

double barrier_travel_cost(const placement::ChannelModel& model, const Eigen::Matrix3Xd& start_m, double alpha,
                           double t, const Eigen::Matrix3Xd& q_m, Eigen::Matrix3Xd* gradient) {
  const Eigen::MatrixXcd H = model.matrix(q_m);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(H.adjoint() * H);
  const Eigen::Index nt = H.cols();
  if (eig.info() != Eigen::Success || H.rows() < nt) return std::numeric_limits<double>::infinity();
  const double lambda_min = eig.eigenvalues()(0);
  const double lambda_max = eig.eigenvalues()(nt - 1);
  const double g = lambda_min - alpha * alpha * lambda_max;
  if (!(g > 0.0)) return std::numeric_limits<double>::infinity();
  const double cost = (q_m - start_m).squaredNorm() - t * std::log(g);
  if (gradient != nullptr) {
    const Eigen::VectorXcd v_min = eig.eigenvectors().col(0);
    const Eigen::VectorXcd v_max = eig.eigenvectors().col(nt - 1);
    const Eigen::VectorXcd a_min = H * v_min;  // x_m^T v for every UAV m
    const Eigen::VectorXcd a_max = H * v_max;
    gradient->resize(3, q_m.cols());
    Eigen::VectorXcd s;
    Eigen::Matrix3Xd U;
    for (Eigen::Index m = 0; m < q_m.cols(); ++m) {
      model.row_derivative_terms(q_m.col(m), s, U);
      Eigen::Vector3d grad_g = Eigen::Vector3d::Zero();
      for (Eigen::Index k = 0; k < nt; ++k) {
        const std::complex<double> xs = H(m, k) * s(k);
        const double d_min = 2.0 * (std::conj(a_min(m)) * v_min(k) * xs).real();
        const double d_max = 2.0 * (std::conj(a_max(m)) * v_max(k) * xs).real();
        grad_g += (d_min - alpha * alpha * d_max) * U.col(k);
      }
      gradient->col(m) = 2.0 * (q_m.col(m) - start_m.col(m)) - (t / g) * grad_g;
    }
  }
  return cost;
}

}  // namespace losmimo::fusion
