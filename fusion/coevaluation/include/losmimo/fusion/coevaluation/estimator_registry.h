#pragma once
// The estimators by name, and the co-evaluation's rows as (planner, estimator) pairs.
//
// A row of the beacon_noise_m and beacon_outage sweeps is a planner of placement's registry
// (placement/planner_registry.h) paired with an estimator of this one: what the planner believes
// about where its UAVs are. `[coevaluation] algorithms` lists rows by alias (gd_ekf, bf, ...) or
// as `planner+estimator` (ura_lattice+pf, cap+gauss); a pair that has an alias is named by it.
// A new estimator is its own source file and one registration (builtin entries in
// estimators.cpp; others, e.g. a test's, through register_estimator() before settings load).
//
// The builtin estimators:
//   truth           the planner sees the true positions (sigma_loc 0); the only one a planner
//                   that uses no positions (bf, random) or a direct one (centralized) pairs with
//   gauss           the paper's Gaussian localization error, sigma_loc_m = the point's beacon
//                   noise v, with [errors] sigma_loc_common_m as its common-mode part
//   gauss_matched   the Gaussian at the error the same planner's ekf row measured in the same
//                   trial and point (sigma_loc_m = its loc_lateral_rmse_m / sqrt(2))
//   gauss_shape_matched  the same at the ekf row's shape error: sigma_loc_m = its
//                   shape_lateral_rmse_m / sqrt((2N - 3) / N), the model's expected shape RMSE
//                   per unit sigma (placement/swarm_shape.h)
//   gauss_split_matched  the Gaussian with both parts matched to the ekf row: the independent
//                   sigma as gauss_shape_matched's, the common-mode sigma (placement/swarm.h)
//                   such that the expected common lateral offset is the ekf row's
//                   common_lateral_m. The matched rows use no [errors] sigma_loc_common_m.
//   ekf, pf         every UAV's own beacon + dead-reckoning filter (fusion/estimation_step.h);
//                   with gd the closed loop (fusion/closed_loop.h, BF fallback on), with another
//                   iterative planner that planner on the filters' beliefs, one epoch per
//                   position estimate (Swarm::set_position_estimator)
//   ekf_nofallback  gd's closed loop with the BF fallback off (gd only)
//   ekf_ceres       gd's closed loop with the EKF and Ceres CSI refinement (gd only)

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/trial.h"
#include "losmimo/fusion/closed_loop.h"
#include "losmimo/placement/channel.h"
#include "losmimo/placement/planner_registry.h"

namespace losmimo::coevaluation {

struct CoevaluationSettings;

// One row: trials.csv's `algorithm` is `name`.
struct CoevalRow {
  std::string name;       // the alias of the pair, else "planner+estimator"
  std::string planner;    // a name of placement's planner registry
  std::string estimator;  // a name of the estimator registry
  bool same_pair(const CoevalRow& other) const { return planner == other.planner && estimator == other.estimator; }
};

// What an estimator's run sees of one trial at one beacon_noise_m point. Every row of the trial
// starts from start_m with the same seed (paired comparison).
struct CoevalTrial {
  const experiment::ExperimentSettings& settings;
  const CoevaluationSettings& coevaluation;
  std::string sweep;
  int point = 0;
  int trial = 0;
  double beacon_noise_m = 0.0;  // the point's value v (coevaluation.h)
  Eigen::Matrix3Xd start_m;
  std::uint64_t seed = 0;
  const placement::ChannelModel& model;
  // The rows of this trial already run, with their records (same order).
  const std::vector<CoevalRow>& rows_done;
  const std::vector<experiment::TrialRecord>& records_done;

  // The record of `row`'s finished run (experiment::make_record); its metrics still unset.
  experiment::TrialRecord record(const CoevalRow& row, const placement::RunResult& run) const;
};

struct EstimatorEntry {
  std::string name;     // [a-z0-9_]+
  std::string summary;  // one line for --help and docs/experiment-sweeps.md
  // The keys ("section.key") that only rows with this estimator read: unused otherwise.
  std::vector<std::string> keys;
  // Why the pair (planner, this estimator) cannot run; nullopt when it can.
  std::function<std::optional<std::string>(const placement::PlannerEntry& planner)> refuses;
  // Runs `row` (planner, this estimator) on trial t and returns its record with every
  // coevaluation metric set (NaN where it has no value). Deterministic in its inputs; may run on
  // several threads at once.
  std::function<experiment::TrialRecord(const CoevalRow& row, const placement::PlannerEntry& planner,
                                        const CoevalTrial& t)>
      run;
  // A filter estimator's closed-loop configuration at beacon cross-range error v [m] (the
  // beacon_outage sweep runs gd's closed loop with it); unset for the others.
  std::function<fusion::ClosedLoopConfig(const CoevaluationSettings& c, const placement::Scenario& scenario,
                                         double beacon_noise_m)>
      closed_loop;
};

// Adds an entry; std::invalid_argument for a malformed entry (bad name, no run or refuses) or a
// name registered already. Register before any run starts.
void register_estimator(EstimatorEntry entry);
const EstimatorEntry* find_estimator(const std::string& name);
// std::invalid_argument naming the known ones when absent.
const EstimatorEntry& estimator_entry(const std::string& name);
std::vector<std::string> estimator_names();  // registration order

// The aliases of today's row names, in their documented order: (alias, planner, estimator).
// ura_ekf's planner is [coevaluation] ura_variant's URA (resolve_rows()).
struct RowAlias {
  std::string alias, planner, estimator;
};
const std::vector<RowAlias>& row_aliases();
// The rows of these aliases, in order (unresolved, as parse_row gives them); std::logic_error for
// a name that is not an alias.
std::vector<CoevalRow> aliased_rows(const std::vector<std::string>& aliases);

// The row `text` names (an alias or "planner+estimator"), unresolved; common::InputError naming
// `where`, the text and the known names when it names nothing registered.
CoevalRow parse_row(const std::string& text, const std::string& where);
// ura_ekf's planner from the variant, then each row's canonical name (its pair's alias, when it
// has one) and its pair checked: common::FieldError on `field` for a pair its estimator refuses
// or a pair listed twice.
void resolve_rows(std::vector<CoevalRow>& rows, placement::UraVariant ura_variant, const std::string& field);

// Registers the co-evaluation's direct planner (centralized: the Ceres solution of eq. 4 with
// perfect knowledge, fusion/centralized.h) in placement's registry; idempotent and thread-safe.
void register_coevaluation_planners();

}  // namespace losmimo::coevaluation
