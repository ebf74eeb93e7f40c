// The co-evaluation trials (coevaluation.h): one record per algorithm from a shared start and
// seed, with the localization statistics as extra columns.
#include "losmimo/coevaluation/coevaluation.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "losmimo/common/seed.h"
#include "losmimo/fusion/centralized.h"
#include "losmimo/coevaluation/report.h"
#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/fusion/estimation_step.h"
#include "losmimo/localization/position/estimation_errors.h"
#include "losmimo/localization/position/initial_belief.h"
#include "losmimo/placement/metrics.h"

namespace losmimo::coevaluation {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Tags of ura_ekf's per-UAV seed streams (sensors, filter), derived from the trial seed with
// common::derive_seed: each UAV's draws depend on (trial seed, tag, UAV) only.
constexpr std::uint64_t kUraSimulatorStream = 0x55524153;  // "URAS"
constexpr std::uint64_t kUraFilterStream = 0x55524146;     // "URAF"
// Straight-line flight to the centralized solution, sampled to find the ICN milestones.
constexpr int kCentralizedFlightSteps = 200;

localization::SimulatorConfig simulator_config(const CoevaluationSettings& c, const placement::Scenario& scenario,
                                               double beacon_noise_m) {
  localization::SimulatorConfig sim;
  sim.sigma_range_m = c.closed_loop.simulator.sigma_range_m;
  sim.sigma_angle_rad = beacon_noise_m / scenario.range_m();
  sim.dr_sigma_floor_m = c.closed_loop.simulator.dr_sigma_floor_m;
  sim.dr_sigma_fraction = c.closed_loop.simulator.dr_sigma_fraction;
  return sim;
}

// The filter assumes the true noise, floored: a zero-noise beacon would make the EKF's
// innovation covariance singular and the refinement's whitening infinite.
localization::FilterConfig filter_config(const CoevaluationSettings& c, const localization::SimulatorConfig& sim) {
  localization::FilterConfig f;
  f.noise.sigma_range_m = std::max(sim.sigma_range_m, f.min_sigma_range_m);
  f.noise.sigma_angle_rad = std::max(sim.sigma_angle_rad, f.min_sigma_angle_rad);
  f.noise.dr_sigma_floor_m = sim.dr_sigma_floor_m;
  f.noise.dr_sigma_fraction = sim.dr_sigma_fraction;
  f.num_particles = c.closed_loop.filter.num_particles;
  return f;
}

// Sets the metrics (coevaluation_metrics()) that a record's algorithm has no value for: NaN.
void not_applicable(experiment::TrialRecord& r, std::initializer_list<experiment::MetricId> metrics) {
  for (const experiment::MetricId m : metrics) r.extension.set(m, kNaN);
}

// The metrics of a run that placed from the Gaussian model's positions, sigma_loc_m per axis.
void set_gaussian_metrics(experiment::TrialRecord& r, double sigma_loc_m) {
  r.extension.set(kLocRmse, std::sqrt(3.0) * sigma_loc_m);
  r.extension.set(kLocLateralRmse, std::sqrt(2.0) * sigma_loc_m);
  not_applicable(r, {kNees, kBfFallbackFraction, kBeaconLateralRmse});
}

double fallback_fraction(const fusion::ClosedLoopStats& s, int iterations) {
  int bf = 0;
  for (const int n : s.bf_fallback_iterations) bf += n;
  const double uav_iterations = static_cast<double>(s.bf_fallback_iterations.size()) * iterations;
  return uav_iterations > 0.0 ? bf / uav_iterations : 0.0;
}

experiment::TrialRecord closed_loop_record(const experiment::ExperimentSettings& s, const std::string& sweep, int point,
                                           int trial, CoevalAlgorithm a, const fusion::ClosedLoopConfig& config) {
  const fusion::ClosedLoopRun r = fusion::run_closed_loop(s.placement, experiment::trial_start_positions_m(s, trial),
                                                          config, experiment::trial_seed(s, sweep, point, trial));
  experiment::TrialRecord rec = experiment::make_record(s, sweep, point, trial, to_string(a), r.run);
  rec.extension.set(kLocRmse, r.stats.rmse_m);
  rec.extension.set(kLocLateralRmse, r.stats.lateral_rmse_m);
  rec.extension.set(kNees, r.stats.average_nees);
  rec.extension.set(kBfFallbackFraction, fallback_fraction(r.stats, r.run.iterations));
  rec.extension.set(kBeaconLateralRmse, r.stats.num_beacons > 0 ? r.stats.beacon_only_lateral_rmse_m : kNaN);
  not_applicable(rec, {kPairedTravelDiff, kPairedIterationsDiff});
  return rec;
}

// URA's position source: every UAV's own sensors and EKF through the closed loop's estimation
// step (fusion/estimation_step.h), one epoch per estimate (the URA planner asks once per UAV at
// start and once per UAV per iteration, as the closed loop localizes).
class EkfPositionSource {
 public:
  EkfPositionSource(const placement::Scenario& scenario, const localization::SimulatorConfig& sim,
                    const localization::FilterConfig& filter, int num_uavs, std::uint64_t seed) {
    const fusion::EstimatorConfig estimator{localization::FilterKind::kEkf, filter, false, {}};
    const localization::Belief prior = localization::start_cube_prior(scenario, filter);
    for (int m = 0; m < num_uavs; ++m) {
      const auto uav = static_cast<std::uint64_t>(m);
      uavs_.push_back(
          {localization::SensorSimulator(sim, common::derive_seed(seed, {kUraSimulatorStream, uav})),
           fusion::UavEstimator(scenario, estimator, prior, common::derive_seed(seed, {kUraFilterStream, uav})),
           Eigen::Vector3d::Zero(), 0});
    }
  }

  Eigen::Vector3d estimate(int m, const Eigen::Vector3d& q_m) {
    Uav& uav = uavs_.at(static_cast<std::size_t>(m));
    fusion::EpochMeasurements in;
    const bool first = !uav.estimator.started();
    if (!first) {
      ++uav.epoch;
      in.displacement_m = uav.simulator.measure_displacement(q_m - uav.last_q_m);
    }
    in.beacon = uav.simulator.measure_beacon(q_m, uav.epoch);
    const fusion::EpochEstimate est = first ? uav.estimator.start(std::move(in)) : uav.estimator.step(std::move(in));
    uav.last_q_m = q_m;
    errors_.add(est.belief, q_m);
    if (est.beacon_fix_m) beacon_only_errors_.add(*est.beacon_fix_m, q_m);
    return est.belief.mean_m;
  }

  // The statistics of the estimates given so far (coevaluation_metrics()).
  void set_metrics(experiment::TrialRecord& r) const {
    r.extension.set(kLocRmse, errors_.rmse_m());
    r.extension.set(kLocLateralRmse, errors_.lateral_rmse_m());
    r.extension.set(kNees, errors_.average_nees());
    r.extension.set(kBeaconLateralRmse, beacon_only_errors_.lateral_rmse_m());
    not_applicable(r, {kBfFallbackFraction, kPairedTravelDiff, kPairedIterationsDiff});
  }

 private:
  struct Uav {
    localization::SensorSimulator simulator;
    fusion::UavEstimator estimator;
    Eigen::Vector3d last_q_m;
    int epoch;
  };
  std::vector<Uav> uavs_;
  localization::ErrorAccumulator errors_, beacon_only_errors_;
};

placement::RunResult centralized_run(const placement::Scenario& scenario, const Eigen::Matrix3Xd& start_m,
                                     const fusion::CentralizedResult& c) {
  placement::RunResult r;
  r.planner = "centralized";
  r.status = c.status == fusion::CentralizedStatus::kFeasible ? placement::RunStatus::kConverged
                                                              : placement::RunStatus::kIterationCap;
  r.iterations = 0;
  r.start_m = start_m;
  r.final_m = c.positions_m;
  r.placement_dist_m = (c.positions_m - start_m).colwise().norm().transpose();
  r.probe_dist_m = Eigen::VectorXd::Zero(start_m.cols());
  const double mean_m = r.placement_dist_m.mean();
  const placement::ChannelModel model(scenario);
  for (int step = 0; step <= kCentralizedFlightSteps; ++step) {
    const double t = static_cast<double>(step) / kCentralizedFlightSteps;
    const double icn = placement::inverse_condition_number(model.matrix(start_m + t * (c.positions_m - start_m)));
    for (auto [milestone, threshold] : {std::pair{&r.icn050, 0.5}, std::pair{&r.icn095, 0.95}}) {
      if (!milestone->reached && icn >= threshold) *milestone = {true, 0, t * mean_m};
    }
  }
  return r;
}

// gd_ekf's record of this trial and point: the one already made, else from its closed loop,
// run for gd_gauss_matched alone.
experiment::TrialRecord gd_ekf_record(const std::vector<experiment::TrialRecord>& records,
                                      const std::function<experiment::TrialRecord()>& run_gd_ekf) {
  const std::string gd_ekf = to_string(CoevalAlgorithm::kGdEkf);
  for (const experiment::TrialRecord& r : records) {
    if (r.algorithm == gd_ekf) return r;
  }
  return run_gd_ekf();
}

}  // namespace

class CentralizedCache {
 public:
  // The solution for `key`, solving (outside the lock) when absent. The solve is deterministic,
  // so a duplicate solve by a second thread changes nothing.
  std::shared_ptr<const fusion::CentralizedResult> get(const std::string& key,
                                                       const std::function<fusion::CentralizedResult()>& solve) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      const auto it = results_.find(key);
      if (it != results_.end()) return it->second;
    }
    auto result = std::make_shared<const fusion::CentralizedResult>(solve());
    const std::lock_guard<std::mutex> lock(mutex_);
    return results_.emplace(key, std::move(result)).first->second;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const fusion::CentralizedResult>> results_;
};

fusion::ClosedLoopConfig coevaluation_closed_loop_config(const CoevaluationSettings& c,
                                                         const placement::Scenario& scenario, CoevalAlgorithm a,
                                                         double beacon_noise_m) {
  if (a != CoevalAlgorithm::kGdEkf && a != CoevalAlgorithm::kGdEkfNoFallback && a != CoevalAlgorithm::kGdPf &&
      a != CoevalAlgorithm::kGdEkfCeres) {
    throw std::invalid_argument("coevaluation_closed_loop_config: " + to_string(a) + " is not a closed loop");
  }
  fusion::ClosedLoopConfig config;
  config.simulator = simulator_config(c, scenario, beacon_noise_m);
  config.filter = filter_config(c, config.simulator);
  config.filter_kind =
      a == CoevalAlgorithm::kGdPf ? localization::FilterKind::kParticle : localization::FilterKind::kEkf;
  config.refine = a == CoevalAlgorithm::kGdEkfCeres;
  config.refinement = fusion::refinement_config_from(config.filter.noise, scenario.noise_variance());
  config.refinement.window_epochs = c.closed_loop.refinement.window_epochs;
  config.refinement.use_csi = c.closed_loop.refinement.use_csi;
  config.fallback_to_bf = a != CoevalAlgorithm::kGdEkfNoFallback;
  return config;
}

std::vector<int> outage_uavs(int num_lost, int num_uavs) {
  if (num_lost < 0 || num_lost > num_uavs)
    throw std::invalid_argument("outage_uavs: " + std::to_string(num_lost) + " of " + std::to_string(num_uavs));
  std::vector<int> uavs;
  for (int i = 0; i < num_lost; ++i) uavs.push_back(i * num_uavs / num_lost);
  return uavs;
}

namespace {

// ura_ekf and cap_ekf: the planner's believed positions are the EKF's (the same per-UAV source
// for both); record(run) makes the run's record, whose localization metrics the source sets.
template <typename Record>
void run_on_ekf_positions(const experiment::ExperimentSettings& s, const CoevaluationSettings& c,
                          const placement::PlacementSettings& p, CoevalAlgorithm a, double v,
                          const placement::ChannelModel& model, const Eigen::Matrix3Xd& start, std::uint64_t seed,
                          const Record& record) {
  const placement::Scenario& scenario = s.placement.scenario;
  const localization::SimulatorConfig sim = simulator_config(c, scenario, v);
  EkfPositionSource source(scenario, sim, filter_config(c, sim), scenario.num_uavs, seed);
  placement::Swarm swarm(model, start, p.errors, seed);
  swarm.set_position_estimator([&source](int m, const Eigen::Vector3d& q) { return source.estimate(m, q); });
  const experiment::Algorithm planned =
      a == CoevalAlgorithm::kCapEkf ? experiment::Algorithm::kCap : experiment::ura_algorithm_of(c.ura_variant);
  const std::unique_ptr<placement::Planner> planner = experiment::make_planner(p, planned);
  const placement::RunResult run =
      placement::run_placement(*planner, swarm, experiment::run_options_of(p, planned, s.placement.run));
  source.set_metrics(record(run));  // after the run: the source's statistics are the run's
}

// centralized: the Ceres solution of the trial's start (shared through `cache`, when given, by
// every sweep point of the trial), flown as one move.
placement::RunResult centralized_trial_run(const experiment::ExperimentSettings& s, int trial,
                                           const Eigen::Matrix3Xd& start, CentralizedCache* cache) {
  const placement::Scenario& scenario = s.placement.scenario;
  fusion::CentralizedConfig cc;
  cc.target_icn = s.placement.run.target_icn;
  const auto solve = [&] { return fusion::solve_centralized(scenario, start, cc); };
  const std::string key =
      placement::to_ini(s.placement) + "#start " + std::to_string(experiment::trial_start_seed(s, trial));
  const std::shared_ptr<const fusion::CentralizedResult> solution =
      cache ? cache->get(key, solve) : std::make_shared<const fusion::CentralizedResult>(solve());
  return centralized_run(scenario, start, *solution);
}

}  // namespace

std::vector<experiment::TrialRecord> run_beacon_noise_trial(const experiment::ExperimentSettings& s, int point,
                                                            int trial, CentralizedCache* cache) {
  const experiment::SweepPoints* sweep = s.sweep(kSweepBeaconNoise);
  if (!sweep) throw std::invalid_argument("run_beacon_noise_trial: the settings have no beacon_noise_m sweep");
  const CoevaluationSettings c = load_coevaluation_settings(s);
  const double v = sweep->values.at(static_cast<std::size_t>(point));
  const placement::Scenario& scenario = s.placement.scenario;
  const Eigen::Matrix3Xd start = experiment::trial_start_positions_m(s, trial);
  const std::uint64_t seed = experiment::trial_seed(s, kSweepBeaconNoise, point, trial);
  const placement::ChannelModel model(scenario);  // the Swarms keep a pointer to it

  std::vector<experiment::TrialRecord> records;
  for (const CoevalAlgorithm a : c.algorithms) {
    // The record of `run`; the caller sets its metrics.
    const auto record = [&](const placement::RunResult& run) -> experiment::TrialRecord& {
      records.push_back(experiment::make_record(s, kSweepBeaconNoise, point, trial, to_string(a), run));
      return records.back();
    };
    // Every algorithm but gd_gauss places from true positions or from its own estimates.
    placement::PlacementSettings p = s.placement;
    p.errors.sigma_loc_m = 0.0;
    switch (a) {
      case CoevalAlgorithm::kGdGauss: {
        // The experiment's GD (one engine): its planner, stop rule and Gaussian localization.
        p.errors.sigma_loc_m = v;
        experiment::TrialRecord& r =
            record(experiment::run_algorithm(s, p, experiment::Algorithm::kGd, trial, start, seed, s.placement.run));
        set_gaussian_metrics(r, v);
        not_applicable(r, {kPairedTravelDiff, kPairedIterationsDiff});
        break;
      }
      case CoevalAlgorithm::kGdGaussMatched: {
        const experiment::TrialRecord ekf = gd_ekf_record(records, [&] {
          return closed_loop_record(s, kSweepBeaconNoise, point, trial, CoevalAlgorithm::kGdEkf,
                                    coevaluation_closed_loop_config(c, scenario, CoevalAlgorithm::kGdEkf, v));
        });
        // The same lateral RMSE as gd_ekf's.
        p.errors.sigma_loc_m = ekf.extension.at(kLocLateralRmse) / std::sqrt(2.0);
        experiment::TrialRecord& own =
            record(experiment::run_algorithm(s, p, experiment::Algorithm::kGd, trial, start, seed, s.placement.run));
        set_gaussian_metrics(own, p.errors.sigma_loc_m);
        own.extension.set(kPairedTravelDiff, ekf.dist_to_icn095_m - own.dist_to_icn095_m);
        own.extension.set(kPairedIterationsDiff, static_cast<double>(ekf.iterations - own.iterations));
        break;
      }
      case CoevalAlgorithm::kBf: {
        not_applicable(
            record(experiment::run_algorithm(s, p, experiment::Algorithm::kBf, trial, start, seed, s.placement.run)),
            {kLocRmse, kLocLateralRmse, kNees, kBfFallbackFraction, kBeaconLateralRmse, kPairedTravelDiff,
             kPairedIterationsDiff});
        break;
      }
      case CoevalAlgorithm::kUraEkf:
      case CoevalAlgorithm::kCapEkf: {
        run_on_ekf_positions(s, c, p, a, v, model, start, seed, record);
        break;
      }
      case CoevalAlgorithm::kCentralized: {
        not_applicable(record(centralized_trial_run(s, trial, start, cache)),
                       {kLocRmse, kLocLateralRmse, kNees, kBfFallbackFraction, kBeaconLateralRmse, kPairedTravelDiff,
                        kPairedIterationsDiff});
        break;
      }
      default:
        records.push_back(closed_loop_record(s, kSweepBeaconNoise, point, trial, a,
                                             coevaluation_closed_loop_config(c, scenario, a, v)));
    }
  }
  return records;
}

std::vector<experiment::TrialRecord> run_outage_trial(const experiment::ExperimentSettings& s, int point, int trial) {
  const experiment::SweepPoints* sweep = s.sweep(kSweepBeaconOutage);
  if (!sweep) throw std::invalid_argument("run_outage_trial: the settings have no beacon_outage sweep");
  const CoevaluationSettings c = load_coevaluation_settings(s);
  const int num_lost = static_cast<int>(sweep->values.at(static_cast<std::size_t>(point)));
  std::vector<experiment::TrialRecord> records;
  for (const CoevalAlgorithm a : c.outage_algorithms) {
    fusion::ClosedLoopConfig config =
        coevaluation_closed_loop_config(c, s.placement.scenario, a, c.outage_beacon_noise_m);
    config.filter.degraded_after_epochs = c.outage_degraded_after_epochs;
    for (const int m : outage_uavs(num_lost, s.placement.scenario.num_uavs)) {
      config.outages.push_back({m, {c.outage_first_epoch, c.outage_epochs}});
    }
    records.push_back(closed_loop_record(s, kSweepBeaconOutage, point, trial, a, config));
  }
  return records;
}

experiment::ExperimentExtension beacon_noise_extension() {
  auto cache = std::make_shared<CentralizedCache>();
  experiment::ExperimentExtension e;
  e.sweep = kSweepBeaconNoise;
  e.config_keys = coevaluation_config_keys();
  e.metrics = coevaluation_metrics();
  e.load_values = [](const experiment::ExperimentSettings& s) {
    return load_coevaluation_settings(s).beacon_noise_values_m;
  };
  e.run = [cache](const experiment::ExperimentSettings& s, int point, int trial) {
    return run_beacon_noise_trial(s, point, trial, cache.get());
  };
  e.figures = write_beacon_noise_figures;
  e.report_section = beacon_noise_report_section;
  return e;
}

experiment::ExperimentExtension beacon_outage_extension() {
  experiment::ExperimentExtension e;
  e.sweep = kSweepBeaconOutage;
  e.config_keys = coevaluation_config_keys();
  e.metrics = coevaluation_metrics();
  e.load_values = [](const experiment::ExperimentSettings& s) {
    const std::vector<int> k = load_coevaluation_settings(s).outage_values;
    return std::vector<double>(k.begin(), k.end());
  };
  e.run = run_outage_trial;
  e.figures = write_outage_figures;
  e.report_section = outage_report_section;
  return e;
}

}  // namespace losmimo::coevaluation
