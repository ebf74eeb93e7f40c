// The co-evaluation trials (coevaluation.h): one record per row (planner, estimator) from a
// shared start and seed, with the localization statistics as extra columns.
#include "losmimo/fusion/coevaluation/coevaluation.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "losmimo/fusion/coevaluation/report.h"
#include "losmimo/placement/metrics.h"
#include "trial_parts.h"

namespace losmimo::coevaluation {

namespace detail {

localization::SimulatorConfig simulator_config(const CoevaluationSettings& c, const placement::Scenario& scenario,
                                               double beacon_noise_m) {
  localization::SimulatorConfig sim;
  sim.sigma_range_m = c.closed_loop.simulator.sigma_range_m;
  sim.sigma_angle_rad = beacon_noise_m / scenario.range_m();
  sim.dr_sigma_floor_m = c.closed_loop.simulator.dr_sigma_floor_m;
  sim.dr_sigma_fraction = c.closed_loop.simulator.dr_sigma_fraction;
  sim.bs_azimuth_bias_rad = c.closed_loop.simulator.bs_azimuth_bias_rad;
  sim.bs_elevation_bias_rad = c.closed_loop.simulator.bs_elevation_bias_rad;
  sim.beacon_range_bias_m = c.closed_loop.simulator.beacon_range_bias_m;
  sim.bs_position_error_m = c.closed_loop.simulator.bs_position_error_m;
  return sim;
}

// A zero-noise beacon would make the EKF's innovation covariance singular and the refinement's
// whitening infinite: hence the floors.
localization::FilterConfig filter_config(const CoevaluationSettings& c, const localization::SimulatorConfig& sim) {
  localization::FilterConfig f;
  f.noise.sigma_range_m = std::max(sim.sigma_range_m, f.min_sigma_range_m);
  f.noise.sigma_angle_rad = std::max(sim.sigma_angle_rad, f.min_sigma_angle_rad);
  f.noise.dr_sigma_floor_m = sim.dr_sigma_floor_m;
  f.noise.dr_sigma_fraction = sim.dr_sigma_fraction;
  f.num_particles = c.closed_loop.filter.num_particles;
  return f;
}

void not_applicable(experiment::TrialRecord& r, std::initializer_list<experiment::MetricId> metrics) {
  for (const experiment::MetricId m : metrics) r.extension.set(m, kNaN);
}

namespace {
double fallback_fraction(const fusion::ClosedLoopStats& s, int iterations) {
  int bf = 0;
  for (const int n : s.bf_fallback_iterations) bf += n;
  const double uav_iterations = static_cast<double>(s.bf_fallback_iterations.size()) * iterations;
  return uav_iterations > 0.0 ? bf / uav_iterations : 0.0;
}
}  // namespace

experiment::TrialRecord closed_loop_record(const experiment::ExperimentSettings& s, const std::string& sweep, int point,
                                           int trial, const std::string& name, const fusion::ClosedLoopConfig& config) {
  const fusion::ClosedLoopRun r = fusion::run_closed_loop(s.placement, experiment::trial_start_positions_m(s, trial),
                                                          config, experiment::trial_seed(s, sweep, point, trial));
  experiment::TrialRecord rec = experiment::make_record(s, sweep, point, trial, name, r.run);
  rec.extension.set(kLocRmse, r.stats.rmse_m);
  rec.extension.set(kLocLateralRmse, r.stats.lateral_rmse_m);
  rec.extension.set(kCommonLateral, r.stats.common_lateral_rms_m);
  rec.extension.set(kShapeLateralRmse, r.stats.shape_lateral_rmse_m);
  rec.extension.set(kShapeNees, r.stats.shape_nees_per_dof);
  rec.extension.set(kNees, r.stats.average_nees);
  rec.extension.set(kBfFallbackFraction, fallback_fraction(r.stats, r.run.iterations));
  rec.extension.set(kBeaconLateralRmse, r.stats.num_beacons > 0 ? r.stats.beacon_only_lateral_rmse_m : kNaN);
  not_applicable(rec, {kPairedTravelDiff, kPairedIterationsDiff});
  return rec;
}

}  // namespace detail

fusion::ClosedLoopConfig coevaluation_closed_loop_config(const CoevaluationSettings& c,
                                                         const placement::Scenario& scenario,
                                                         const std::string& estimator, double beacon_noise_m) {
  const EstimatorEntry& e = estimator_entry(estimator);
  if (!e.closed_loop) {
    throw std::invalid_argument("coevaluation_closed_loop_config: " + estimator + " runs no closed loop");
  }
  return e.closed_loop(c, scenario, beacon_noise_m);
}

std::vector<int> outage_uavs(int num_lost, int num_uavs) {
  if (num_lost < 0 || num_lost > num_uavs)
    throw std::invalid_argument("outage_uavs: " + std::to_string(num_lost) + " of " + std::to_string(num_uavs));
  std::vector<int> uavs;
  for (int i = 0; i < num_lost; ++i) uavs.push_back(i * num_uavs / num_lost);
  return uavs;
}

std::vector<experiment::TrialRecord> detail::run_rows(const experiment::ExperimentSettings& s,
                                                      const CoevaluationSettings& c, const std::vector<CoevalRow>& rows,
                                                      const std::string& sweep, int point, int trial,
                                                      double beacon_noise_m) {
  const placement::ChannelModel model(s.placement.scenario);  // the Swarms keep a pointer to it
  std::vector<CoevalRow> rows_done;
  std::vector<experiment::TrialRecord> records;
  const CoevalTrial t{s,
                      c,
                      sweep,
                      point,
                      trial,
                      beacon_noise_m,
                      experiment::trial_start_positions_m(s, trial),
                      experiment::trial_seed(s, sweep, point, trial),
                      model,
                      rows_done,
                      records};
  for (const CoevalRow& row : rows) {
    experiment::TrialRecord r = estimator_entry(row.estimator).run(row, placement::planner_entry(row.planner), t);
    rows_done.push_back(row);
    records.push_back(std::move(r));
  }
  return records;
}

std::vector<experiment::TrialRecord> run_beacon_noise_trial(const experiment::ExperimentSettings& s,
                                                            const CoevaluationSettings& c, int point, int trial) {
  const experiment::SweepPoints* sweep = s.sweep(kSweepBeaconNoise);
  if (!sweep) throw std::invalid_argument("run_beacon_noise_trial: the settings have no beacon_noise_m sweep");
  return detail::run_rows(s, c, c.algorithms, kSweepBeaconNoise, point, trial,
                          sweep->values.at(static_cast<std::size_t>(point)));
}

std::vector<experiment::TrialRecord> run_beacon_noise_trial(const experiment::ExperimentSettings& s, int point,
                                                            int trial) {
  return run_beacon_noise_trial(s, load_coevaluation_settings(s), point, trial);
}

std::vector<experiment::TrialRecord> run_outage_trial(const experiment::ExperimentSettings& s,
                                                      const CoevaluationSettings& c, int point, int trial) {
  const experiment::SweepPoints* sweep = s.sweep(kSweepBeaconOutage);
  if (!sweep) throw std::invalid_argument("run_outage_trial: the settings have no beacon_outage sweep");
  const int num_lost = static_cast<int>(sweep->values.at(static_cast<std::size_t>(point)));
  std::vector<experiment::TrialRecord> records;
  for (const CoevalRow& row : c.outage_algorithms) {
    fusion::ClosedLoopConfig config =
        coevaluation_closed_loop_config(c, s.placement.scenario, row.estimator, c.outage_beacon_noise_m);
    config.filter.degraded_after_epochs = c.outage_degraded_after_epochs;
    for (const int m : outage_uavs(num_lost, s.placement.scenario.num_uavs)) {
      config.outages.push_back({m, {c.outage_first_epoch, c.outage_epochs}});
    }
    records.push_back(detail::closed_loop_record(s, kSweepBeaconOutage, point, trial, row.name, config));
  }
  return records;
}

std::vector<experiment::TrialRecord> run_outage_trial(const experiment::ExperimentSettings& s, int point, int trial) {
  return run_outage_trial(s, load_coevaluation_settings(s), point, trial);
}

experiment::ExperimentExtension::TrialFn detail::bound(const experiment::ExperimentSettings& s, TrialOf run) {
  auto c = std::make_shared<const CoevaluationSettings>(load_coevaluation_settings(s));
  return [&s, c, run](int point, int trial) { return run(s, *c, point, trial); };
}

experiment::ExperimentExtension detail::make_extension(
    const std::string& sweep, std::vector<double> (*values)(const CoevaluationSettings&), TrialOf trial,
    decltype(experiment::ExperimentExtension::figures) figures,
    decltype(experiment::ExperimentExtension::report_section) section) {
  register_coevaluation_planners();
  experiment::ExperimentExtension e;
  e.sweep = sweep;
  e.config_keys = coevaluation_config_keys();
  e.metrics = coevaluation_metrics();
  e.load_values = [values](const experiment::ExperimentSettings& s) { return values(load_coevaluation_settings(s)); };
  e.bind = [trial](const experiment::ExperimentSettings& s) { return bound(s, trial); };
  e.figures = std::move(figures);
  e.report_section = std::move(section);
  return e;
}

experiment::ExperimentExtension beacon_noise_extension() {
  return detail::make_extension(
      kSweepBeaconNoise, [](const CoevaluationSettings& c) { return c.beacon_noise_values_m; }, &run_beacon_noise_trial,
      write_beacon_noise_figures, beacon_noise_report_section);
}

experiment::ExperimentExtension beacon_outage_extension() {
  return detail::make_extension(
      kSweepBeaconOutage,
      [](const CoevaluationSettings& c) { return std::vector<double>(c.outage_values.begin(), c.outage_values.end()); },
      &run_outage_trial, write_outage_figures, outage_report_section);
}

}  // namespace losmimo::coevaluation
