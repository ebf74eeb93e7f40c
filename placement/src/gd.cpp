#include "losmimo/placement/gd.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace losmimo::placement {

namespace {
void require_positive(const char* field, double value) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << field << " = " << value << ": must be a finite positive number";
    throw std::invalid_argument(msg.str());
  }
}
}  // namespace

void validate(const GdOptions& o) {
  require_positive("gd.step", o.step);
  require_positive("gd.max_move_m", o.max_move_m);
  if (!(o.decay > 0.0 && o.decay <= 1.0)) {
    std::ostringstream msg;
    msg << "gd.decay = " << o.decay << ": must be in (0, 1]";
    throw std::invalid_argument(msg.str());
  }
  if (o.max_halvings < 0 || o.max_halvings > 60)
    throw std::invalid_argument("gd.max_halvings = " + std::to_string(o.max_halvings) +
                                ": must be in [0, 60]");
}

GradientDescentPlanner::GradientDescentPlanner(const GdOptions& options) : options_(options) {
  validate(options_);
}

Eigen::Vector3d GradientDescentPlanner::plan_move(const Swarm& swarm, int m,
                                                  const Eigen::Vector3d& q_hat_m,
                                                  int iteration) const {
  const UavObjective view(swarm.channel(), m);
  const double f_scale = swarm.num_uavs();
  const double b = options_.step * std::pow(options_.decay, iteration - 1);
  Eigen::Vector3d r = -b * view.gradient_at(q_hat_m) / f_scale;
  if (!r.allFinite()) return Eigen::Vector3d::Zero();
  const double norm = r.norm();
  if (norm > options_.max_move_m) r *= options_.max_move_m / norm;
  if (options_.backtracking) {
    const double f0 = view.objective_at(q_hat_m);
    for (int h = 0; h < options_.max_halvings && view.objective_at(q_hat_m + r) > f0; ++h) r *= 0.5;
  }
  return r;
}

void GradientDescentPlanner::iterate(Swarm& swarm, int iteration) {
  // estimatePositionAll(), then calcGradientAndMoveDrone(d) for each drone in turn.
  const int nr = swarm.num_uavs();
  Eigen::Matrix3Xd q_hat(3, nr);
  for (int m = 0; m < nr; ++m) q_hat.col(m) = swarm.estimate_position(m);
  for (int m = 0; m < nr; ++m) swarm.move(m, plan_move(swarm, m, q_hat.col(m), iteration), MotionKind::kPlacement);
}

}  // namespace losmimo::placement
