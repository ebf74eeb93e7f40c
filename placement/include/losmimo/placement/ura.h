#pragma once
// Uniform rectangular array (URA) baseline (paper section 4, Bohagen et al. 2007).
//
// The optimal receive URA for a BS URA with spacing d_t and n elements along an axis has, at
// depth x, spacing d_r = lambda x / (n d_t) along that axis: then H has orthogonal columns.
// Rigid variant: the URA at the start cube's centre (depth R). Each UAV gets a slot by a
// minimum-total-distance assignment (Hungarian) of its first position estimate.
// Lattice variant: orthogonality survives (in the paraxial approximation) moving a UAV along
// the link (any depth x) and shifting it laterally by whole periods lambda x / d_t, so a slot
// is a lattice of points; each UAV's cost to a slot is the distance to its nearest point at
// the UAV's own depth, which travels far less (ICN ~0.99 instead of 1: the approximation).
// Every iteration each UAV re-estimates its position and commands the move to its target
// (target - believed position), so localization and actuation errors are retried away.
// Needs num_uavs == bs_rows * bs_cols.

#include "losmimo/placement/run.h"

namespace losmimo::placement {

enum class UraVariant { kRigid, kLattice };

// Slot positions of the rigid URA at depth R (3 x Nt, same order as the BS antennas).
Eigen::Matrix3Xd optimal_ura_positions_m(const Scenario& scenario);

class UraPlanner : public Planner {
 public:
  UraPlanner(const Scenario& scenario, UraVariant variant);
  std::string name() const override { return variant_ == UraVariant::kRigid ? "ura" : "ura_lattice"; }
  void start(Swarm& swarm) override;
  void iterate(Swarm& swarm, int iteration) override;

  // Targets chosen by start() (3 x Nr).
  const Eigen::Matrix3Xd& targets_m() const { return targets_m_; }
  // Nearest lattice-equivalent point of slot s to position q (lattice variant).
  Eigen::Vector3d nearest_lattice_point_m(int slot, const Eigen::Vector3d& q_m) const;

 private:
  Scenario scenario_;
  UraVariant variant_;
  Eigen::Matrix3Xd targets_m_;
};

}  // namespace losmimo::placement
