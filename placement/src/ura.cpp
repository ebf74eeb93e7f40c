#include "losmimo/placement/ura.h"

#include <cmath>
#include <stdexcept>

#include "losmimo/placement/assignment.h"

namespace losmimo::placement {

namespace {
// Lateral offsets of slot s (y, z) per metre of depth: the URA's angular layout.
Eigen::Vector2d slot_angle_rad(const Scenario& s, int slot) {
  const double lambda = s.wavelength_m();
  const int r = slot / s.bs_cols;
  const int c = slot % s.bs_cols;
  const double dy = lambda / (s.bs_cols * s.bs_spacing_m);  // d_r / depth
  const double dz = lambda / (s.bs_rows * s.bs_spacing_m);
  return {(c - 0.5 * (s.bs_cols - 1)) * dy, (r - 0.5 * (s.bs_rows - 1)) * dz};
}
}  // namespace

Eigen::Matrix3Xd optimal_ura_positions_m(const Scenario& s) {
  const Eigen::Vector3d& c = s.cube_center_m;
  Eigen::Matrix3Xd q(3, s.num_bs_antennas());
  for (int slot = 0; slot < s.num_bs_antennas(); ++slot) {
    const Eigen::Vector2d a = slot_angle_rad(s, slot);
    q.col(slot) << c.x(), c.y() + a.x() * c.x(), c.z() + a.y() * c.x();
  }
  return q;
}

UraPlanner::UraPlanner(const Scenario& scenario, UraVariant variant)
    : scenario_(scenario), variant_(variant) {
  if (scenario.num_uavs != scenario.num_bs_antennas()) {
    throw std::invalid_argument("ura: scenario.num_uavs = " + std::to_string(scenario.num_uavs) +
                                " must equal bs_rows * bs_cols = " +
                                std::to_string(scenario.num_bs_antennas()));
  }
}

Eigen::Vector3d UraPlanner::nearest_lattice_point_m(int slot, const Eigen::Vector3d& q_m) const {
  const Scenario& s = scenario_;
  const double depth = q_m.x();
  const Eigen::Vector2d a = slot_angle_rad(s, slot);
  // The centre keeps its angle from the BS, so a common lateral shift stays column-common.
  const double y0 = depth * (s.cube_center_m.y() / s.cube_center_m.x() + a.x());
  const double z0 = depth * (s.cube_center_m.z() / s.cube_center_m.x() + a.y());
  const double period = s.wavelength_m() * depth / s.bs_spacing_m;
  const double y = y0 + period * std::round((q_m.y() - y0) / period);
  const double z = z0 + period * std::round((q_m.z() - z0) / period);
  return {depth, y, z};
}

void UraPlanner::start(Swarm& swarm) {
  const int n = swarm.num_uavs();
  Eigen::Matrix3Xd q_hat(3, n);
  for (int m = 0; m < n; ++m) q_hat.col(m) = swarm.estimate_position(m);
  const Eigen::Matrix3Xd rigid = optimal_ura_positions_m(scenario_);
  Eigen::MatrixXd cost(n, n);
  for (int m = 0; m < n; ++m) {
    for (int slot = 0; slot < n; ++slot) {
      const Eigen::Vector3d target = variant_ == UraVariant::kRigid
                                         ? Eigen::Vector3d(rigid.col(slot))
                                         : nearest_lattice_point_m(slot, q_hat.col(m));
      cost(m, slot) = (target - q_hat.col(m)).norm();
    }
  }
  const std::vector<int> slot_of = min_cost_assignment(cost);
  targets_m_.resize(3, n);
  for (int m = 0; m < n; ++m) {
    targets_m_.col(m) = variant_ == UraVariant::kRigid
                            ? Eigen::Vector3d(rigid.col(slot_of[m]))
                            : nearest_lattice_point_m(slot_of[m], q_hat.col(m));
  }
}

void UraPlanner::iterate(Swarm& swarm, int /*iteration*/) {
  for (int m = 0; m < swarm.num_uavs(); ++m) {
    const Eigen::Vector3d q_hat = swarm.estimate_position(m);
    swarm.move(m, targets_m_.col(m) - q_hat, MotionKind::kPlacement);
  }
}

}  // namespace losmimo::placement
