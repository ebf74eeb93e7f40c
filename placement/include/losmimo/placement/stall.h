#pragma once
// Escaping the local minima of one-UAV-at-a-time descent.
//
// From random starts GD and BF sometimes stall where one UAV duplicates another's "slot"
// (ICN ~ 0, f stationary at ~320 for the paper's 16 x 16 setup): no single UAV can lower f by
// a small move. The master sees this from the channel alone: f stops falling, and the UAV
// whose row weighs most in the left singular vector of H's smallest singular value is the
// redundant one. That UAV then searches farther (GD: over its lateral period under its own
// model; BF: longer probe flights), after which plain descent resumes.

#include <Eigen/Core>

#include "losmimo/placement/swarm_channel.h"

namespace losmimo::placement {

// f has not fallen by more than min_relative_decrease over `window` iterations.
class StallDetector {
 public:
  StallDetector(int window, double min_relative_decrease);
  // Feeds the objective after an iteration; true when the descent has stalled.
  bool update(double objective);
  void reset();

 private:
  int window_;
  double min_relative_decrease_;
  Eigen::VectorXd history_;
  int count_ = 0;
};

// UAVs ordered by their weight |u_n| in the left singular vector of the smallest singular
// value of H (largest first): the most redundant rows first. From CSI only.
std::vector<int> uavs_by_redundancy(const SwarmChannel& channel);

// The lateral period lambda * x / d_t (metres) at depth x: shifting a UAV by it across the BS
// array's antenna spacing d_t leaves every column's phase unchanged (mod 2 pi).
double lateral_period_m(double wavelength_m, double depth_m, double bs_spacing_m);

// The escape search of a UAV that knows (or believes) its position q_m: f under its own model
// on the lateral grid (0, i s, j s), |i|, |j| <= half_grid, s = period / (2 half_grid), around
// q_m. The default (9 x 9, s = period / 8) suits the paper's 4 x 4 BS array, whose slots are a
// quarter period apart; an n x n array's slots are period / n apart, so a 16 x 16 array needs
// half_grid >= 8 (slot spacing 1.25 m at 1 km) for the grid to reach every slot.
inline constexpr int kDefaultLateralHalfGrid = 4;
struct LateralSearch {
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();  // the best grid offset (0 if none is lower)
  double best_objective = 0.0;
  double objective_at_start = 0.0;
};
LateralSearch search_lateral_period(const UavObjective& view, const Eigen::Vector3d& q_m, double period_m,
                                    int half_grid = kDefaultLateralHalfGrid);

}  // namespace losmimo::placement
