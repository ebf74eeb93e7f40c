#include "losmimo/placement/common/hash.h"
#include "losmimo/placement/common/seed.h"
#include "losmimo/placement/experiment/trial.h"

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include "losmimo/placement/experiment/capacity_claims.h"
#include "losmimo/placement/capacity.h"
#include "losmimo/placement/metrics.h"
#include "losmimo/placement/ura.h"

namespace losmimo::experiment {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean_db(const Eigen::VectorXd& linear) {
  double sum = 0.0;
  for (Eigen::Index k = 0; k < linear.size(); ++k) sum += placement::to_db(linear(k));
  return sum / linear.size();
}

}  // namespace

std::unique_ptr<placement::Planner> make_planner(const placement::PlacementSettings& p, const Algorithm& a) {
  const placement::PlannerEntry& e = a.entry();
  if (!e.make) throw std::invalid_argument("make_planner: " + e.name + " is a direct planner");
  return e.make(p);
}

Algorithm ura_algorithm_of(placement::UraVariant variant) {
  switch (variant) {
    case placement::UraVariant::kLattice:
      return Algorithm::kUraLattice;
    case placement::UraVariant::kLatticeExact:
      return Algorithm::kUraLatticeExact;
    case placement::UraVariant::kRigid:
      break;
  }
  return Algorithm::kUra;
}

placement::RunOptions run_options_of(const placement::PlacementSettings& p, const Algorithm& a,
                                     placement::RunOptions run) {
  return placement::planner_run_options(a.entry(), p, run);
}

namespace {
// run_algorithm; `seed_free` (optional) is set to whether the run took nothing from its seed
// (SeedFreeRuns): no normal draw, and no position estimate under a localization error.
placement::RunResult run_algorithm_on_swarm(const ExperimentSettings& s, const placement::PlacementSettings& p,
                                            const Algorithm& a, int trial, const Eigen::Matrix3Xd& start,
                                            std::uint64_t seed, placement::RunOptions run, bool* seed_free) {
  const placement::PlannerEntry& entry = a.entry();
  if (entry.direct()) {  // computed at once from the start: no swarm, no draw
    if (seed_free) *seed_free = true;
    return placement::fly_straight(p.scenario, entry.name, start, entry.solve(p, start));
  }
  run = placement::planner_run_options(entry, p, run);
  const placement::ChannelModel model(p.scenario);
  placement::Swarm swarm(model, start, p.errors, seed);
  if (p.channel.active()) {
    swarm.set_channel_conditions(placement::ChannelConditions(p.channel, swarm.num_uavs(), model.num_antennas(),
                                                              trial_scatter_seed(s, trial),
                                                              common::derive_seed(seed, {5})));
  }
  const std::unique_ptr<placement::Planner> planner = entry.make(p);
  placement::RunResult result = placement::run_placement(*planner, swarm, run);
  if (seed_free) {
    *seed_free = !p.channel.active() && swarm.normal_blocks_drawn() == 0 &&
                 (p.errors.exact_localization() || swarm.position_estimates() == 0);
  }
  return result;
}
}  // namespace

placement::RunResult run_algorithm(const ExperimentSettings& s, const placement::PlacementSettings& p,
                                   const Algorithm& a, int trial, const Eigen::Matrix3Xd& start, std::uint64_t seed,
                                   placement::RunOptions run) {
  return run_algorithm_on_swarm(s, p, a, trial, start, seed, run, nullptr);
}

bool SeedFreeRuns::applies(const placement::PlacementSettings& p, const Algorithm& a) {
  return !p.channel.active() && p.errors.sigma_act_m == 0.0 &&
         (p.errors.exact_localization() || !a.entry().uses_positions);
}

std::optional<TrialRecord> SeedFreeRuns::find(const Algorithm& a, int trial) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto it = records_.find({a.name(), trial});
  if (it == records_.end()) return std::nullopt;
  return it->second;
}

void SeedFreeRuns::put(const Algorithm& a, int trial, const TrialRecord& record) {
  const std::lock_guard<std::mutex> lock(mutex_);
  records_.emplace(std::make_pair(a.name(), trial), record);
}

std::uint64_t trial_start_seed(const ExperimentSettings& s, int trial) {
  return common::derive_seed(s.seed, {0, static_cast<std::uint64_t>(trial)});
}

Eigen::Matrix3Xd trial_start_positions_m(const ExperimentSettings& s, int trial) {
  std::mt19937_64 rng(trial_start_seed(s, trial));
  return placement::random_start_positions_m(s.placement.scenario, rng);
}

std::uint64_t trial_seed(const ExperimentSettings& s, const std::string& sweep, int point, int trial) {
  return common::derive_seed(
      s.seed, {1, common::fnv1a64(sweep), static_cast<std::uint64_t>(point), static_cast<std::uint64_t>(trial)});
}

std::uint64_t trial_scatter_seed(const ExperimentSettings& s, int trial) {
  return common::derive_seed(s.seed, {4, static_cast<std::uint64_t>(trial)});
}

std::uint64_t trial_fading_eval_seed(const ExperimentSettings& s, int trial) {
  return common::derive_seed(s.seed, {3, static_cast<std::uint64_t>(trial)});
}

TrialRecord make_record(const ExperimentSettings& s, const std::string& sweep, int point, int trial,
                        const std::string& algorithm, const placement::RunResult& r) {
  return make_record(s, s.placement, sweep, point, trial, algorithm, r);
}

TrialRecord make_record(const ExperimentSettings& s, const placement::PlacementSettings& p, const std::string& sweep,
                        int point, int trial, const std::string& algorithm, const placement::RunResult& r,
                        placement::FadedLinkMetrics* metrics) {
  const SweepPoints* points = s.sweep(sweep);
  TrialRecord rec;
  rec.sweep = sweep;
  rec.value = points ? points->values.at(point) : kNaN;
  rec.algorithm = algorithm;
  rec.trial = trial;
  rec.seed = trial_seed(s, sweep, point, trial);
  rec.start_seed = trial_start_seed(s, trial);
  rec.iterations = r.iterations;
  rec.converged = r.converged();
  rec.status = to_string(r.status);
  const placement::Scenario& scenario = p.scenario;
  const Eigen::MatrixXcd H_los = placement::ChannelModel(scenario).matrix(r.final_m);
  const placement::FadedLinkMetrics faded =
      placement::evaluate_link_faded(H_los, scenario.noise_variance(), p.channel, trial_fading_eval_seed(s, trial));
  if (s.capacity_columns) {
    rec.capacity_claims = capacity_claim_values(scenario, p.cap.power, H_los, r.start_m, r.final_m);
  }
  if (metrics) *metrics = faded;
  const placement::LinkMetrics& m = faded.los;
  rec.final_icn = m.icn;
  rec.dist_to_icn050_m = r.icn050.reached ? r.icn050.placement_dist_m : kNaN;
  rec.dist_to_icn095_m = r.icn095.reached ? r.icn095.placement_dist_m : kNaN;
  rec.icn050_iteration = r.icn050.reached ? r.icn050.iteration : -1;
  rec.icn095_iteration = r.icn095.reached ? r.icn095.iteration : -1;
  rec.dist_placement_m = r.placement_dist_m.mean();
  rec.probe_dist_m = r.probe_dist_m.mean();
  rec.dist_total_m = rec.dist_placement_m + rec.probe_dist_m;
  rec.sinr_nv_db = placement::to_db(m.sinr.nv(0));
  rec.sinr_zf_db = placement::to_db(m.sinr.zf(0));
  rec.sinr_mf_db = placement::to_db(m.sinr.mf(0));
  rec.mean_sinr_nv_db = mean_db(m.sinr.nv);
  rec.mean_sinr_zf_db = mean_db(m.sinr.zf);
  rec.mean_sinr_mf_db = mean_db(m.sinr.mf);
  rec.sum_rate_nv_bps_hz = m.sum_rate_nv_bps_hz;
  rec.sum_rate_zf_bps_hz = m.sum_rate_zf_bps_hz;
  if (faded.draws > 0) {  // fading: the true channel's means over the draws
    rec.final_icn = faded.icn;
    rec.sinr_nv_db = faded.sinr_nv_db(0);
    rec.sinr_zf_db = faded.sinr_zf_db(0);
    rec.sinr_mf_db = faded.sinr_mf_db(0);
    rec.mean_sinr_nv_db = faded.sinr_nv_db.mean();
    rec.mean_sinr_zf_db = faded.sinr_zf_db.mean();
    rec.mean_sinr_mf_db = faded.sinr_mf_db.mean();
    rec.sum_rate_nv_bps_hz = faded.sum_rate_nv_bps_hz;
    rec.sum_rate_zf_bps_hz = faded.sum_rate_zf_bps_hz;
  }
  rec.start_m = r.start_m;
  rec.final_m = r.final_m;
  return rec;
}

std::vector<TrialRecord> run_trial(const ExperimentSettings& s, const std::string& sweep, int point, int trial,
                                   SeedFreeRuns* seed_free) {
  placement::PlacementSettings p = s.placement;
  const SweepPoints* points = s.sweep(sweep);
  if (!points) throw std::invalid_argument("run_trial: the settings have no '" + sweep + "' sweep");
  const double value = points->values.at(point);
  if (sweep == kSweepSigmaLoc) {
    p.errors.sigma_loc_m = value;
  } else if (sweep == kSweepSigmaAct) {
    p.errors.sigma_act_m = value;
  } else {
    throw std::invalid_argument("run_trial: '" + sweep + "' is not a built-in sweep");
  }
  const Eigen::Matrix3Xd start = trial_start_positions_m(s, trial);
  const std::uint64_t seed = trial_seed(s, sweep, point, trial);
  placement::RunOptions run = p.run;
  run.full_icn_trace = false;  // only milestones and the final positions are recorded
  std::vector<TrialRecord> records;
  for (const Algorithm& a : s.algorithms) {
    const bool reusable = seed_free && SeedFreeRuns::applies(p, a);
    if (std::optional<TrialRecord> done = reusable ? seed_free->find(a, trial) : std::nullopt) {
      done->sweep = sweep;  // make_record's point-dependent fields
      done->value = points->values.at(point);
      done->seed = seed;
      records.push_back(std::move(*done));
      continue;
    }
    bool drew_nothing = false;
    const placement::RunResult r = run_algorithm_on_swarm(s, p, a, trial, start, seed, run, &drew_nothing);
    records.push_back(make_record(s, p, sweep, point, trial, to_string(a), r));
    if (reusable && !drew_nothing) {
      throw std::logic_error("run_trial: " + to_string(a) +
                             " drew from its seed in a run SeedFreeRuns calls seed-free");
    }
    if (reusable) seed_free->put(a, trial, records.back());
  }
  return records;
}

placement::RunResult run_traced(const ExperimentSettings& s, const Algorithm& algorithm, int trial, bool record_path) {
  placement::PlacementSettings p = s.placement;
  p.errors = placement::ErrorModel{};
  placement::RunOptions run = p.run;
  run.trace_sinr = true;
  run.record_path = record_path;
  return run_algorithm(s, p, algorithm, trial, trial_start_positions_m(s, trial),
                       common::derive_seed(s.seed, {2, static_cast<std::uint64_t>(trial)}), run);
}

placement::RunResult run_path(const ExperimentSettings& s, const Algorithm& algorithm, int trial, double sigma_act_m) {
  placement::PlacementSettings p = s.placement;
  p.errors.clear_localization();
  p.errors.sigma_act_m = sigma_act_m;
  placement::RunOptions run = p.run;
  run.record_path = true;
  return run_algorithm(s, p, algorithm, trial, trial_start_positions_m(s, trial),
                       common::derive_seed(s.seed, {6, static_cast<std::uint64_t>(trial)}), run);
}

}  // namespace losmimo::experiment
