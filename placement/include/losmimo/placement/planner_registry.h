#pragma once
// The planners by name: every placement algorithm the apps, the experiment and the co-evaluation
// run is one entry here, found by the name a config lists (`[experiment] algorithms = gd, bf`,
// `[coevaluation] algorithms = cap+ekf`). A new planner is its own source file and one
// registration: builtin entries in planner_registry.cpp, others (a higher library's, a test's)
// through register_planner() before any settings are loaded.
//
// An entry is one of two kinds:
//   iterative  make() builds a Planner that run_placement() drives (gd, bf, cap, the URAs,
//              random);
//   direct     solve() computes the final placement from the start at once, and the swarm flies
//              straight to it (fly_straight(): the co-evaluation's centralized reference).
// Registration order is the order of every listing (--help, error messages, docs).

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "losmimo/placement/run.h"
#include "losmimo/placement/settings.h"

namespace losmimo::placement {

// What a direct planner computes: the final positions (3 x Nr, metres, BS frame) and whether
// they meet the run's target (false: the best it found).
struct DirectSolution {
  Eigen::Matrix3Xd positions_m;
  bool feasible = false;
};

struct PlannerEntry {
  std::string name;     // lower case, [a-z0-9_]: the config's and trials.csv's spelling
  std::string summary;  // one line for --help and docs/planners.md's table
  // The INI sections only this planner reads (its options and stop rule), e.g. {"gd"}; a
  // section may belong to several entries (the URA variants share [ura]).
  std::vector<std::string> sections;
  // Whether it asks the swarm where its UAVs are (Swarm::position_estimate): only then does a
  // localization error, or an estimator, reach it.
  bool uses_positions = true;
  // The figures' colour (gnuplot "#rrggbb").
  std::string plot_color = "#000000";
  // Iterative: the planner under settings p. Exactly one of make and solve is set.
  std::function<std::unique_ptr<Planner>(const PlacementSettings& p)> make;
  // Its stop rule: `run` ([placement]'s) with the planner's own target_icn / max_iterations where
  // set. Unset: [placement]'s as it is.
  std::function<RunOptions(const PlacementSettings& p, RunOptions run)> stop_rule;
  // Direct: the placement from `start_m` under settings p (deterministic: the same inputs give
  // the same bits; it may be called from several threads at once).
  std::function<DirectSolution(const PlacementSettings& p, const Eigen::Matrix3Xd& start_m)> solve;

  bool direct() const { return static_cast<bool>(solve); }
};

// Adds an entry. std::invalid_argument for a malformed entry (empty or badly spelled name,
// neither or both of make and solve) or a name already registered. Not thread-safe against
// concurrent lookups: register before any run starts.
void register_planner(PlannerEntry entry);
// The entry of `name`; nullptr when none.
const PlannerEntry* find_planner(const std::string& name);
// The entry of `name`; std::invalid_argument naming the known ones when none.
const PlannerEntry& planner_entry(const std::string& name);
// Every registered name, in registration order.
std::vector<std::string> planner_names();

// The stop rule `entry` runs under: its stop_rule over `run`, noise variance p's scenario's.
RunOptions planner_run_options(const PlannerEntry& entry, const PlacementSettings& p, RunOptions run);

// A direct planner's run: the UAVs fly from start_m to final_m simultaneously in straight lines;
// the ICN milestones (0.5, 0.95) are taken on that flight, sampled at `flight_steps` + 1 evenly
// spaced points, at the mean distance flown by then; iterations 0; status converged when
// `feasible`, iteration_cap otherwise.
RunResult fly_straight(const Scenario& scenario, const std::string& planner, const Eigen::Matrix3Xd& start_m,
                       const DirectSolution& solution, int flight_steps = 200);

}  // namespace losmimo::placement
