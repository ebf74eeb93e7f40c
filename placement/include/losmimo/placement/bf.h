#pragma once
// Brute-force placement (paper section 3.3): no position information, channel measurements
// only. At iteration i each UAV m in turn tries the probe moves z in
// {0, +e1, -e1, +e2, -e2, +e3, -e3} times b_i = step * decay^(i-1): it flies there, measures
// its channel row (hence f with the others' broadcast rows) and flies back, each flight
// subject to actuation error; it then moves by b_i times the probe of least measured f.
// Probe flights are counted as probe distance, the final move as placement distance.
// Evaluation: the six probes are flown first (their actuation errors drawn in flight order),
// then their LoS rows and the "stay" value are evaluated in one pass (UavObjective::
// objectives_at, a small complex matrix product); with channel conditions each probe is a
// measurement taken in flight, one at a time. The escape's 80 probes go the same way.
// ProbeActuation::kKeptMoveOnly reads the pseudocode's probe flights as exact: each probe
// measures f at q_m + b z without an actuation error (and without a draw), and only the kept
// move has one; the probe lengths are still counted.
//
// Robustness, both location-free: (1) compass contraction: a UAV whose best probe is z = 0
// multiplies its own step by `contraction` (down to min_step_m) and grows it back by
// 1 / contraction after a successful move (1 = the paper's fixed schedule); the paper's fixed
// step oscillates around ICN ~0.93 for hundreds of iterations. (2) escape: when f stalls
// (stall.h) the most redundant UAV (from CSI) probes farther, on the lateral grid of eighths
// of the lateral period within half a period (80 probe flights, rare), and moves to the best
// point if it lowers f. Probing only along the axes left 2 of 40 paper starts stuck.

#include "losmimo/placement/run.h"
#include "losmimo/placement/stall.h"

namespace losmimo::placement {

enum class ProbeActuation { kEveryLeg, kKeptMoveOnly };
std::string to_string(ProbeActuation mode);                           // "every_leg", "kept_move_only"
ProbeActuation probe_actuation_from_string(const std::string& name);  // std::invalid_argument

struct BfOptions {
  double step = 0.3;
  double decay = 0.999;
  double contraction = 0.5;
  double min_step_m = 0.01;
  bool escape = true;
  int stall_window = 20;
  double stall_min_decrease = 0.01;
  ProbeActuation probe_actuation = ProbeActuation::kEveryLeg;
};
// The values each option accepts (validate() and the [bf] keys).
namespace bf_range {
inline constexpr common::Range step = common::Range::above_up_to(0.0, 1e6);
inline constexpr common::Range decay = common::Range::above_up_to(0.0, 1.0);
inline constexpr common::Range contraction = common::Range::above_up_to(0.0, 1.0);
inline constexpr common::Range min_step_m = common::Range::above_up_to(0.0, 1e6);
inline constexpr common::Range stall_window = common::Range::closed(1, 100000);
inline constexpr common::Range stall_min_decrease = common::Range::above_up_to(0.0, 1.0);
}  // namespace bf_range
void validate(const BfOptions& options);

// The probe moves z, unit vectors in the BS array frame: index 0 "stay" (the zero vector),
// then +e1, -e1, +e2, -e2, +e3, -e3. BruteForcePlanner::step_uav returns such an index.
inline constexpr int kBfNumProbes = 7;
// z for probe in [0, kBfNumProbes); throws std::out_of_range otherwise.
Eigen::Vector3d bf_probe_direction(int probe);

class BruteForcePlanner : public Planner {
 public:
  BruteForcePlanner(const Scenario& scenario, const BfOptions& options);
  std::string name() const override { return "bf"; }
  void start(Swarm& swarm) override;
  void iterate(Swarm& swarm, int iteration) override;
  // Probes and moves one UAV with step b (metres): it moves by b bf_probe_direction(z) for the
  // probe z of least measured f, and returns z (0: it stays).
  static int step_uav(Swarm& swarm, int m, double b, ProbeActuation probe_actuation = ProbeActuation::kEveryLeg);

 private:
  bool try_escape(Swarm& swarm);

  BfOptions options_;
  double wavelength_m_;
  double bs_spacing_m_;
  Eigen::VectorXd step_scale_;  // per-UAV compass factor in (0, 1]
  StallDetector stall_;
  int escape_rank_ = 0;
};

}  // namespace losmimo::placement
