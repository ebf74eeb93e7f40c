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
  require_positive("gd.stall_min_decrease", o.stall_min_decrease);
  if (o.stall_window < 1 || o.stall_window > 100000)
    throw std::invalid_argument("gd.stall_window = " + std::to_string(o.stall_window) +
                                ": must be in [1, 100000]");
  if (o.max_halvings < 0 || o.max_halvings > 60)
    throw std::invalid_argument("gd.max_halvings = " + std::to_string(o.max_halvings) +
                                ": must be in [0, 60]");
}

GradientDescentPlanner::GradientDescentPlanner(const Scenario& scenario, const GdOptions& options)
    : options_(options),
      wavelength_m_(scenario.wavelength_m()),
      bs_spacing_m_(scenario.bs_spacing_m),
      stall_(options.stall_window, options.stall_min_decrease) {
  validate(options_);
}

void GradientDescentPlanner::start(Swarm& /*swarm*/) {
  stall_.reset();
  escape_rank_ = 0;
}

bool GradientDescentPlanner::try_escape(Swarm& swarm) {
  const std::vector<int> order = uavs_by_redundancy(swarm.channel());
  const int m = order[escape_rank_ % static_cast<int>(order.size())];
  const Eigen::Vector3d q_hat = swarm.estimate_position(m);
  const LateralSearch search = search_lateral_period(
      UavObjective(swarm.channel(), m), q_hat, lateral_period_m(wavelength_m_, q_hat.x(), bs_spacing_m_));
  if (search.best_objective < (1.0 - options_.stall_min_decrease) * search.objective_at_start) {
    swarm.move(m, search.offset_m, MotionKind::kPlacement);
    escape_rank_ = 0;
    return true;
  }
  ++escape_rank_;
  return false;
}

Eigen::Vector3d GradientDescentPlanner::plan_move(const Swarm& swarm, int m,
                                                  const Eigen::Vector3d& q_hat_m,
                                                  int iteration) const {
  const UavObjective view(swarm.channel(), m);
  const double b = options_.step * std::pow(options_.decay, iteration - 1);
  double f0 = 0.0;  // f at q_hat_m, from the gradient's channel row (one row, Nt sincos, less)
  Eigen::Vector3d r = -b * view.gradient_at(q_hat_m, options_.backtracking ? &f0 : nullptr) / swarm.num_uavs();
  if (!r.allFinite()) return Eigen::Vector3d::Zero();
  const double norm = r.norm();
  if (norm > options_.max_move_m) r *= options_.max_move_m / norm;
  if (options_.backtracking) {
    for (int h = 0; h < options_.max_halvings && view.objective_at(q_hat_m + r) > f0; ++h) r *= 0.5;
  }
  return r;
}

void GradientDescentPlanner::iterate(Swarm& swarm, int iteration) {
  // estimatePositionAll(), then calcGradientAndMoveDrone(d) for each drone in turn.
  const int nr = swarm.num_uavs();
  Eigen::Matrix3Xd q_hat(3, nr);
  for (int m = 0; m < nr; ++m) q_hat.col(m) = swarm.estimate_position(m);
  for (int m = 0; m < nr; ++m) {
    swarm.move(m, plan_move(swarm, m, q_hat.col(m), iteration), MotionKind::kPlacement);
  }
  if (options_.escape && stall_.update(swarm.channel().objective()) && try_escape(swarm)) {
    stall_.reset();
  }
}

}  // namespace losmimo::placement
