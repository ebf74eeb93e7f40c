#include "losmimo/placement/bf.h"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace losmimo::placement {

void validate(const BfOptions& o) {
  if (!(o.step > 0.0) || !std::isfinite(o.step)) {
    std::ostringstream msg;
    msg << "bf.step = " << o.step << ": must be a finite positive number";
    throw std::invalid_argument(msg.str());
  }
  if (!(o.decay > 0.0 && o.decay <= 1.0)) {
    std::ostringstream msg;
    msg << "bf.decay = " << o.decay << ": must be in (0, 1]";
    throw std::invalid_argument(msg.str());
  }
}

BruteForcePlanner::BruteForcePlanner(const BfOptions& options) : options_(options) {
  validate(options_);
}

int BruteForcePlanner::step_uav(Swarm& swarm, int m, int iteration) const {
  static const std::array<Eigen::Vector3d, 7> kProbes = {
      Eigen::Vector3d(0, 0, 0),  Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0),
      Eigen::Vector3d(0, 1, 0),  Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 0, 1),
      Eigen::Vector3d(0, 0, -1)};
  const double b = options_.step * std::pow(options_.decay, iteration - 1);
  // The others do not move while UAV m probes: their Gram matrix is fixed.
  const UavObjective view(swarm.channel(), m);
  int best = 0;
  double best_f = view.objective_of_row(swarm.channel().H().row(m).transpose());
  for (int z = 1; z < static_cast<int>(kProbes.size()); ++z) {
    swarm.move(m, b * kProbes[z], MotionKind::kProbe);
    const double f = view.objective_of_row(swarm.channel().H().row(m).transpose());
    swarm.move(m, -b * kProbes[z], MotionKind::kProbe);
    if (f < best_f) {
      best_f = f;
      best = z;
    }
  }
  if (best != 0) swarm.move(m, b * kProbes[best], MotionKind::kPlacement);
  return best;
}

void BruteForcePlanner::iterate(Swarm& swarm, int iteration) {
  for (int m = 0; m < swarm.num_uavs(); ++m) step_uav(swarm, m, iteration);
}

}  // namespace losmimo::placement
