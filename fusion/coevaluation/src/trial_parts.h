#pragma once
// What the co-evaluation's estimators (estimators.cpp) and its sweeps (coevaluation.cpp) share:
// the sensor and filter configs of a beacon-noise point, and the records of the closed loop.
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/estimator_registry.h"

namespace losmimo::coevaluation::detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The true sensors at beacon cross-range error beacon_noise_m [m] (sigma_angle = v / R).
localization::SimulatorConfig simulator_config(const CoevaluationSettings& c, const placement::Scenario& scenario,
                                               double beacon_noise_m);
// The filter assumes the true noise, floored (FilterConfig's min_sigma_*).
localization::FilterConfig filter_config(const CoevaluationSettings& c, const localization::SimulatorConfig& sim);

// Sets the given metrics of a record to NaN (it has no value for them).
void not_applicable(experiment::TrialRecord& r, std::initializer_list<experiment::MetricId> metrics);

// Every row of `rows` on one trial at one point of `sweep`, in order, from the trial's start and
// seed, the estimators at beacon noise beacon_noise_m (CoevalTrial).
std::vector<experiment::TrialRecord> run_rows(const experiment::ExperimentSettings& s, const CoevaluationSettings& c,
                                              const std::vector<CoevalRow>& rows, const std::string& sweep, int point,
                                              int trial, double beacon_noise_m);

// A sweep's trial function bound to the run's settings, its co-evaluation settings parsed once.
using TrialOf = std::vector<experiment::TrialRecord> (*)(const experiment::ExperimentSettings&,
                                                         const CoevaluationSettings&, int, int);
experiment::ExperimentExtension::TrialFn bound(const experiment::ExperimentSettings& s, TrialOf run);

// A co-evaluation sweep's extension: its sweep points from the parsed settings, its trial
// function bound once per run, its figures and report section.
experiment::ExperimentExtension make_extension(const std::string& sweep,
                                               std::vector<double> (*values)(const CoevaluationSettings&),
                                               TrialOf trial,
                                               decltype(experiment::ExperimentExtension::figures) figures,
                                               decltype(experiment::ExperimentExtension::report_section) section);

// The record of gd's closed loop under `config` for row `name` (metrics from its statistics).
experiment::TrialRecord closed_loop_record(const experiment::ExperimentSettings& s, const std::string& sweep, int point,
                                           int trial, const std::string& name, const fusion::ClosedLoopConfig& config);

}  // namespace losmimo::coevaluation::detail

namespace losmimo::coevaluation {
// The builtin estimators, in registration order (estimators.cpp).
std::vector<EstimatorEntry> builtin_estimators();
}  // namespace losmimo::coevaluation
