#pragma once
// One Monte Carlo trial of the experiment: every algorithm from the same start with the same
// error seed (paired comparison), and the Fig 1 traced runs.
//
// Seeds: start_seed = derive_seed(seed, {0, trial}) (the same start at every sweep point);
//        seed       = derive_seed(seed, {1, fnv1a(sweep name), point, trial}) drives the error
//        draws: adding or reordering sweeps changes no other sweep's numbers.
//        With [channel] conditions (placement/channel_conditions.h): the scatter of every run of
//        trial t from derive_seed(seed, {4, t}) and the evaluation draws at the final positions
//        from derive_seed(seed, {3, t}) (the same for every algorithm and sweep point), the
//        estimation noise of a run from derive_seed(its error seed, {5}).
//        The Fig 1 traced runs draw from derive_seed(seed, {2, t}), the path figure's runs from
//        derive_seed(seed, {6, t}). Each first tag belongs to one purpose only.
// Distances are means per UAV in metres; dist_to_icn050_m / dist_to_icn095_m are placement
// distance when the ICN first reached 0.5 / 0.95 (NaN if never); dist_total_m is everything
// flown (placement + probe), probe_dist_m the BF probe flights alone. SINR columns are stream 1
// (as the paper) and the mean of the per-stream dB values, at the final positions; streams are
// the BS antennas when Nr >= Nt, the UAVs when Nr < Nt (placement/metrics.h). With Rician fading
// the final metrics are of the true channel, averaged over [channel] fading_eval_draws scatter
// draws (ICN and sum rates linearly, SINR in dB).
// icn050_iteration / icn095_iteration: the iteration at which the ICN first reached 0.5 / 0.95
// (-1: never); they are columns of trials.csv and summary.csv only with
// [experiment] milestone_columns (iterations_to_icn050, iterations_to_icn095).

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/placement/experiment/metric_values.h"
#include "losmimo/placement/experiment/settings.h"
#include "losmimo/placement/channel_conditions.h"
#include "losmimo/placement/run.h"
#include "losmimo/placement/ura.h"

namespace losmimo::experiment {

struct TrialRecord {
  std::string sweep;   // the sweep's name, e.g. "sigma_loc_m"
  double value = 0.0;  // the swept quantity at this point
  std::string algorithm;
  int trial = 0;
  std::uint64_t seed = 0;
  std::uint64_t start_seed = 0;
  int iterations = 0;
  bool converged = false;
  std::string status;
  double final_icn = 0.0;
  double dist_to_icn050_m = 0.0;
  double dist_to_icn095_m = 0.0;
  double dist_total_m = 0.0;
  double dist_placement_m = 0.0;
  double probe_dist_m = 0.0;
  double sinr_nv_db = 0.0;
  double sinr_zf_db = 0.0;
  double sinr_mf_db = 0.0;
  double mean_sinr_nv_db = 0.0;
  double mean_sinr_zf_db = 0.0;
  double mean_sinr_mf_db = 0.0;
  double sum_rate_nv_bps_hz = 0.0;
  double sum_rate_zf_bps_hz = 0.0;
  int icn050_iteration = -1;
  int icn095_iteration = -1;
  Eigen::Matrix3Xd start_m;
  Eigen::Matrix3Xd final_m;
  // An extension's metrics, set by handle (ExperimentExtension::metrics; every one, NaN where it
  // does not apply).
  MetricValues extension;
  // With [experiment] capacity_columns, capacity_claim_metrics()' values (capacity_claims.h).
  MetricValues capacity_claims;
  // The extra columns (extra_metric_names, extension.h), in that order: the engine fills them
  // from `extension` and the milestones, and clears `extension`.
  std::vector<double> extra;
};

// The trial's start positions and seeds (shared by every sweep kind, extensions included).
Eigen::Matrix3Xd trial_start_positions_m(const ExperimentSettings& settings, int trial);
std::uint64_t trial_start_seed(const ExperimentSettings& settings, int trial);
std::uint64_t trial_seed(const ExperimentSettings& settings, const std::string& sweep, int point, int trial);
std::uint64_t trial_scatter_seed(const ExperimentSettings& settings, int trial);
std::uint64_t trial_fading_eval_seed(const ExperimentSettings& settings, int trial);

// The planner of iterative algorithm a under placement settings p (its registry entry's make:
// [gd], [bf], [ura], [cap] options; random stays at the start); std::invalid_argument for a
// direct one.
std::unique_ptr<placement::Planner> make_planner(const placement::PlacementSettings& p, const Algorithm& a);
// The URA algorithm of a variant (ura, ura_lattice, ura_lattice_exact).
Algorithm ura_algorithm_of(placement::UraVariant variant);
// The stop rule algorithm a runs under: `run` with the algorithm's own [gd] / [bf] / [ura] / [cap]
// target_icn and max_iterations where set (random: 0 iterations), noise variance the scenario's
// (placement::planner_run_options).
placement::RunOptions run_options_of(const placement::PlacementSettings& p, const Algorithm& a,
                                     placement::RunOptions run);

// Runs algorithm a from `start` under the placement settings p, errors drawn from `seed`, with
// p.channel's conditions (trial `trial`'s scatter) when active. A direct planner's run is its
// solution flown straight (placement::fly_straight), without errors.
placement::RunResult run_algorithm(const ExperimentSettings& settings, const placement::PlacementSettings& p,
                                   const Algorithm& a, int trial, const Eigen::Matrix3Xd& start, std::uint64_t seed,
                                   placement::RunOptions run);

// Fills a record's common fields from a finished run (metrics at the final positions).
TrialRecord make_record(const ExperimentSettings& settings, const std::string& sweep, int point, int trial,
                        const std::string& algorithm, const placement::RunResult& run);
// The same for a run under placement settings p (another scenario or channel than settings');
// `metrics` (optional) receives the final positions' metrics.
TrialRecord make_record(const ExperimentSettings& settings, const placement::PlacementSettings& p,
                        const std::string& sweep, int point, int trial, const std::string& algorithm,
                        const placement::RunResult& run, placement::FadedLinkMetrics* metrics = nullptr);

// The runs of one experiment that take nothing from their seed, one record per (algorithm,
// trial), shared by the sweep points that would repeat them; safe to use from several threads.
// A run is seed-free when no channel conditions are active, sigma_act_m is 0 and either
// sigma_loc_m is 0 or the algorithm never estimates a position (its planner does not use positions: bf, random): then
// it draws no number, and its record differs between those points only in sweep, value and seed. Whichever point
// computes it first stores it; one computed twice (two threads at once) is the same.
class SeedFreeRuns {
 public:
  // Whether algorithm a under placement settings p is seed-free (above).
  static bool applies(const placement::PlacementSettings& p, const Algorithm& a);
  std::optional<TrialRecord> find(const Algorithm& a, int trial) const;
  void put(const Algorithm& a, int trial, const TrialRecord& record);

 private:
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, int>, TrialRecord> records_;
};

// The built-in sweeps (sigma_loc_m, sigma_act_m): the settings' algorithms on trial `trial`
// at sweep point `point`. With `seed_free` (one per experiment), seed-free runs are computed once
// and their records reused with this point's sweep, value and seed: the same records.
std::vector<TrialRecord> run_trial(const ExperimentSettings& settings, const std::string& sweep, int point, int trial,
                                   SeedFreeRuns* seed_free = nullptr);

// A Fig 1 run: `algorithm` without errors from trial `trial`'s start, SINR traced (and with
// record_path, the positions after every iteration).
placement::RunResult run_traced(const ExperimentSettings& settings, const Algorithm& algorithm, int trial,
                                bool record_path = false);
// The same start under actuation error sigma_act_m alone, positions recorded (the path figure);
// seed derive_seed(seed, {6, trial}).
placement::RunResult run_path(const ExperimentSettings& settings, const Algorithm& algorithm, int trial,
                              double sigma_act_m);

}  // namespace losmimo::experiment
