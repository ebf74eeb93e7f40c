#pragma once
// The swarm pass that GD and the capacity planner share (internal to the placement library):
// the paper's master loop of a planner that acts on believed positions.

#include <Eigen/Core>
#include <cmath>

#include "losmimo/placement/swarm.h"

namespace losmimo::placement::detail {

// b_i = step * decay^(i - 1): the base step of iteration i (counted from 1).
inline double decayed_step(double step, double decay, int iteration) { return step * std::pow(decay, iteration - 1); }

// One iteration over the swarm: every UAV estimates its position first (estimatePositionAll()),
// then each UAV m in turn, in UAV order and seeing the moves of those before it, commands
// r = plan(m, q_hat_m) and flies it (MotionKind::kPlacement). believed_m (3 x Nr on return) is
// each UAV's estimate plus the move it commanded: the planner's belief.
template <typename Plan>
void estimate_then_move_each(Swarm& swarm, Eigen::Matrix3Xd& believed_m, const Plan& plan) {
  const int nr = swarm.num_uavs();
  believed_m.resize(3, nr);
  for (int m = 0; m < nr; ++m) believed_m.col(m) = swarm.estimate_position(m);
  for (int m = 0; m < nr; ++m) {
    const Eigen::Vector3d r = plan(m, Eigen::Vector3d(believed_m.col(m)));
    swarm.move(m, r, MotionKind::kPlacement);
    believed_m.col(m) += r;
  }
}

}  // namespace losmimo::placement::detail
