#include "losmimo/placement/experiment_trial.h"

#include <cmath>
#include <limits>
#include <memory>

#include "losmimo/placement/metrics.h"
#include "losmimo/placement/ura.h"

namespace losmimo::placement {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::unique_ptr<Planner> make_planner(const PlacementSettings& p, Algorithm a) {
  switch (a) {
    case Algorithm::kGd: return std::make_unique<GradientDescentPlanner>(p.scenario, p.gd);
    case Algorithm::kBf: return std::make_unique<BruteForcePlanner>(p.scenario, p.bf);
    case Algorithm::kUra: return std::make_unique<UraPlanner>(p.scenario, UraVariant::kRigid);
    case Algorithm::kUraLattice: return std::make_unique<UraPlanner>(p.scenario, UraVariant::kLattice);
    case Algorithm::kRandom: break;
  }
  return nullptr;
}

// Placement without motion: the start itself, evaluated like any other result.
class StayPlanner : public Planner {
 public:
  std::string name() const override { return "random"; }
  void iterate(Swarm& /*swarm*/, int /*iteration*/) override {}
};

Eigen::Matrix3Xd start_positions(const ExperimentSettings& s, int trial) {
  std::mt19937_64 rng(derive_seed(s.seed, {0, static_cast<std::uint64_t>(trial)}));
  return random_start_positions_m(s.placement.scenario, rng);
}

double mean_db(const Eigen::VectorXd& linear) {
  double sum = 0.0;
  for (Eigen::Index k = 0; k < linear.size(); ++k) sum += to_db(linear(k));
  return sum / linear.size();
}
}  // namespace

std::vector<TrialRecord> run_trial(const ExperimentSettings& s, Sweep sweep, int point, int trial) {
  const std::vector<double>& values = sweep == Sweep::kSigmaLoc ? s.sigma_loc_values_m : s.sigma_act_values_m;
  const double value = values.at(point);
  PlacementSettings p = s.placement;
  (sweep == Sweep::kSigmaLoc ? p.errors.sigma_loc_m : p.errors.sigma_act_m) = value;
  const std::uint64_t start_seed = derive_seed(s.seed, {0, static_cast<std::uint64_t>(trial)});
  const std::uint64_t seed = derive_seed(s.seed, {1, static_cast<std::uint64_t>(sweep),
                                                  static_cast<std::uint64_t>(point),
                                                  static_cast<std::uint64_t>(trial)});
  const ChannelModel model(p.scenario);
  const Eigen::Matrix3Xd start = start_positions(s, trial);

  std::vector<TrialRecord> records;
  for (const Algorithm a : s.algorithms) {
    Swarm swarm(model, start, p.errors, seed);
    std::unique_ptr<Planner> planner = make_planner(p, a);
    StayPlanner stay;
    RunOptions run = p.run;
    if (a == Algorithm::kRandom) run.max_iterations = 0;
    const RunResult r = run_placement(planner ? *planner : stay, swarm, run);

    TrialRecord rec;
    rec.sweep = sweep;
    rec.value = value;
    rec.algorithm = a;
    rec.trial = trial;
    rec.seed = seed;
    rec.start_seed = start_seed;
    rec.iterations = r.iterations;
    rec.converged = r.converged();
    rec.status = to_string(r.status);
    const LinkMetrics m = evaluate_link(model.matrix(r.final_m), p.scenario.noise_variance());
    rec.final_icn = m.icn;
    rec.dist_to_icn050_m = r.icn050.reached ? r.icn050.placement_dist_m : kNaN;
    rec.dist_to_icn095_m = r.icn095.reached ? r.icn095.placement_dist_m : kNaN;
    rec.dist_placement_m = r.placement_dist_m.mean();
    rec.probe_dist_m = r.probe_dist_m.mean();
    rec.dist_total_m = rec.dist_placement_m + rec.probe_dist_m;
    rec.sinr_nv_db = to_db(m.sinr.nv(0));
    rec.sinr_zf_db = to_db(m.sinr.zf(0));
    rec.sinr_mf_db = to_db(m.sinr.mf(0));
    rec.mean_sinr_nv_db = mean_db(m.sinr.nv);
    rec.mean_sinr_zf_db = mean_db(m.sinr.zf);
    rec.mean_sinr_mf_db = mean_db(m.sinr.mf);
    rec.sum_rate_nv_bps_hz = m.sum_rate_nv_bps_hz;
    rec.sum_rate_zf_bps_hz = m.sum_rate_zf_bps_hz;
    rec.start_m = r.start_m;
    rec.final_m = r.final_m;
    records.push_back(std::move(rec));
  }
  return records;
}

RunResult run_traced(const ExperimentSettings& s, Algorithm algorithm, int trial) {
  const PlacementSettings& p = s.placement;
  const ChannelModel model(p.scenario);
  Swarm swarm(model, start_positions(s, trial), ErrorModel{},
              derive_seed(s.seed, {2, static_cast<std::uint64_t>(trial)}));
  std::unique_ptr<Planner> planner = make_planner(p, algorithm);
  StayPlanner stay;
  RunOptions run = p.run;
  run.trace_sinr = true;
  if (!planner) run.max_iterations = 0;
  return run_placement(planner ? *planner : stay, swarm, run);
}

}  // namespace losmimo::placement
