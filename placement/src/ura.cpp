#include "losmimo/placement/ura.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "losmimo/placement/assignment.h"

namespace losmimo::placement {

namespace {
constexpr double kPi = 3.14159265358979323846;

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

double lattice_depth_band_m(const Scenario& s) {
  const double half_y = 0.5 * (s.bs_cols - 1) * s.bs_spacing_m;
  const double half_z = 0.5 * (s.bs_rows - 1) * s.bs_spacing_m;
  const double rho_max_sq = half_y * half_y + half_z * half_z;
  const double range = s.cube_center_m.norm();
  if (!(rho_max_sq > 0.0)) return std::numeric_limits<double>::infinity();
  return kLatticeFresnelTolerance_rad * s.wavelength_m() * range * range / (kPi * rho_max_sq);
}

UraPlanner::UraPlanner(const Scenario& scenario, UraVariant variant)
    : scenario_(scenario), variant_(variant) {
  if (scenario.num_uavs > scenario.num_bs_antennas()) {
    throw std::invalid_argument("ura: scenario.num_uavs = " + std::to_string(scenario.num_uavs) +
                                " must be at most bs_rows * bs_cols = " +
                                std::to_string(scenario.num_bs_antennas()));
  }
}

std::string UraPlanner::name() const {
  switch (variant_) {
    case UraVariant::kRigid: return "ura";
    case UraVariant::kLattice: return "ura_lattice";
    case UraVariant::kLatticeExact: return "ura_lattice_exact";
  }
  return "ura";
}

Eigen::Vector3d UraPlanner::nearest_lattice_point_m(int slot, const Eigen::Vector3d& q_m) const {
  const Scenario& s = scenario_;
  if (variant_ == UraVariant::kLatticeExact) return nearest_exact_lattice_point_m(slot, q_m);
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

Eigen::Vector3d UraPlanner::nearest_exact_lattice_point_m(int slot, const Eigen::Vector3d& q_m) const {
  const Scenario& s = scenario_;
  const Eigen::Vector3d& c = s.cube_center_m;
  const double band = lattice_depth_band_m(s);
  const double depth = std::clamp(q_m.x(), c.x() - band, c.x() + band);
  // Direction cosines (u, v) = (y, z) / |q|: the slot's, shifted by whole periods lambda / d_t
  // to the nearest of the UAV's own.
  const Eigen::Vector2d a = slot_angle_rad(s, slot);
  const double u0 = c.y() / c.norm() + a.x();
  const double v0 = c.z() / c.norm() + a.y();
  const double period = s.wavelength_m() / s.bs_spacing_m;
  const double u = u0 + period * std::round((q_m.y() / q_m.norm() - u0) / period);
  const double v = v0 + period * std::round((q_m.z() / q_m.norm() - v0) / period);
  const double range = depth / std::sqrt(1.0 - u * u - v * v);
  return {depth, u * range, v * range};
}

void UraPlanner::start(Swarm& swarm) {
  const int n = swarm.num_uavs();
  Eigen::Matrix3Xd q_hat(3, n);
  for (int m = 0; m < n; ++m) q_hat.col(m) = swarm.estimate_position(m);
  const Eigen::Matrix3Xd rigid = optimal_ura_positions_m(scenario_);
  // n x Nt: with fewer UAVs than slots the assignment also picks which slots are used.
  const int slots = static_cast<int>(rigid.cols());
  Eigen::MatrixXd cost(n, slots);
  for (int m = 0; m < n; ++m) {
    for (int slot = 0; slot < slots; ++slot) {
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
