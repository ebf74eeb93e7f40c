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
//
// Large swarms (e.g. 256 UAVs, BS 16 x 16): from a random start about a third of the UAVs
// share a slot with another (slots are period / n apart on an n x n BS array), and a single UAV
// step cannot cross an occupied slot, so f stalls within ~20 iterations. Three options, whose
// defaults are the paper-setup behaviour above, scale GD with the array:
// - escape_half_grid: the lateral grid must resolve slots period / n apart (half_grid >= n / 2);
// - escape_uavs: how many of the most redundant UAVs search at each stall, in turn;
// - depth_step_gain: near the optimum the remaining error is the BS aperture's Fresnel phase
//   of UAVs at different depths (ura.h), along which f varies ~x / rho times more slowly than
//   laterally; with gain 1 GD stalls there (ICN 0.943 on 16 x 16).
// Measured on 16 x 16 from a random start (tests/bench/bench_placement.cpp, Swarm256): with
// half grid 8, 32 UAVs per stall, stall window 10 and depth gain 1000, ICN 0.95 in ~410
// iterations.

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
  // Escape search grid: (2 h + 1)^2 lateral points, spaced period / (2 h) (stall.h).
  int escape_half_grid = kDefaultLateralHalfGrid;
  // UAVs that search at each stall, the most redundant first (each with the others' moves so far).
  int escape_uavs = 1;
  // Multiplies the depth (x, along the link) component of the step before the cap. f varies
  // along the link only through the BS aperture's Fresnel phase pi rho^2 / (lambda x), about
  // x / rho times more slowly than laterally, so a large array needs a gain of that order for
  // the UAVs to even out their depths; 1 leaves the step as the paper's.
  double depth_step_gain = 1.0;
};
// The values each option accepts (validate() and the [gd] keys).
namespace gd_range {
inline constexpr common::Range step = common::Range::above(0.0);
inline constexpr common::Range decay = common::Range::above_up_to(0.0, 1.0);
inline constexpr common::Range max_move_m = common::Range::above(0.0);
inline constexpr common::Range max_halvings = common::Range::closed(0, 60);
inline constexpr common::Range stall_window = common::Range::closed(1, 100000);
inline constexpr common::Range stall_min_decrease = common::Range::above(0.0);
inline constexpr common::Range escape_half_grid = common::Range::closed(1, 256);
inline constexpr common::Range escape_uavs = common::Range::closed(1, 100000);
inline constexpr common::Range depth_step_gain = common::Range::above(0.0);
}  // namespace gd_range
void validate(const GdOptions& options);

class GradientDescentPlanner : public Planner {
 public:
  GradientDescentPlanner(const Scenario& scenario, const GdOptions& options);
  std::string name() const override { return "gd"; }
  void start(Swarm& swarm) override;
  void iterate(Swarm& swarm, int iteration) override;
  // Each UAV's estimate at the last iteration plus the moves it commanded since.
  std::optional<Eigen::Matrix3Xd> believed_positions() const override;

  // The move UAV m would command from believed position q_hat_m (exposed for tests).
  Eigen::Vector3d plan_move(const Swarm& swarm, int m, const Eigen::Vector3d& q_hat_m, int iteration) const;

 private:
  // plan_move with the iteration's base step b = step * decay^(iteration - 1).
  Eigen::Vector3d plan_step(const Swarm& swarm, int m, const Eigen::Vector3d& q_hat_m, double b) const;
  bool try_escape(Swarm& swarm);

  GdOptions options_;
  double wavelength_m_;
  double bs_spacing_m_;
  StallDetector stall_;
  int escape_rank_ = 0;
  Eigen::Matrix3Xd believed_m_;  // empty before the first iteration
};

}  // namespace losmimo::placement
