#include "losmimo/placement/swarm_shape.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace losmimo::placement {

SwarmErrorSplit split_swarm_error(const Eigen::Matrix3Xd& truth_m, const Eigen::Matrix3Xd& estimate_m) {
  if (truth_m.cols() < 1 || truth_m.cols() != estimate_m.cols()) {
    throw std::invalid_argument("split_swarm_error: " + std::to_string(truth_m.cols()) + " true and " +
                                std::to_string(estimate_m.cols()) + " estimated positions");
  }
  if (!truth_m.allFinite() || !estimate_m.allFinite()) {
    throw std::invalid_argument("split_swarm_error: a position is not finite");
  }
  const double n = static_cast<double>(truth_m.cols());
  const Eigen::Matrix3Xd e = estimate_m - truth_m;
  SwarmErrorSplit s;
  s.common_boresight_m = e.row(0).mean();
  s.common_lateral_m = e.bottomRows<2>().rowwise().mean();
  const Eigen::Vector2d centroid = truth_m.bottomRows<2>().rowwise().mean();
  Eigen::Matrix2Xd jr(2, truth_m.cols());  // J r_n
  for (Eigen::Index k = 0; k < truth_m.cols(); ++k) {
    const Eigen::Vector2d r = truth_m.col(k).tail<2>() - centroid;
    jr.col(k) = Eigen::Vector2d(-r.y(), r.x());
  }
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

double SwarmShapeAccumulator::common_lateral_rms_m() const {
  return epochs_ > 0 ? std::sqrt(common_sq_ / epochs_) : std::nan("");
}

double SwarmShapeAccumulator::shape_lateral_rmse_m() const {
  return uav_epochs_ > 0 ? std::sqrt(shape_sq_ / static_cast<double>(uav_epochs_)) : std::nan("");
}

}  // namespace losmimo::placement
