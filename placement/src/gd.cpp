#include "losmimo/placement/gd.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/common/field_error.h"

namespace losmimo::placement {

namespace {
void require_positive(const char* field, double value) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "gd." << field << " = " << value << ": must be a finite positive number";
    throw common::FieldError(field, msg.str());
  }
}
}  // namespace

void validate(const GdOptions& o) {
  require_positive("step", o.step);
  require_positive("max_move_m", o.max_move_m);
  if (!(o.decay > 0.0 && o.decay <= 1.0)) {
    std::ostringstream msg;
    msg << "gd.decay = " << o.decay << ": must be in (0, 1]";
    throw common::FieldError("decay", msg.str());
  }
  require_positive("stall_min_decrease", o.stall_min_decrease);
  require_positive("depth_step_gain", o.depth_step_gain);
  if (o.stall_window < 1 || o.stall_window > 100000)
    throw common::FieldError("stall_window", "gd.stall_window = " + std::to_string(o.stall_window) +
                                ": must be in [1, 100000]");
  if (o.escape_half_grid < 1 || o.escape_half_grid > 256)
    throw common::FieldError("escape_half_grid", "gd.escape_half_grid = " + std::to_string(o.escape_half_grid) +
                                ": must be in [1, 256]");
  if (o.escape_uavs < 1 || o.escape_uavs > 100000)
    throw common::FieldError("escape_uavs", "gd.escape_uavs = " + std::to_string(o.escape_uavs) +
                                ": must be in [1, 100000]");
  if (o.max_halvings < 0 || o.max_halvings > 60)
    throw common::FieldError("max_halvings", "gd.max_halvings = " + std::to_string(o.max_halvings) +
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
  // The escape_uavs most redundant UAVs from escape_rank_ on search in turn, each seeing the
  // moves of those before it. With escape_uavs = 1 this is the one-UAV escape of the paper setup.
  const std::vector<int> order = uavs_by_redundancy(swarm.channel());
  bool moved = false;
  for (int k = 0; k < options_.escape_uavs; ++k) {
    const int m = order[(escape_rank_ + k) % static_cast<int>(order.size())];
    const Eigen::Vector3d q_hat = swarm.estimate_position(m);
    const LateralSearch search =
        search_lateral_period(UavObjective(swarm.channel(), m), q_hat,
                              lateral_period_m(wavelength_m_, q_hat.x(), bs_spacing_m_), options_.escape_half_grid);
    if (search.best_objective < (1.0 - options_.stall_min_decrease) * search.objective_at_start) {
      swarm.move(m, search.offset_m, MotionKind::kPlacement);
      moved = true;
    }
  }
  escape_rank_ = moved ? 0 : escape_rank_ + options_.escape_uavs;
  return moved;
}

Eigen::Vector3d GradientDescentPlanner::plan_move(const Swarm& swarm, int m,
                                                  const Eigen::Vector3d& q_hat_m,
                                                  int iteration) const {
  const UavObjective view(swarm.channel(), m);
  const double b = options_.step * std::pow(options_.decay, iteration - 1);
  double f0 = 0.0;  // f at q_hat_m, from the gradient's channel row (one row, Nt sincos, less)
  Eigen::Vector3d r = -b * view.gradient_at(q_hat_m, options_.backtracking ? &f0 : nullptr) / swarm.num_uavs();
  if (!r.allFinite()) return Eigen::Vector3d::Zero();
  if (options_.depth_step_gain != 1.0) r.x() *= options_.depth_step_gain;
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
  const double f = swarm.channel().objective();
  if (options_.escape && stall_.update(f) && swarm.escape_allowed(f) && try_escape(swarm)) {
    stall_.reset();
  }
}

}  // namespace losmimo::placement
