// The planner registry (planner_registry.h) and its builtin entries.
#include "losmimo/placement/planner_registry.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "losmimo/placement/common/named_registry.h"
#include "losmimo/placement/bf.h"
#include "losmimo/placement/capacity.h"
#include "losmimo/placement/channel.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/ura.h"

namespace losmimo::placement {

namespace {

// Placement without motion: the start itself, evaluated like any other result.
class StayPlanner : public Planner {
 public:
  std::string name() const override { return "random"; }
  void iterate(Swarm& /*swarm*/, int /*iteration*/) override {}
};

// A stop rule from one RunOverride of the settings.
std::function<RunOptions(const PlacementSettings&, RunOptions)> override_of(RunOverride PlacementSettings::*field) {
  return [field](const PlacementSettings& p, RunOptions run) { return with_override(run, p.*field); };
}

PlannerEntry ura_entry(const std::string& name, UraVariant variant, const std::string& summary,
                       const std::string& color) {
  PlannerEntry e;
  e.name = name;
  e.summary = summary;
  e.sections = {"ura"};
  e.plot_color = color;
  e.make = [variant](const PlacementSettings& p) { return std::make_unique<UraPlanner>(p.scenario, variant, p.ura); };
  e.stop_rule = override_of(&PlacementSettings::ura_run);
  return e;
}

std::vector<PlannerEntry> builtin_planners() {
  std::vector<PlannerEntry> out;
  {
    PlannerEntry e;
    e.name = "random";
    e.summary = "no motion: the random start itself (the paper's baseline)";
    e.uses_positions = false;
    e.plot_color = "#7f7f7f";
    e.make = [](const PlacementSettings&) { return std::make_unique<StayPlanner>(); };
    e.stop_rule = [](const PlacementSettings&, RunOptions run) {
      run.max_iterations = 0;
      return run;
    };
    out.push_back(std::move(e));
  }
  {
    PlannerEntry e;
    e.name = "gd";
    e.summary = "distributed gradient descent on the objective f ([gd]; needs each UAV's position)";
    e.sections = {"gd"};
    e.plot_color = "#1f77b4";
    e.make = [](const PlacementSettings& p) { return std::make_unique<GradientDescentPlanner>(p.scenario, p.gd); };
    e.stop_rule = override_of(&PlacementSettings::gd_run);
    out.push_back(std::move(e));
  }
  {
    PlannerEntry e;
    e.name = "bf";
    e.summary = "distributed brute force, 7 probe moves per UAV ([bf]; channel measurements only)";
    e.sections = {"bf"};
    e.uses_positions = false;
    e.plot_color = "#d62728";
    e.make = [](const PlacementSettings& p) { return std::make_unique<BruteForcePlanner>(p.scenario, p.bf); };
    e.stop_rule = override_of(&PlacementSettings::bf_run);
    out.push_back(std::move(e));
  }
  out.push_back(ura_entry("ura", UraVariant::kRigid,
                          "the optimal URA reached by a minimum-distance assignment, rigid ([ura])", "#2ca02c"));
  out.push_back(ura_entry("ura_lattice", UraVariant::kLattice,
                          "the URA assignment over the optimal lattice's translations ([ura])", "#ff7f0e"));
  out.push_back(ura_entry("ura_lattice_exact", UraVariant::kLatticeExact,
                          "ura_lattice with the exact assignment over every translation ([ura])", "#9467bd"));
  {
    PlannerEntry e;
    e.name = "cap";
    e.summary = "gradient ascent on the capacity (the follow-up paper's planner; [cap])";
    e.sections = {"cap"};
    e.plot_color = "#8c564b";
    e.make = [](const PlacementSettings& p) { return std::make_unique<CapacityPlanner>(p.scenario, p.cap); };
    e.stop_rule = override_of(&PlacementSettings::cap_run);
    out.push_back(std::move(e));
  }
  return out;
}

common::NamedRegistry<PlannerEntry>& registry() {
  static common::NamedRegistry<PlannerEntry> entries("planner", builtin_planners());
  return entries;
}

}  // namespace

void register_planner(PlannerEntry entry) {
  if (static_cast<bool>(entry.make) == static_cast<bool>(entry.solve)) {
    throw std::invalid_argument("register_planner: " + entry.name + ": exactly one of make and solve");
  }
  registry().add(std::move(entry));
}

const PlannerEntry* find_planner(const std::string& name) { return registry().find(name); }
const PlannerEntry& planner_entry(const std::string& name) { return registry().at(name); }
std::vector<std::string> planner_names() { return registry().names(); }

RunOptions planner_run_options(const PlannerEntry& entry, const PlacementSettings& p, RunOptions run) {
  if (entry.stop_rule) run = entry.stop_rule(p, run);
  run.noise_variance = p.scenario.noise_variance();
  return run;
}

RunResult fly_straight(const Scenario& scenario, const std::string& planner, const Eigen::Matrix3Xd& start_m,
                       const DirectSolution& solution, int flight_steps) {
  RunResult r;
  r.planner = planner;
  r.status = solution.feasible ? RunStatus::kConverged : RunStatus::kIterationCap;
  r.iterations = 0;
  r.start_m = start_m;
  r.final_m = solution.positions_m;
  r.placement_dist_m = (solution.positions_m - start_m).colwise().norm().transpose();
  r.probe_dist_m = Eigen::VectorXd::Zero(start_m.cols());
  const double mean_m = r.placement_dist_m.mean();
  const ChannelModel model(scenario);
  for (int step = 0; step <= flight_steps; ++step) {
    const double t = static_cast<double>(step) / flight_steps;
    const double icn = inverse_condition_number(model.matrix(start_m + t * (solution.positions_m - start_m)));
    for (auto [milestone, threshold] : {std::pair{&r.icn050, 0.5}, std::pair{&r.icn095, 0.95}}) {
      if (!milestone->reached && icn >= threshold) *milestone = {true, 0, t * mean_m};
    }
  }
  return r;
}

}  // namespace losmimo::placement
