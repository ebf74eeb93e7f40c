#pragma once
// Gradient-descent placement (paper section 3.2), one UAV at a time.
//
// Iteration i: every UAV estimates its position (Swarm::estimate_position); then each UAV m in
// turn computes grad f at the position it *believes* it has, from its modelled channel row
// and the measured rows of the others (UavObjective), and moves by
//   r = -b_i * grad f / Nr,   b_i = step * decay^(i-1).
// Normalisation: f is that of the normalised channel H / g_R (unit-modulus entries in the far
// field, see channel.h), divided by Nr: the squared off-diagonal Gram entries per UAV. The
// paper does not state its normalisation. With this one its step 0.05 reaches ICN 0.95 in
// ~87 iterations on its setup (the paper: ~78) and tolerates sigma_loc up to 0.18 m; without
// the 1/Nr the same step is 16x larger: ~19 iterations without errors, but the move then
// re-injects the localization error every iteration and ICN 0.95 is never reached at
// sigma_loc = 0.1 m (0 of 40 starts).
//
// Robustness (the paper's plain step overshoots in steep regions and stalls in local minima):
// the step is capped at max_move_m and, with backtracking on, halved until f under the UAV's
// own model decreases (at most max_halvings times; the last candidate is taken). With escape
// on, when f stalls (stall.h) the most redundant UAV evaluates f under its own model on a
// lateral grid spanning one lateral period around where it believes it is and jumps to the
// best point if that lowers f; the next stall tries the next most redundant UAV.

#include "losmimo/placement/run.h"
#include "losmimo/placement/stall.h"

namespace losmimo::placement {

struct GdOptions {
  double step = 0.05;
  double decay = 0.999;
  double max_move_m = 0.5;  // a per-iteration speed limit
  bool backtracking = true;
  int max_halvings = 6;
  bool escape = true;
  int stall_window = 20;             // iterations
  double stall_min_decrease = 0.01;  // relative decrease of f over the window
};
void validate(const GdOptions& options);

class GradientDescentPlanner : public Planner {
 public:
  GradientDescentPlanner(const Scenario& scenario, const GdOptions& options);
  std::string name() const override { return "gd"; }
  void start(Swarm& swarm) override;
  void iterate(Swarm& swarm, int iteration) override;

  // The move UAV m would command from believed position q_hat_m (exposed for tests).
  Eigen::Vector3d plan_move(const Swarm& swarm, int m, const Eigen::Vector3d& q_hat_m,
                            int iteration) const;

 private:
  bool try_escape(Swarm& swarm);

  GdOptions options_;
  double wavelength_m_;
  double bs_spacing_m_;
  StallDetector stall_;
  int escape_rank_ = 0;
};

}  // namespace losmimo::placement
