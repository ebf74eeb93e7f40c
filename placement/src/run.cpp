#include "losmimo/placement/run.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/metrics.h"

namespace losmimo::placement {

void validate(const RunOptions& o) {
  if (!(o.target_icn > 0.0 && o.target_icn <= 1.0)) {
    std::ostringstream msg;
    msg << "placement.target_icn = " << o.target_icn << ": must be in (0, 1]";
    throw std::invalid_argument(msg.str());
  }
  if (!(o.noise_variance > 0.0) || !std::isfinite(o.noise_variance)) {
    std::ostringstream msg;
    msg << "noise variance = " << o.noise_variance << ": must be a finite positive number";
    throw std::invalid_argument(msg.str());
  }
  if (o.max_iterations < 0 || o.max_iterations > 10'000'000) {
    throw std::invalid_argument("placement.max_iterations = " + std::to_string(o.max_iterations) +
                                ": must be in [0, 10000000]");
  }
}

std::string to_string(RunStatus status) {
  return status == RunStatus::kConverged ? "converged" : "iteration_cap";
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

IterationRecord record(const Swarm& swarm, int iteration, const RunOptions& options) {
  IterationRecord r;
  r.iteration = iteration;
  const SwarmChannel& ch = swarm.channel();
  r.icn = icn_from_gram(ch.gram(), ch.num_uavs());
  r.objective = ch.objective();
  r.placement_dist_m = swarm.placement_distance_m().mean();
  r.probe_dist_m = swarm.probe_distance_m().mean();
  if (options.trace_sinr) {
    const StreamSinr sinr = stream_sinr(ch.H(), options.noise_variance);
    r.sinr_nv_db = to_db(sinr.nv(0));
    r.sinr_zf_db = to_db(sinr.zf(0));
    r.sinr_mf_db = to_db(sinr.mf(0));
  }
  return r;
}

void update_milestone(Milestone& m, const IterationRecord& r, double threshold) {
  if (!m.reached && r.icn >= threshold) {
    m.reached = true;
    m.iteration = r.iteration;
    m.placement_dist_m = r.placement_dist_m;
  }
}

}  // namespace

RunResult run_placement(Planner& planner, Swarm& swarm, const RunOptions& options) {
  validate(options);
  RunResult result;
  result.planner = planner.name();
  result.start_m = swarm.true_positions_m();
  planner.start(swarm);

  const auto observe = [&](int iteration) {
    result.trace.push_back(record(swarm, iteration, options));
    const IterationRecord& r = result.trace.back();
    update_milestone(result.icn050, r, 0.5);
    update_milestone(result.icn095, r, 0.95);
    return r.icn >= options.target_icn;
  };

  bool done = observe(0);
  int iteration = 0;
  while (!done && iteration < options.max_iterations) {
    ++iteration;
    planner.iterate(swarm, iteration);
    done = observe(iteration);
  }
  result.status = done ? RunStatus::kConverged : RunStatus::kIterationCap;
  result.iterations = iteration;
  result.final_m = swarm.true_positions_m();
  result.placement_dist_m = swarm.placement_distance_m();
  result.probe_dist_m = swarm.probe_distance_m();
  return result;
}

}  // namespace losmimo::placement
