#pragma once
// Gradient-descent placement (paper section 3.2), one UAV at a time.
//
// Iteration i: every UAV estimates its position (Swarm::estimate_position); then each UAV m in
// turn computes grad f at the position it *believes* it has, from its modelled channel row
// and the measured rows of the others (UavObjective), and moves by
//   r = -b_i * grad f / f_scale,   b_i = step * decay^(i-1).
// Normalisation: f is that of the normalised channel (unit-modulus entries in the far field,
// see channel.h) divided by f_scale = Nr, i.e. the squared off-diagonal Gram entries of H/g_R
// per UAV. With it the paper's step 0.05 moves a UAV ~0.2 m per iteration at the start, as
// the paper's distances imply (15 m in ~80 iterations).
//
// Robustness (the paper's plain step stalls in shallow local minima and overshoots in steep
// ones): the step is capped at max_move_m and, with backtracking on, halved until f under the
// UAV's own model decreases (at most max_halvings times; the last candidate is taken).

#include "losmimo/placement/run.h"

namespace losmimo::placement {

struct GdOptions {
  double step = 0.05;
  double decay = 0.999;
  double max_move_m = 1.0;
  bool backtracking = true;
  int max_halvings = 6;
};
void validate(const GdOptions& options);

class GradientDescentPlanner : public Planner {
 public:
  explicit GradientDescentPlanner(const GdOptions& options);
  std::string name() const override { return "gd"; }
  void iterate(Swarm& swarm, int iteration) override;

  // The move UAV m would command from believed position q_hat_m (exposed for tests).
  Eigen::Vector3d plan_move(const Swarm& swarm, int m, const Eigen::Vector3d& q_hat_m,
                            int iteration) const;

 private:
  GdOptions options_;
};

}  // namespace losmimo::placement
