#include "losmimo/placement/gd.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/common/range.h"
#include "belief_sweep.h"

namespace losmimo::placement {

void validate(const GdOptions& o) {
  namespace r = gd_range;
  const auto require = [](const common::Range& range, double value, const char* field) {
    common::require_field_in(range, value, "gd", field);
  };
  require(r::step, o.step, "step");
  require(r::max_move_m, o.max_move_m, "max_move_m");
  require(r::decay, o.decay, "decay");
  require(r::stall_min_decrease, o.stall_min_decrease, "stall_min_decrease");
  require(r::depth_step_gain, o.depth_step_gain, "depth_step_gain");
  require(r::stall_window, o.stall_window, "stall_window");
  require(r::escape_half_grid, o.escape_half_grid, "escape_half_grid");
  require(r::escape_uavs, o.escape_uavs, "escape_uavs");
  require(r::max_halvings, o.max_halvings, "max_halvings");
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
  believed_m_.resize(3, 0);
}

std::optional<Eigen::Matrix3Xd> GradientDescentPlanner::believed_positions() const {
  if (believed_m_.cols() == 0) return std::nullopt;
  return believed_m_;
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
      believed_m_.col(m) = q_hat + search.offset_m;
      moved = true;
    }
  }
  escape_rank_ = moved ? 0 : escape_rank_ + options_.escape_uavs;
  return moved;
}

Eigen::Vector3d GradientDescentPlanner::plan_move(const Swarm& swarm, int m, const Eigen::Vector3d& q_hat_m,
                                                  int iteration) const {
  return plan_step(swarm, m, q_hat_m, detail::decayed_step(options_.step, options_.decay, iteration));
}

Eigen::Vector3d GradientDescentPlanner::plan_step(const Swarm& swarm, int m, const Eigen::Vector3d& q_hat_m,
                                                  double b) const {
  // f without the others' energy: only comparisons of UAV m's positions follow.
  const UavObjective view(swarm.channel(), m, UavObjective::Energy::kWithoutOthers);
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
  const double b = detail::decayed_step(options_.step, options_.decay, iteration);
  detail::estimate_then_move_each(
      swarm, believed_m_, [&](int m, const Eigen::Vector3d& q_hat_m) { return plan_step(swarm, m, q_hat_m, b); });
  const double f = swarm.channel().objective();
  if (options_.escape && stall_.update(f) && swarm.escape_allowed(f) && try_escape(swarm)) {
    stall_.reset();
  }
}

}  // namespace losmimo::placement
