#include "losmimo/placement/bf.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "losmimo/placement/common/range.h"
#include "belief_sweep.h"

namespace losmimo::placement {

namespace {
// Flies to r, measures f with the others fixed, flies back: one probe. The cached channel is
// brought up to date once per UAV turn (Swarm::sync_channel), not per flight. With channel
// conditions every probe is a measurement with its own noise draw, in flight order.
double probe(Swarm& swarm, const UavObjective& view, int m, const Eigen::Vector3d& r, ProbeActuation mode) {
  if (mode == ProbeActuation::kKeptMoveOnly) {
    swarm.count_exact_probe(m, r);
    return view.objective_at(swarm.true_positions_m().col(m) + r);
  }
  thread_local Eigen::VectorXcd row;  // reused: a probe allocates nothing
  swarm.move(m, r, MotionKind::kProbe, false);
  swarm.measure_row_into(m, row);  // the LoS row, or with channel conditions a measurement
  const double f = view.objective_of_row(row);
  swarm.move(m, -r, MotionKind::kProbe, false);
  return f;
}

// f at UAV m's current cached row (f[0]) and at the probes r_1 .. r_K (f[1..K]) flown in
// order. Without channel conditions the LoS row at a probe point depends on that point only:
// the flights come first (their actuation errors drawn in flight order), then every point and
// the "stay" row are evaluated in passes of kernels::kLanes (UavObjective::objectives_at).
void probe_all(Swarm& swarm, const UavObjective& view, int m, const Eigen::Matrix3Xd& r, ProbeActuation mode,
               double* f) {
  if (swarm.channel_conditions().active()) {
    f[0] = view.objective_of_row(swarm.channel().H().row(m).transpose());
    for (Eigen::Index k = 0; k < r.cols(); ++k) f[k + 1] = probe(swarm, view, m, r.col(k), mode);
    return;
  }
  thread_local Eigen::Matrix3Xd points;
  points.resize(3, r.cols());
  for (Eigen::Index k = 0; k < r.cols(); ++k) {
    if (mode == ProbeActuation::kKeptMoveOnly) {
      swarm.count_exact_probe(m, r.col(k));
      points.col(k) = swarm.true_positions_m().col(m) + r.col(k);
      continue;
    }
    swarm.move(m, r.col(k), MotionKind::kProbe, false);
    points.col(k) = swarm.true_positions_m().col(m);
    swarm.move(m, -r.col(k), MotionKind::kProbe, false);
  }
  view.objectives_at(points, true, f);
}
}  // namespace

std::string to_string(ProbeActuation mode) {
  return mode == ProbeActuation::kKeptMoveOnly ? "kept_move_only" : "every_leg";
}

ProbeActuation probe_actuation_from_string(const std::string& name) {
  if (name == "every_leg") return ProbeActuation::kEveryLeg;
  if (name == "kept_move_only") return ProbeActuation::kKeptMoveOnly;
  throw std::invalid_argument("unknown probe actuation '" + name + "' (known: every_leg, kept_move_only)");
}

void validate(const BfOptions& o) {
  namespace r = bf_range;
  const auto require = [](const common::Range& range, double value, const char* field) {
    common::require_field_in(range, value, "bf", field);
  };
  require(r::step, o.step, "step");
  require(r::decay, o.decay, "decay");
  require(r::contraction, o.contraction, "contraction");
  require(r::min_step_m, o.min_step_m, "min_step_m");
  require(r::stall_min_decrease, o.stall_min_decrease, "stall_min_decrease");
  require(r::stall_window, o.stall_window, "stall_window");
}

BruteForcePlanner::BruteForcePlanner(const Scenario& scenario, const BfOptions& options)
    : options_(options),
      wavelength_m_(scenario.wavelength_m()),
      bs_spacing_m_(scenario.bs_spacing_m),
      stall_(options.stall_window, options.stall_min_decrease) {
  validate(options_);
}

void BruteForcePlanner::start(Swarm& swarm) {
  step_scale_ = Eigen::VectorXd::Ones(swarm.num_uavs());
  stall_.reset();
  escape_rank_ = 0;
}

Eigen::Vector3d bf_probe_direction(int probe) {
  static const Eigen::Vector3d kDirections[kBfNumProbes] = {
      Eigen::Vector3d(0, 0, 0),  Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, 1, 0),
      Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1)};
  if (probe < 0 || probe >= kBfNumProbes) {
    throw std::out_of_range("bf_probe_direction: probe " + std::to_string(probe) + " is not in [0, " +
                            std::to_string(kBfNumProbes) + ")");
  }
  return kDirections[probe];
}

int BruteForcePlanner::step_uav(Swarm& swarm, int m, double b, ProbeActuation probe_actuation) {
  // The moves of probes 1 .. 6 as columns 0 .. 5.
  static const Eigen::Matrix<double, 3, kBfNumProbes - 1> kProbes = [] {
    Eigen::Matrix<double, 3, kBfNumProbes - 1> p;
    for (int z = 1; z < kBfNumProbes; ++z) p.col(z - 1) = bf_probe_direction(z);
    return p;
  }();
  // The others do not move while UAV m probes: their Gram matrix is fixed.
  const UavObjective view(swarm.channel(), m);
  double f[kBfNumProbes];
  probe_all(swarm, view, m, b * kProbes, probe_actuation, f);
  int best = 0;
  for (int z = 1; z < kBfNumProbes; ++z) {
    if (f[z] < f[best]) best = z;
  }
  if (best != 0) {
    swarm.move(m, b * kProbes.col(best - 1), MotionKind::kPlacement);
  } else {
    swarm.sync_channel(m);  // the probe flights' actuation errors moved it
  }
  return best;
}

bool BruteForcePlanner::try_escape(Swarm& swarm) {
  constexpr int kReach = 4;  // probes at 1..4 eighths of the lateral period
  constexpr int kSide = 2 * kReach + 1;
  const std::vector<int> order = uavs_by_redundancy(swarm.channel());
  const int m = order[escape_rank_ % static_cast<int>(order.size())];
  const UavObjective view(swarm.channel(), m);
  // Depth from the scenario geometry (|q| ~ R): BF never uses its own position.
  const double depth_m = swarm.channel().model().range_m();
  const double spacing = lateral_period_m(wavelength_m_, depth_m, bs_spacing_m_) / (2 * kReach);
  Eigen::Matrix3Xd r(3, kSide * kSide - 1);
  int count = 0;
  for (int i = -kReach; i <= kReach; ++i) {
    for (int k = -kReach; k <= kReach; ++k) {
      if (k != 0 || i != 0) r.col(count++) = Eigen::Vector3d(0.0, i * spacing, k * spacing);
    }
  }
  double f[kSide * kSide];
  probe_all(swarm, view, m, r, options_.probe_actuation, f);
  int best = 0;
  for (int c = 1; c <= count; ++c) {
    if (f[c] < f[best]) best = c;
  }
  if (best != 0 && f[best] < (1.0 - options_.stall_min_decrease) * f[0]) {
    swarm.move(m, r.col(best - 1), MotionKind::kPlacement);
    escape_rank_ = 0;
    return true;
  }
  swarm.sync_channel(m);
  ++escape_rank_;
  return false;
}

void BruteForcePlanner::iterate(Swarm& swarm, int iteration) {
  const double b = detail::decayed_step(options_.step, options_.decay, iteration);
  for (int m = 0; m < swarm.num_uavs(); ++m) {
    const double b_m = std::max(b * step_scale_(m), std::min(b, options_.min_step_m));
    const bool moved = step_uav(swarm, m, b_m, options_.probe_actuation) != 0;
    step_scale_(m) =
        moved ? std::min(1.0, step_scale_(m) / options_.contraction) : step_scale_(m) * options_.contraction;
  }
  const double f = swarm.channel().objective();
  if (options_.escape && stall_.update(f) && swarm.escape_allowed(f) && try_escape(swarm)) {
    stall_.reset();
  }
}

}  // namespace losmimo::placement
