#include "losmimo/placement/swarm_shape.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>

#include <cmath>
#include <stdexcept>
#include <string>

namespace losmimo::placement {

namespace {

void check_positions(const char* what, const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m) {
  if (truth_m.cols() < 1 || truth_m.cols() != estimate_m.cols()) {
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(truth_m.cols()) + " true and " +
                                std::to_string(estimate_m.cols()) + " estimated positions");
  }
  if (!truth_m.allFinite() || !estimate_m.allFinite()) {
    throw std::invalid_argument(std::string(what) + ": a position is not finite");
  }
}

// J r_n per UAV: the lateral motion of a unit rotation about boresight through the centroid.
Eigen::Matrix2Xd rotation_field(const Eigen::Matrix3Xd& truth_m) {
  const Eigen::Vector2d centroid = truth_m.bottomRows<2>().rowwise().mean();
  Eigen::Matrix2Xd jr(2, truth_m.cols());
  for (Eigen::Index k = 0; k < truth_m.cols(); ++k) {
    const Eigen::Vector2d r = truth_m.col(k).tail<2>() - centroid;
    jr.col(k) = Eigen::Vector2d(-r.y(), r.x());
  }
  return jr;
}

}  // namespace

int shape_dof(const Eigen::Matrix3Xd& truth_m) {
  const auto n = static_cast<int>(truth_m.cols());
  if (n < 1) return 0;
  return 2 * n - 2 - (rotation_field(truth_m).squaredNorm() > 0.0 ? 1 : 0);
}

ExpectedSwarmSplit expected_split_of_independent_errors(int num_uavs, double sigma_m) {
  if (num_uavs < 1 || !std::isfinite(sigma_m) || sigma_m < 0.0) {
    throw std::invalid_argument("expected_split_of_independent_errors: " + std::to_string(num_uavs) + " UAVs, sigma " +
                                std::to_string(sigma_m) + " m");
  }
  const double n = num_uavs;
  const double dof = num_uavs >= 2 ? 2.0 * n - 3.0 : 0.0;
  return {sigma_m * std::sqrt(2.0 / n), sigma_m * std::sqrt(dof / n)};
}

double shape_nees_per_dof(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m,
                          const std::vector<Eigen::Matrix2d>& lateral_cov_m2) {
  check_positions("shape_nees_per_dof", truth_m, estimate_m);
  const Eigen::Index n = truth_m.cols();
  if (static_cast<Eigen::Index>(lateral_cov_m2.size()) != n) {
    throw std::invalid_argument("shape_nees_per_dof: " + std::to_string(lateral_cov_m2.size()) + " covariances for " +
                                std::to_string(n) + " UAVs");
  }
  const int dof = shape_dof(truth_m);
  if (dof == 0) return std::nan("");
  // The 2N-space: translations along y and z and the rotation span what the shape excludes.
  Eigen::MatrixXd excluded = Eigen::MatrixXd::Zero(2 * n, 3);
  const Eigen::Matrix2Xd jr = rotation_field(truth_m);
  Eigen::VectorXd e(2 * n);
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (Eigen::Index k = 0; k < n; ++k) {
    excluded(2 * k, 0) = 1.0;
    excluded(2 * k + 1, 1) = 1.0;
    excluded.block<2, 1>(2 * k, 2) = jr.col(k);
    e.segment<2>(2 * k) = (estimate_m.col(k) - truth_m.col(k)).tail<2>();
    const Eigen::Matrix2d& c = lateral_cov_m2[static_cast<std::size_t>(k)];
    if (!c.allFinite() || std::abs(c(0, 1) - c(1, 0)) > 1e-12 * std::abs(c.trace()) || c(0, 0) <= 0.0 ||
        c.determinant() <= 0.0) {
      throw std::invalid_argument("shape_nees_per_dof: UAV " + std::to_string(k) +
                                  "'s lateral covariance is not symmetric positive definite");
    }
    s.block<2, 2>(2 * k, 2 * k) = c;
  }
  const int kept = static_cast<int>(2 * n) - dof;  // 2 or 3 excluded directions
  const Eigen::MatrixXd q_full = Eigen::HouseholderQR<Eigen::MatrixXd>(excluded.leftCols(kept)).householderQ();
  const Eigen::MatrixXd q = q_full.rightCols(dof);
  const Eigen::VectorXd sq = q.transpose() * e;
  const Eigen::MatrixXd cq = q.transpose() * s * q;
  const Eigen::LLT<Eigen::MatrixXd> llt(cq);
  if (llt.info() != Eigen::Success) throw std::invalid_argument("shape_nees_per_dof: the shape covariance is singular");
  return sq.dot(llt.solve(sq)) / dof;
}

SwarmErrorSplit split_swarm_error(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m) {
  check_positions("split_swarm_error", truth_m, estimate_m);
  const double n = static_cast<double>(truth_m.cols());
  const Eigen::Matrix3Xd e = estimate_m - truth_m;
  SwarmErrorSplit s;
  s.common_boresight_m = e.row(0).mean();
  s.common_lateral_m = e.bottomRows<2>().rowwise().mean();
  const Eigen::Matrix2Xd jr = rotation_field(truth_m);
  const Eigen::Matrix2Xd centred = e.bottomRows<2>().colwise() - s.common_lateral_m;
  const double jr_sq = jr.squaredNorm();
  s.rotation_rad = jr_sq > 0.0 ? (jr.array() * centred.array()).sum() / jr_sq : 0.0;
  s.shape_lateral_m = centred - s.rotation_rad * jr;
  s.lateral_rmse_m = std::sqrt(e.bottomRows<2>().squaredNorm() / n);
  s.shape_lateral_rmse_m = std::sqrt(s.shape_lateral_m.squaredNorm() / n);
  return s;
}

void SwarmShapeAccumulator::add(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m) {
  const SwarmErrorSplit s = split_swarm_error(truth_m, estimate_m);
  ++epochs_;
  uav_epochs_ += truth_m.cols();
  common_sq_ += s.common_lateral_m.squaredNorm();
  shape_sq_ += s.shape_lateral_m.squaredNorm();
}

void SwarmShapeAccumulator::add(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m,
                                const std::vector<Eigen::Matrix2d>& lateral_cov_m2) {
  double nees = std::nan("");
  try {
    nees = placement::shape_nees_per_dof(truth_m, estimate_m, lateral_cov_m2);
  } catch (const std::invalid_argument&) {
    // A belief without a usable covariance (a collapsed particle cloud) leaves this epoch out
    // of the NEES only; bad positions throw from add() below.
  }
  add(truth_m, estimate_m);
  if (std::isfinite(nees)) {
    ++nees_epochs_;
    nees_sum_ += nees;
  }
}

double SwarmShapeAccumulator::shape_nees_per_dof() const {
  return nees_epochs_ > 0 ? nees_sum_ / nees_epochs_ : std::nan("");
}

double SwarmShapeAccumulator::common_lateral_rms_m() const {
  return epochs_ > 0 ? std::sqrt(common_sq_ / epochs_) : std::nan("");
}

double SwarmShapeAccumulator::shape_lateral_rmse_m() const {
  return uav_epochs_ > 0 ? std::sqrt(shape_sq_ / static_cast<double>(uav_epochs_)) : std::nan("");
}

}  // namespace losmimo::placement
