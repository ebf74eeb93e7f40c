#include "losmimo/placement/ura.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "losmimo/placement/common/field_error.h"
#include "losmimo/placement/assignment.h"

namespace losmimo::placement {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Lateral offsets of slot s (y, z) per metre of depth: the URA's angular layout (spacing
// multiple k).
Eigen::Vector2d slot_angle_rad(const Scenario& s, int slot, int k) {
  const double lambda = s.wavelength_m();
  const int r = slot / s.bs_cols;
  const int c = slot % s.bs_cols;
  double dy = lambda / (s.bs_cols * s.bs_spacing_m);  // d_r / depth
  double dz = lambda / (s.bs_rows * s.bs_spacing_m);
  if (k != 1) {
    dy *= k;
    dz *= k;
  }
  return {(c - 0.5 * (s.bs_cols - 1)) * dy, (r - 0.5 * (s.bs_rows - 1)) * dz};
}

int gcd(int a, int b) { return b == 0 ? a : gcd(b, a % b); }
}  // namespace

std::string to_string(UraDepth depth) { return depth == UraDepth::kOwn ? "own" : "plane"; }

std::string to_string(UraRetry retry) {
  switch (retry) {
    case UraRetry::kEveryIteration:
      return "every_iteration";
    case UraRetry::kOnce:
      return "once";
    case UraRetry::kAverage:
      return "average";
  }
  return "every_iteration";
}

UraDepth ura_depth_from_string(const std::string& name) {
  if (name == "plane") return UraDepth::kPlane;
  if (name == "own") return UraDepth::kOwn;
  throw std::invalid_argument("unknown URA depth '" + name + "' (known: plane, own)");
}

UraRetry ura_retry_from_string(const std::string& name) {
  if (name == "every_iteration") return UraRetry::kEveryIteration;
  if (name == "once") return UraRetry::kOnce;
  if (name == "average") return UraRetry::kAverage;
  throw std::invalid_argument("unknown URA retry rule '" + name + "' (known: every_iteration, once, average)");
}

void validate(const UraOptions& o) {
  if (o.spacing_multiple < 1 || o.spacing_multiple > 64) {
    throw common::FieldError("spacing_multiple",
                             "ura.spacing_multiple = " + std::to_string(o.spacing_multiple) + ": must be in [1, 64]");
  }
}

void validate(const UraOptions& o, const Scenario& s) {
  validate(o);
  if (gcd(o.spacing_multiple, s.bs_rows) != 1 || gcd(o.spacing_multiple, s.bs_cols) != 1) {
    throw common::FieldError("spacing_multiple", "ura.spacing_multiple = " + std::to_string(o.spacing_multiple) +
                                                     ": must be coprime with the BS array's " +
                                                     std::to_string(s.bs_rows) + " rows and " +
                                                     std::to_string(s.bs_cols) + " columns");
  }
}

Eigen::Matrix3Xd optimal_ura_positions_m(const Scenario& s, int spacing_multiple) {
  const Eigen::Vector3d& c = s.cube_center_m;
  Eigen::Matrix3Xd q(3, s.num_bs_antennas());
  for (int slot = 0; slot < s.num_bs_antennas(); ++slot) {
    const Eigen::Vector2d a = slot_angle_rad(s, slot, spacing_multiple);
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

UraPlanner::UraPlanner(const Scenario& scenario, UraVariant variant, const UraOptions& options)
    : scenario_(scenario), variant_(variant), options_(options) {
  validate(options_, scenario);
  if (scenario.num_uavs > scenario.num_bs_antennas()) {
    throw std::invalid_argument("ura: scenario.num_uavs = " + std::to_string(scenario.num_uavs) +
                                " must be at most bs_rows * bs_cols = " + std::to_string(scenario.num_bs_antennas()));
  }
}

std::string UraPlanner::name() const {
  switch (variant_) {
    case UraVariant::kRigid:
      return "ura";
    case UraVariant::kLattice:
      return "ura_lattice";
    case UraVariant::kLatticeExact:
      return "ura_lattice_exact";
  }
  return "ura";
}

Eigen::Vector3d UraPlanner::nearest_lattice_point_m(int slot, const Eigen::Vector3d& q_m) const {
  const Scenario& s = scenario_;
  if (variant_ == UraVariant::kLatticeExact) return nearest_exact_lattice_point_m(slot, q_m);
  const double depth = q_m.x();
  const Eigen::Vector2d a = slot_angle_rad(s, slot, options_.spacing_multiple);
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
  const Eigen::Vector2d a = slot_angle_rad(s, slot, options_.spacing_multiple);
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
  const Eigen::Matrix3Xd rigid = optimal_ura_positions_m(scenario_, options_.spacing_multiple);
  const bool own_depth = variant_ == UraVariant::kRigid && options_.depth == UraDepth::kOwn;
  // The rigid slot at the UAV's own depth: the same direction from the BS as the slot at R.
  const auto at_own_depth = [&](int slot, const Eigen::Vector3d& q) {
    const double scale = q.x() / scenario_.cube_center_m.x();
    return Eigen::Vector3d(q.x(), rigid(1, slot) * scale, rigid(2, slot) * scale);
  };
  const auto target_of = [&](int m, int slot) -> Eigen::Vector3d {
    if (variant_ != UraVariant::kRigid) return nearest_lattice_point_m(slot, q_hat.col(m));
    if (own_depth) return at_own_depth(slot, q_hat.col(m));
    return rigid.col(slot);
  };
  // n x Nt: with fewer UAVs than slots the assignment also picks which slots are used.
  const int slots = static_cast<int>(rigid.cols());
  Eigen::MatrixXd cost(n, slots);
  for (int m = 0; m < n; ++m) {
    for (int slot = 0; slot < slots; ++slot) cost(m, slot) = (target_of(m, slot) - q_hat.col(m)).norm();
  }
  const std::vector<int> slot_of = min_cost_assignment(cost);
  targets_m_.resize(3, n);
  for (int m = 0; m < n; ++m) targets_m_.col(m) = target_of(m, slot_of[m]);
  commanded_ = false;
  if (options_.retry == UraRetry::kAverage) {
    start_sum_m_ = Eigen::Matrix3Xd::Zero(3, n);
    commanded_sum_m_ = Eigen::Matrix3Xd::Zero(3, n);
    estimates_ = 0;
  }
}

std::optional<Eigen::Matrix3Xd> UraPlanner::believed_positions() const {
  if (!commanded_) return std::nullopt;
  return targets_m_;
}

void UraPlanner::iterate(Swarm& swarm, int iteration) {
  if (options_.retry == UraRetry::kOnce && iteration > 1) return;
  commanded_ = true;
  if (options_.retry == UraRetry::kAverage) {
    // The start is estimated once per iteration (estimate - moves commanded so far); the
    // running mean of those estimates, plus the moves, is where the UAV believes it is.
    ++estimates_;
    for (int m = 0; m < swarm.num_uavs(); ++m) {
      start_sum_m_.col(m) += swarm.estimate_position(m) - commanded_sum_m_.col(m);
      const Eigen::Vector3d q_hat = start_sum_m_.col(m) / estimates_ + commanded_sum_m_.col(m);
      const Eigen::Vector3d r = targets_m_.col(m) - q_hat;
      swarm.move(m, r, MotionKind::kPlacement, false);
      commanded_sum_m_.col(m) += r;
    }
  } else {
    for (int m = 0; m < swarm.num_uavs(); ++m) {
      const Eigen::Vector3d q_hat = swarm.estimate_position(m);
      swarm.move(m, targets_m_.col(m) - q_hat, MotionKind::kPlacement, false);
    }
  }
  // No UAV measures the channel during the iteration: every row and G at once, at the end.
  swarm.sync_channels();
}

}  // namespace losmimo::placement
