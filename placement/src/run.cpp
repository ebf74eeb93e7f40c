#include "losmimo/placement/run.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/common/range.h"
#include "losmimo/placement/metrics.h"
#include "finite.h"

namespace losmimo::placement {

void validate(const RunOptions& o) {
  common::require_field_in(run_range::target_icn, o.target_icn, "placement", "target_icn");
  common::require_field_in(run_range::noise_variance, o.noise_variance, "placement", "noise_variance");
  common::require_field_in(run_range::max_iterations, o.max_iterations, "placement", "max_iterations");
}

std::string to_string(RunStatus status) {
  switch (status) {
    case RunStatus::kConverged:
      return "converged";
    case RunStatus::kIterationCap:
      return "iteration_cap";
    case RunStatus::kUavUnresponsive:
      return "uav_unresponsive";
    case RunStatus::kNumericalFault:
      return "numerical_fault";
  }
  return "unknown";
}

std::string to_string(StopOn stop_on) { return stop_on == StopOn::kBelief ? "belief" : "csi"; }

StopOn stop_on_from_string(const std::string& name) {
  if (name == "csi") return StopOn::kCsi;
  if (name == "belief") return StopOn::kBelief;
  throw std::invalid_argument("unknown stop test '" + name + "' (known: csi, belief)");
}

std::string to_string(DistanceKind kind) { return kind == DistanceKind::kCommanded ? "commanded" : "true_path"; }

DistanceKind distance_kind_from_string(const std::string& name) {
  if (name == "true_path") return DistanceKind::kTruePath;
  if (name == "commanded") return DistanceKind::kCommanded;
  throw std::invalid_argument("unknown distance '" + name + "' (known: true_path, commanded)");
}

std::optional<PlannerFault> check_finite(const Swarm& swarm) {
  const Eigen::Matrix3Xd& q = swarm.true_positions_m();
  const Eigen::MatrixXcd& H = swarm.channel().H();
  if (detail::all_finite(q) && detail::all_finite(H) && swarm.channel().gram_is_finite()) {
    return std::nullopt;  // the usual case
  }
  const Eigen::MatrixXcd& G = swarm.channel().gram();
  std::ostringstream reason;
  for (Eigen::Index m = 0; m < q.cols(); ++m) {
    if (!q.col(m).allFinite()) {
      reason << "UAV " << m << ": position is non-finite (q = (" << q(0, m) << ", " << q(1, m) << ", " << q(2, m)
             << "))";
      return PlannerFault{RunStatus::kNumericalFault, static_cast<int>(m), reason.str()};
    }
  }
  for (Eigen::Index m = 0; m < H.rows(); ++m) {
    for (Eigen::Index k = 0; k < H.cols(); ++k) {
      if (!std::isfinite(H(m, k).real()) || !std::isfinite(H(m, k).imag())) {
        reason << "UAV " << m << ": channel row is non-finite (H(" << m << ", " << k << ") = " << H(m, k) << ")";
        return PlannerFault{RunStatus::kNumericalFault, static_cast<int>(m), reason.str()};
      }
    }
  }
  for (Eigen::Index l = 0; l < G.rows(); ++l) {
    for (Eigen::Index k = 0; k < G.cols(); ++k) {
      if (!std::isfinite(G(l, k).real()) || !std::isfinite(G(l, k).imag())) {
        reason << "Gram matrix is non-finite (G(" << l << ", " << k << ") = " << G(l, k)
               << ") with every channel row finite";
        return PlannerFault{RunStatus::kNumericalFault, -1, reason.str()};
      }
    }
  }
  return std::nullopt;  // not reached: one of the loops found it
}

double icn_from_gram(const Eigen::MatrixXcd& G, int num_rows) {
  if (num_rows < G.cols() || G.size() == 0) return 0.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> eig(G, Eigen::EigenvaluesOnly);
  const Eigen::VectorXd& ev = eig.eigenvalues();  // ascending
  const double hi = ev(ev.size() - 1);
  const double lo = std::max(ev(0), 0.0);
  return hi > 0.0 ? std::sqrt(lo / hi) : 0.0;
}

namespace {

const Eigen::VectorXd& placement_distances(const Swarm& swarm, const RunOptions& options) {
  return options.distance == DistanceKind::kCommanded ? swarm.commanded_placement_distance_m()
                                                      : swarm.placement_distance_m();
}
const Eigen::VectorXd& probe_distances(const Swarm& swarm, const RunOptions& options) {
  return options.distance == DistanceKind::kCommanded ? swarm.commanded_probe_distance_m() : swarm.probe_distance_m();
}

IterationRecord record(const Swarm& swarm, int iteration, const RunOptions& options, double proven_below,
                       IcnWarmStart& icn_warm_start) {
  IterationRecord r;
  r.iteration = iteration;
  const SwarmChannel& ch = swarm.channel();
  // With channel conditions every iteration is evaluated in full: the shortcut's thresholds are
  // the milestones', which then come from another matrix.
  const bool conditions = swarm.channel_conditions().active();
  r.icn = !conditions && proven_below > 0.0 && icn_below(ch, proven_below, &icn_warm_start)
              ? std::numeric_limits<double>::quiet_NaN()
              : icn_from_gram(ch.gram(), ch.num_uavs());
  r.icn_los = conditions ? inverse_condition_number(ch.model().matrix(swarm.true_positions_m())) : r.icn;
  r.objective = ch.objective();
  r.placement_dist_m = placement_distances(swarm, options).mean();
  r.probe_dist_m = probe_distances(swarm, options).mean();
  if (options.trace_sinr) {
    const StreamSinr sinr = stream_sinr(conditions ? swarm.true_channel() : ch.H(), options.noise_variance);
    r.sinr_nv_db = to_db(sinr.nv(0));
    r.sinr_zf_db = to_db(sinr.zf(0));
    r.sinr_mf_db = to_db(sinr.mf(0));
  }
  return r;
}

// Milestones are read on the true LoS channel (icn_los), whatever the planners measure.
void update_milestone(Milestone& m, const IterationRecord& r, double threshold, bool with_probes) {
  if (!m.reached && r.icn_los >= threshold) {
    m.reached = true;
    m.iteration = r.iteration;
    m.placement_dist_m = with_probes ? r.placement_dist_m + r.probe_dist_m : r.placement_dist_m;
  }
}

// The ICN the planner's belief would give, or nullopt without a belief.
std::optional<double> believed_icn(const Planner& planner, const Swarm& swarm) {
  const std::optional<Eigen::Matrix3Xd> believed = planner.believed_positions();
  if (!believed) return std::nullopt;
  const Eigen::MatrixXcd H = swarm.channel().model().matrix(*believed);
  return icn_from_gram(H.adjoint() * H, static_cast<int>(H.rows()));
}

}  // namespace

RunResult run_placement(Planner& planner, Swarm& swarm, const RunOptions& options) {
  validate(options);
  RunResult result;
  result.planner = planner.name();
  result.start_m = swarm.true_positions_m();
  planner.start(swarm);

  IcnWarmStart icn_warm_start;  // icn_below's eigenvector estimates, kept across iterations
  const auto observe = [&](int iteration) {
    // The smallest ICN that would change anything: skip the eigen-solve below it if allowed.
    double pending = options.target_icn;
    if (!result.icn050.reached) pending = std::min(pending, 0.5);
    if (!result.icn095.reached) pending = std::min(pending, 0.95);
    result.trace.push_back(record(swarm, iteration, options, options.full_icn_trace ? 0.0 : pending, icn_warm_start));
    const IterationRecord& r = result.trace.back();
    update_milestone(result.icn050, r, 0.5, options.milestone_distance_includes_probes);
    update_milestone(result.icn095, r, 0.95, options.milestone_distance_includes_probes);
    if (options.record_path) result.path.push_back(swarm.true_positions_m());
    if (options.stop_on == StopOn::kBelief) {
      if (const std::optional<double> icn = believed_icn(planner, swarm)) return *icn >= options.target_icn;
    }
    return r.icn >= options.target_icn;
  };

  // The first fault of the planner or the swarm, with the iteration it was found in.
  const auto health = [&](int iteration) -> std::optional<PlannerFault> {
    std::optional<PlannerFault> fault = planner.fault();
    if (!fault && swarm.numerical_fault()) {
      fault = PlannerFault{RunStatus::kNumericalFault, swarm.numerical_fault()->uav, swarm.numerical_fault()->reason};
    }
    if (!fault) fault = check_finite(swarm);
    if (fault) fault->reason += " at iteration " + std::to_string(iteration);
    return fault;
  };

  int iteration = 0;
  std::optional<PlannerFault> fault = health(0);
  bool done = false;
  if (!fault || fault->status != RunStatus::kNumericalFault) done = observe(0);
  while (!fault && !done && iteration < options.max_iterations) {
    ++iteration;
    swarm.begin_iteration(iteration);
    planner.iterate(swarm, iteration);
    fault = health(iteration);
    // A non-finite swarm is not evaluated (the eigen-solve of a NaN Gram matrix means nothing).
    if (!fault || fault->status != RunStatus::kNumericalFault) done = observe(iteration);
  }
  if (fault) {
    result.status = fault->status;
    result.fault = fault->reason;
    result.fault_uav = fault->uav;
  } else {
    result.status = done ? RunStatus::kConverged : RunStatus::kIterationCap;
  }
  result.iterations = iteration;
  result.final_m = swarm.true_positions_m();
  result.placement_dist_m = placement_distances(swarm, options);
  result.probe_dist_m = probe_distances(swarm, options);
  return result;
}

}  // namespace losmimo::placement
