#pragma once
// Brute-force placement (paper section 3.3): no position information, channel measurements
// only. At iteration i each UAV m in turn tries the probe moves z in
// {0, +e1, -e1, +e2, -e2, +e3, -e3} times b_i = step * decay^(i-1): it flies there, measures
// its channel row (hence f with the others' broadcast rows) and flies back, each flight
// subject to actuation error; it then moves by b_i times the probe of least measured f.
// Probe flights are counted as probe distance, the final move as placement distance.

#include "losmimo/placement/run.h"

namespace losmimo::placement {

struct BfOptions {
  double step = 0.3;
  double decay = 0.999;
};
void validate(const BfOptions& options);

class BruteForcePlanner : public Planner {
 public:
  explicit BruteForcePlanner(const BfOptions& options);
  std::string name() const override { return "bf"; }
  void iterate(Swarm& swarm, int iteration) override;
  // Probes and moves one UAV; returns the index (0..6) of the chosen probe.
  int step_uav(Swarm& swarm, int m, int iteration) const;

 private:
  BfOptions options_;
};

}  // namespace losmimo::placement
