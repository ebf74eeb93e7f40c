#include "losmimo/fusion/centralized.h"

#include <ceres/ceres.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/assignment.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/run.h"
#include "losmimo/placement/swarm.h"
#include "losmimo/placement/ura.h"

namespace losmimo::fusion {

namespace {

template <typename V>
[[noreturn]] void bad_field(const char* field, const V& value, const char* requirement) {
  std::ostringstream msg;
  msg << "centralized." << field << " = " << value << ": " << requirement;
  throw std::invalid_argument(msg.str());
}

// J_mu over the stacked positions (x_1, y_1, z_1, x_2, ...), for L-BFGS.
class PenalizedTravel final : public ceres::FirstOrderFunction {
 public:
  PenalizedTravel(const placement::ChannelModel& model, const Eigen::Matrix3Xd& start_m, double mu)
      : model_(model), start_m_(start_m), mu_(mu) {}

  bool Evaluate(const double* parameters, double* cost, double* gradient) const override {
    const Eigen::Map<const Eigen::Matrix3Xd> q(parameters, 3, start_m_.cols());
    if (gradient == nullptr) {
      *cost = penalized_travel_cost(model_, start_m_, mu_, q, nullptr);
    } else {
      Eigen::Matrix3Xd g;
      *cost = penalized_travel_cost(model_, start_m_, mu_, q, &g);
      Eigen::Map<Eigen::Matrix3Xd>(gradient, 3, start_m_.cols()) = g;
    }
    return std::isfinite(*cost);
  }
  int NumParameters() const override { return static_cast<int>(3 * start_m_.cols()); }

 private:
  const placement::ChannelModel& model_;
  const Eigen::Matrix3Xd start_m_;
  const double mu_;
};

// B_t over the stacked positions; an infeasible point is reported as a failed evaluation, which
// makes Ceres' line search contract the step (the iterates stay strictly feasible).
class BarrierTravel final : public ceres::FirstOrderFunction {
 public:
  BarrierTravel(const placement::ChannelModel& model, const Eigen::Matrix3Xd& start_m, double alpha, double t)
      : model_(model), start_m_(start_m), alpha_(alpha), t_(t) {}

  bool Evaluate(const double* parameters, double* cost, double* gradient) const override {
    const Eigen::Map<const Eigen::Matrix3Xd> q(parameters, 3, start_m_.cols());
    Eigen::Matrix3Xd g;
    *cost = barrier_travel_cost(model_, start_m_, alpha_, t_, q, gradient ? &g : nullptr);
    if (!std::isfinite(*cost)) return false;
    if (gradient != nullptr) Eigen::Map<Eigen::Matrix3Xd>(gradient, 3, start_m_.cols()) = g;
    return true;
  }
  int NumParameters() const override { return static_cast<int>(3 * start_m_.cols()); }

 private:
  const placement::ChannelModel& model_;
  const Eigen::Matrix3Xd start_m_;
  const double alpha_;
  const double t_;
};

ceres::GradientProblemSolver::Options lbfgs_options(int max_iterations) {
  ceres::GradientProblemSolver::Options options;
  options.line_search_direction_type = ceres::LBFGS;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-10;
  options.gradient_tolerance = 1e-10;
  options.parameter_tolerance = 1e-10;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  return options;
}

struct Solver {
  const placement::ChannelModel& model;
  const Eigen::Matrix3Xd& start_m;
  const CentralizedConfig& config;
  int num_solves = 0;

  Eigen::Matrix3Xd minimise(const Eigen::Matrix3Xd& initial_m, double mu) {
    Eigen::Matrix3Xd q = initial_m;
    ceres::GradientProblem problem(new PenalizedTravel(model, start_m, mu));
    ceres::GradientProblemSolver::Summary summary;
    ceres::Solve(lbfgs_options(config.max_lbfgs_iterations), problem, q.data(), &summary);
    ++num_solves;
    return q;
  }

  Eigen::Matrix3Xd minimise_barrier(const Eigen::Matrix3Xd& initial_m, double t) {
    Eigen::Matrix3Xd q = initial_m;
    ceres::GradientProblem problem(new BarrierTravel(model, start_m, config.target_icn, t));
    ceres::GradientProblemSolver::Summary summary;
    ceres::Solve(lbfgs_options(config.max_lbfgs_iterations), problem, q.data(), &summary);
    ++num_solves;
    return q;
  }

  double icn(const Eigen::Matrix3Xd& q_m) const { return placement::inverse_condition_number(model.matrix(q_m)); }
  bool feasible(const Eigen::Matrix3Xd& q_m) const { return icn(q_m) >= config.target_icn; }
  double travel2(const Eigen::Matrix3Xd& q_m) const { return (q_m - start_m).squaredNorm(); }
};

struct Candidate {
  bool feasible = false;
  Eigen::Matrix3Xd q_m;
  double mu = 0.0;
  bool polished = false;
};

// Barrier stage (header): keeps only iterates that the SVD confirms feasible and that travel less.
void polish(Solver& solver, Candidate& candidate) {
  const CentralizedConfig& c = solver.config;
  if (!candidate.feasible) return;
  const double alpha = c.target_icn;
  if (!std::isfinite(
          barrier_travel_cost(solver.model, solver.start_m, alpha, c.barrier_t_initial, candidate.q_m, nullptr))) {
    return;  // on the boundary itself (ICN == alpha to rounding): nothing to polish from
  }
  Eigen::Matrix3Xd q = candidate.q_m;
  for (double t = c.barrier_t_initial; t >= c.barrier_t_final * (1.0 - 1e-9); t *= c.barrier_t_factor) {
    const Eigen::Matrix3Xd q_next = solver.minimise_barrier(q, t);
    if (solver.feasible(q_next)) q = q_next;
  }
  if (solver.travel2(q) < solver.travel2(candidate.q_m)) {
    candidate.q_m = q;
    candidate.polished = true;
  }
}

// Continuation from initial_m: grow mu from mu_start until feasible, then lower it by
// log-bisection, keeping the feasible solution of least squared travel.
Candidate continuation(Solver& solver, const Eigen::Matrix3Xd& initial_m, double mu_start) {
  const CentralizedConfig& c = solver.config;
  Candidate best;
  Eigen::Matrix3Xd q = initial_m;
  double mu = mu_start;
  double mu_infeasible = 0.0;  // largest mu known to give an infeasible solution
  while (true) {
    q = solver.minimise(q, mu);
    if (solver.feasible(q)) {
      best = {true, q, mu};
      break;
    }
    mu_infeasible = mu;
    mu *= c.mu_growth;
    if (mu > c.mu_max * (1.0 + 1e-12)) return best;
  }
  double hi = best.mu;
  double lo = mu_infeasible;
  for (int step = 0; step < c.reduce_steps; ++step) {
    // Without a known infeasible weight, step down by mu_growth^2; else bisect in log scale.
    const double mu_try = lo > 0.0 ? std::sqrt(lo * hi) : hi / (c.mu_growth * c.mu_growth);
    const Eigen::Matrix3Xd q_try = solver.minimise(best.q_m, mu_try);
    if (solver.feasible(q_try) && solver.travel2(q_try) < solver.travel2(best.q_m)) {
      best = {true, q_try, mu_try};
      hi = mu_try;
    } else {
      lo = mu_try;
    }
  }
  return best;
}

// A candidate with the start it came from; raw: a URA placement itself, not optimised.
struct Entry {
  Candidate candidate;
  CentralizedStart start;
  bool raw;
};

// Noise-free GD until alpha from the start positions; its end point is a candidate as it
// stands (J_mu is not involved).
Candidate gd_candidate(const placement::Scenario& scenario, const Solver& solver) {
  placement::Swarm swarm(solver.model, solver.start_m, placement::ErrorModel{}, /*seed=*/0);
  placement::GradientDescentPlanner gd(scenario, placement::GdOptions{});
  placement::RunOptions run;
  run.target_icn = solver.config.target_icn;
  run.max_iterations = solver.config.gd_max_iterations;
  const placement::RunResult gd_run = placement::run_placement(gd, swarm, run);
  return {solver.feasible(gd_run.final_m), gd_run.final_m, 0.0};
}

// The URA baselines (num_uavs == Nt) into result: the lattice URA with perfect knowledge (the
// planner's own targets from the true positions), and the rigid URA with its slots assigned
// by the eq. 4 cost (squared distance), each with its ICN and travel.
void ura_baselines(const placement::Scenario& scenario, const Solver& solver, CentralizedResult& result) {
  const Eigen::Matrix3Xd& start_m = solver.start_m;
  placement::Swarm swarm(solver.model, start_m, placement::ErrorModel{}, /*seed=*/0);
  placement::UraPlanner lattice(scenario, placement::UraVariant::kLattice);
  lattice.start(swarm);
  result.lattice_ura_m = lattice.targets_m();
  result.lattice_ura_icn = solver.icn(result.lattice_ura_m);
  result.lattice_ura_travel = travel_stats(start_m, result.lattice_ura_m);

  const Eigen::Matrix3Xd slots = placement::optimal_ura_positions_m(scenario);
  const int n = scenario.num_uavs;
  Eigen::MatrixXd cost(n, n);
  for (int m = 0; m < n; ++m) {
    for (int s = 0; s < n; ++s) cost(m, s) = (slots.col(s) - start_m.col(m)).squaredNorm();
  }
  const std::vector<int> slot_of = placement::min_cost_assignment(cost);
  result.rigid_ura_m.resize(3, n);
  for (int m = 0; m < n; ++m) result.rigid_ura_m.col(m) = slots.col(slot_of[m]);
  result.rigid_ura_icn = solver.icn(result.rigid_ura_m);
  result.rigid_ura_travel = travel_stats(start_m, result.rigid_ura_m);
}

// The candidates from result's URA baselines: the continuations from each (mu_max down) and
// the raw lattice URA as configured; the raw rigid URA always (the feasible fallback).
void add_ura_entries(Solver& solver, const CentralizedResult& result, std::vector<Entry>& entries) {
  const CentralizedConfig& config = solver.config;
  if (config.start_from_lattice_ura) {
    entries.push_back(
        {continuation(solver, result.lattice_ura_m, config.mu_max), CentralizedStart::kLatticeUra, false});
    entries.push_back({{result.lattice_ura_icn >= config.target_icn, result.lattice_ura_m, 0.0},
                       CentralizedStart::kLatticeUra,
                       true});
  }
  if (config.start_from_rigid_ura) {
    entries.push_back({continuation(solver, result.rigid_ura_m, config.mu_max), CentralizedStart::kRigidUra, false});
  }
  entries.push_back(
      {{result.rigid_ura_icn >= config.target_icn, result.rigid_ura_m, 0.0}, CentralizedStart::kRigidUra, true});
}

// The feasible entry of least squared travel (the first of equals) into result; result is
// untouched when none is feasible.
void keep_least_travel(const Solver& solver, const std::vector<Entry>& entries, CentralizedResult& result) {
  double best_travel2 = std::numeric_limits<double>::infinity();
  for (const Entry& e : entries) {
    if (!e.candidate.feasible) continue;
    const double t2 = solver.travel2(e.candidate.q_m);
    if (t2 < best_travel2) {
      best_travel2 = t2;
      result.status = CentralizedStatus::kFeasible;
      result.best_start = e.start;
      result.best_is_raw_ura = e.raw && !e.candidate.polished;
      result.polished = e.candidate.polished;
      result.positions_m = e.candidate.q_m;
      result.mu = e.candidate.mu;
    }
  }
}

}  // namespace

void validate(const CentralizedConfig& c) {
  if (!(c.target_icn > 0.0) || !(c.target_icn < 1.0)) bad_field("target_icn", c.target_icn, "must be in (0, 1)");
  if (!(c.mu_initial > 0.0) || !std::isfinite(c.mu_initial))
    bad_field("mu_initial", c.mu_initial, "must be a finite positive number");
  if (!(c.mu_growth > 1.0) || !std::isfinite(c.mu_growth))
    bad_field("mu_growth", c.mu_growth, "must be a finite number > 1");
  if (!(c.mu_max >= c.mu_initial) || !std::isfinite(c.mu_max))
    bad_field("mu_max", c.mu_max, "must be finite and >= mu_initial");
  if (c.reduce_steps < 0 || c.reduce_steps > 100) bad_field("reduce_steps", c.reduce_steps, "must be in [0, 100]");
  if (c.max_lbfgs_iterations < 1 || c.max_lbfgs_iterations > 100000)
    bad_field("max_lbfgs_iterations", c.max_lbfgs_iterations, "must be in [1, 100000]");
  if (!(c.barrier_t_initial > 0.0) || !std::isfinite(c.barrier_t_initial))
    bad_field("barrier_t_initial", c.barrier_t_initial, "must be a finite positive number");
  if (!(c.barrier_t_final > 0.0) || !(c.barrier_t_final <= c.barrier_t_initial))
    bad_field("barrier_t_final", c.barrier_t_final, "must be in (0, barrier_t_initial]");
  if (!(c.barrier_t_factor > 0.0) || !(c.barrier_t_factor < 1.0))
    bad_field("barrier_t_factor", c.barrier_t_factor, "must be in (0, 1)");
}

TravelStats travel_stats(const Eigen::Matrix3Xd& from_m, const Eigen::Matrix3Xd& to_m) {
  if (from_m.cols() != to_m.cols() || from_m.cols() == 0) {
    throw std::invalid_argument("travel_stats: placements of different or zero size");
  }
  const Eigen::VectorXd dist = (to_m - from_m).colwise().norm().transpose();
  const double n = static_cast<double>(dist.size());
  TravelStats t;
  t.total_m = dist.sum();
  t.mean_m = t.total_m / n;
  t.max_m = dist.maxCoeff();
  t.total_squared_m2 = dist.squaredNorm();
  t.mean_squared_m2 = t.total_squared_m2 / n;
  return t;
}

std::string to_string(CentralizedStatus status) {
  return status == CentralizedStatus::kFeasible ? "feasible" : "infeasible";
}

std::string to_string(CentralizedStart start) {
  switch (start) {
    case CentralizedStart::kStartPositions:
      return "start_positions";
    case CentralizedStart::kLatticeUra:
      return "lattice_ura";
    case CentralizedStart::kRigidUra:
      return "rigid_ura";
    case CentralizedStart::kGd:
      return "gd";
    case CentralizedStart::kNone:
      break;
  }
  return "none";
}

CentralizedResult solve_centralized(const placement::Scenario& scenario, const Eigen::Matrix3Xd& start_m,
                                    const CentralizedConfig& config) {
  placement::validate(scenario);
  validate(config);
  if (start_m.cols() != scenario.num_uavs || !start_m.allFinite()) {
    throw std::invalid_argument("solve_centralized: start_m must be finite and 3 x num_uavs = " +
                                std::to_string(scenario.num_uavs));
  }
  const placement::ChannelModel model(scenario);
  Solver solver{model, start_m, config};
  CentralizedResult result;

  std::vector<Entry> entries;
  entries.push_back({continuation(solver, start_m, config.mu_initial), CentralizedStart::kStartPositions, false});
  if (config.start_from_gd) entries.push_back({gd_candidate(scenario, solver), CentralizedStart::kGd, false});
  if (scenario.num_uavs == scenario.num_bs_antennas()) {
    ura_baselines(scenario, solver, result);
    add_ura_entries(solver, result, entries);
  }
  if (config.barrier_polish) {
    for (Entry& e : entries) polish(solver, e.candidate);
  }
  keep_least_travel(solver, entries, result);
  if (result.status != CentralizedStatus::kFeasible) result.positions_m = start_m;
  result.icn = solver.icn(result.positions_m);
  result.travel = travel_stats(start_m, result.positions_m);
  result.num_solves = solver.num_solves;
  return result;
}

}  // namespace losmimo::fusion
