// The builtin estimators of the co-evaluation (estimator_registry.h): truth, the Gaussian model,
// the matched Gaussian and the filter family (ekf, pf, ekf_nofallback, ekf_ceres).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/estimator_registry.h"
#include "losmimo/placement/common/seed.h"
#include "losmimo/fusion/estimation_step.h"
#include "losmimo/localization/position/estimation_errors.h"
#include "losmimo/localization/position/initial_belief.h"
#include "losmimo/placement/swarm_shape.h"
#include "trial_parts.h"

namespace losmimo::coevaluation {

namespace {

using detail::kNaN;
using detail::not_applicable;

// Tags of the per-UAV seed streams (sensors, filter) of a planner on filter beliefs, derived from
// the trial seed with common::derive_seed: each UAV's draws depend on (trial seed, tag, UAV) only.
constexpr std::uint64_t kSourceSimulatorStream = 0x55524153;  // "URAS"
constexpr std::uint64_t kSourceFilterStream = 0x55524146;     // "URAF"

// The Gaussian model's two parts, 1-sigma per axis [m]: independent per UAV and estimate
// (sigma_loc_m) and common to the swarm for the run (sigma_loc_common_m).
struct GaussianSigmas {
  double independent_m = 0.0;
  double common_m = 0.0;
};

// The metrics of a run that placed from the Gaussian model's positions: their expected values.
// The common part adds to the common offset only (it has no shape), the independent part to both.
// Without a common part every value is the independent one's, to the bit (std::hypot(a, 0) = |a|).
void set_gaussian_metrics(experiment::TrialRecord& r, GaussianSigmas g, int num_uavs) {
  const double sigma = std::hypot(g.independent_m, g.common_m);
  r.extension.set(kLocRmse, std::sqrt(3.0) * sigma);
  r.extension.set(kLocLateralRmse, std::sqrt(2.0) * sigma);
  const placement::ExpectedSwarmSplit split =
      placement::expected_split_of_independent_errors(num_uavs, g.independent_m);
  r.extension.set(kCommonLateral, std::hypot(split.common_lateral_rms_m, std::sqrt(2.0) * g.common_m));
  r.extension.set(kShapeLateralRmse, split.shape_lateral_rmse_m);
  not_applicable(r, {kShapeNees, kNees, kBfFallbackFraction, kBeaconLateralRmse});
}

std::optional<std::string> needs_positions(const placement::PlannerEntry& planner, const std::string& estimator) {
  if (planner.direct() || !planner.uses_positions) {
    return planner.name + " does not place from position estimates: " + estimator +
           " cannot reach it (pair it with truth)";
  }
  return std::nullopt;
}

std::optional<std::string> needs_gd(const placement::PlannerEntry& planner, const std::string& estimator,
                                    const std::string& why) {
  if (planner.name != "gd") return estimator + " " + why + ": it pairs with gd only";
  return std::nullopt;
}

// The planner's position source: every UAV's own sensors and filter through the closed loop's
// estimation step (fusion/estimation_step.h), one epoch per estimate (a planner asks once per UAV
// at start and once per UAV per iteration, as the closed loop localizes).
class FilterPositionSource {
 public:
  FilterPositionSource(const placement::Scenario& scenario, const localization::SimulatorConfig& sim,
                       const fusion::EstimatorConfig& estimator, int num_uavs, std::uint64_t seed) {
    const localization::Belief prior = localization::start_cube_prior(scenario, estimator.filter);
    for (int m = 0; m < num_uavs; ++m) {
      const auto uav = static_cast<std::uint64_t>(m);
      uavs_.push_back(
          {localization::SensorSimulator(sim, common::derive_seed(seed, {kSourceSimulatorStream, uav})),
           fusion::UavEstimator(scenario, estimator, prior, common::derive_seed(seed, {kSourceFilterStream, uav})),
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
    // The swarm's epoch e: every UAV's e-th estimate (the planner asks each UAV once per epoch).
    const auto e = static_cast<std::size_t>(uav.epoch);
    if (epochs_truth_.size() <= e) {
      epochs_truth_.resize(e + 1, Eigen::Matrix3Xd::Constant(3, static_cast<Eigen::Index>(uavs_.size()), kNaN));
      epochs_mean_.resize(e + 1, Eigen::Matrix3Xd::Constant(3, static_cast<Eigen::Index>(uavs_.size()), kNaN));
    }
    epochs_truth_[e].col(m) = q_m;
    epochs_mean_[e].col(m) = est.belief.mean_m;
    if (epochs_cov_.size() <= e) epochs_cov_.resize(e + 1, std::vector<Eigen::Matrix2d>(uavs_.size()));
    epochs_cov_[e][static_cast<std::size_t>(m)] = est.belief.cov_m2.bottomRightCorner<2, 2>();
    if (est.beacon_fix_m) beacon_only_errors_.add(*est.beacon_fix_m, q_m);
    return est.belief.mean_m;
  }

  // The statistics of the estimates given so far (coevaluation_metrics()).
  void set_metrics(experiment::TrialRecord& r) const {
    r.extension.set(kLocRmse, errors_.rmse_m());
    r.extension.set(kLocLateralRmse, errors_.lateral_rmse_m());
    placement::SwarmShapeAccumulator shape;  // the epochs every UAV was estimated in
    for (std::size_t e = 0; e < epochs_truth_.size(); ++e) {
      if (epochs_truth_[e].allFinite() && epochs_mean_[e].allFinite())
        shape.add(epochs_truth_[e], epochs_mean_[e], epochs_cov_[e]);
    }
    r.extension.set(kCommonLateral, shape.common_lateral_rms_m());
    r.extension.set(kShapeLateralRmse, shape.shape_lateral_rmse_m());
    r.extension.set(kShapeNees, shape.shape_nees_per_dof());
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
  std::vector<Eigen::Matrix3Xd> epochs_truth_, epochs_mean_;  // [epoch]: 3 x Nr, NaN where not estimated
  std::vector<std::vector<Eigen::Matrix2d>> epochs_cov_;      // [epoch][uav]: the belief's lateral covariance
};

// The placement settings every row but gauss's starts from: no Gaussian localization error.
placement::PlacementSettings exact_positions(const CoevalTrial& t) {
  placement::PlacementSettings p = t.settings.placement;
  p.errors.clear_localization();
  return p;
}

// The record of `planner` run by the experiment (its stop rule, the trial's start and seed)
// under placement settings p.
experiment::TrialRecord run_planner(const CoevalRow& row, const placement::PlannerEntry& planner, const CoevalTrial& t,
                                    const placement::PlacementSettings& p) {
  return t.record(row, experiment::run_algorithm(t.settings, p, experiment::Algorithm(planner.name), t.trial, t.start_m,
                                                 t.seed, t.settings.placement.run));
}

EstimatorEntry truth() {
  EstimatorEntry e;
  e.name = "truth";
  e.summary = "the true positions (sigma_loc 0); bf, random and centralized pair with it alone";
  e.refuses = [](const placement::PlannerEntry&) { return std::nullopt; };
  e.run = [](const CoevalRow& row, const placement::PlannerEntry& planner, const CoevalTrial& t) {
    experiment::TrialRecord r = run_planner(row, planner, t, exact_positions(t));
    not_applicable(r, {kLocRmse, kLocLateralRmse, kCommonLateral, kShapeLateralRmse, kShapeNees, kNees,
                       kBfFallbackFraction, kBeaconLateralRmse, kPairedTravelDiff, kPairedIterationsDiff});
    return r;
  };
  return e;
}

EstimatorEntry gauss() {
  EstimatorEntry e;
  e.name = "gauss";
  e.summary =
      "the paper's Gaussian localization error, sigma_loc_m = the point's beacon noise (plus [errors] "
      "sigma_loc_common_m)";
  e.keys = {"errors.sigma_loc_common_m"};
  e.refuses = [](const placement::PlannerEntry& planner) { return needs_positions(planner, "gauss"); };
  e.run = [](const CoevalRow& row, const placement::PlannerEntry& planner, const CoevalTrial& t) {
    placement::PlacementSettings p = t.settings.placement;
    p.errors.sigma_loc_m = t.beacon_noise_m;
    experiment::TrialRecord r = run_planner(row, planner, t, p);
    set_gaussian_metrics(r, {p.errors.axis_sigma_loc_m(), p.errors.axis_sigma_loc_common_m()},
                         static_cast<int>(t.start_m.cols()));
    not_applicable(r, {kPairedTravelDiff, kPairedIterationsDiff});
    return r;
  };
  return e;
}

// The Gaussian model's sigmas per axis that match an ekf record, for a swarm of num_uavs.
using MatchSigmas = GaussianSigmas (*)(const experiment::TrialRecord& ekf, int num_uavs);

// The Gaussian model at the sigmas that `sigma_of_ekf` takes from the same planner's ekf record
// (the one already run in this trial, else its own run for this row alone), with the paired
// travel and iteration differences against that record. [errors] sigma_loc_common_m does not
// apply: the match sets both parts.
experiment::TrialRecord run_matched_gaussian(const CoevalRow& row, const placement::PlannerEntry& planner,
                                             const CoevalTrial& t, MatchSigmas sigma_of_ekf) {
  const CoevalRow ekf_row{planner.name + "+ekf", planner.name, "ekf"};
  std::optional<experiment::TrialRecord> ekf;
  for (std::size_t i = 0; i < t.rows_done.size(); ++i) {
    if (t.rows_done[i].same_pair(ekf_row)) ekf = t.records_done[i];
  }
  if (!ekf) ekf = estimator_entry("ekf").run(ekf_row, planner, t);
  const int num_uavs = static_cast<int>(t.start_m.cols());
  placement::PlacementSettings p = t.settings.placement;
  const GaussianSigmas g = sigma_of_ekf(*ekf, num_uavs);
  // Per axis whatever [errors] sigma_convention says: the match is per axis.
  p.errors.sigma_convention = placement::SigmaConvention::kPerAxis;
  p.errors.sigma_loc_m = g.independent_m;
  p.errors.sigma_loc_common_m = g.common_m;
  experiment::TrialRecord own = run_planner(row, planner, t, p);
  set_gaussian_metrics(own, g, num_uavs);
  own.extension.set(kPairedTravelDiff, ekf->dist_to_icn095_m - own.dist_to_icn095_m);
  own.extension.set(kPairedIterationsDiff, static_cast<double>(ekf->iterations - own.iterations));
  return own;
}

EstimatorEntry matched_gaussian(const std::string& name, const std::string& summary, MatchSigmas sigma_of_ekf) {
  EstimatorEntry e;
  e.name = name;
  e.summary = summary;
  e.refuses = [name](const placement::PlannerEntry& planner) {
    if (auto why = needs_positions(planner, name)) return why;
    return estimator_entry("ekf").refuses(planner);
  };
  e.run = [sigma_of_ekf](const CoevalRow& row, const placement::PlannerEntry& planner, const CoevalTrial& t) {
    return run_matched_gaussian(row, planner, t, sigma_of_ekf);
  };
  return e;
}

EstimatorEntry gauss_matched() {
  return matched_gaussian("gauss_matched",
                          "the Gaussian at the lateral RMSE the same planner's ekf row measured (same trial and point)",
                          [](const experiment::TrialRecord& ekf, int) {
                            return GaussianSigmas{ekf.extension.at(kLocLateralRmse) / std::sqrt(2.0), 0.0};
                          });
}

// The independent sigma whose expected shape RMSE, sigma sqrt((2N - 3) / N), is the ekf's.
double shape_matched_sigma(const experiment::TrialRecord& ekf, int num_uavs) {
  const double unit = placement::expected_split_of_independent_errors(num_uavs, 1.0).shape_lateral_rmse_m;
  return unit > 0.0 ? ekf.extension.at(kShapeLateralRmse) / unit : 0.0;
}

EstimatorEntry gauss_shape_matched() {
  return matched_gaussian(
      "gauss_shape_matched",
      "the Gaussian at the shape RMSE (common offset and rotation removed) the same planner's ekf row measured",
      [](const experiment::TrialRecord& ekf, int num_uavs) {
        return GaussianSigmas{shape_matched_sigma(ekf, num_uavs), 0.0};
      });
}

// Both parts matched: the independent one at the ekf's shape RMSE, the common one so that the
// expected common lateral offset, 2 sigma^2 / N + 2 sigma_common^2, is the ekf's squared.
EstimatorEntry gauss_split_matched() {
  return matched_gaussian(
      "gauss_split_matched",
      "the Gaussian with a common-mode part, both matched: shape RMSE and common lateral offset of the ekf row",
      [](const experiment::TrialRecord& ekf, int num_uavs) {
        const double sigma = shape_matched_sigma(ekf, num_uavs);
        const double common = ekf.extension.at(kCommonLateral);
        const double from_independent = 2.0 * sigma * sigma / num_uavs;
        return GaussianSigmas{sigma, std::sqrt(std::max(0.0, common * common - from_independent) / 2.0)};
      });
}

// The filter family: `kind`, refined or not, with or without gd's BF fallback.
struct FilterRow {
  localization::FilterKind kind;
  bool refine;
  bool fallback;
};

fusion::ClosedLoopConfig filter_closed_loop(const CoevaluationSettings& c, const placement::Scenario& scenario,
                                            double v, FilterRow f) {
  fusion::ClosedLoopConfig config;
  config.simulator = detail::simulator_config(c, scenario, v);
  config.filter = detail::filter_config(c, config.simulator);
  config.filter_kind = f.kind;
  config.refine = f.refine;
  config.refinement = fusion::refinement_config_from(config.filter.noise, scenario.noise_variance());
  config.refinement.window_epochs = c.closed_loop.refinement.window_epochs;
  config.refinement.use_csi = c.closed_loop.refinement.use_csi;
  config.fallback_to_bf = f.fallback;
  return config;
}

// gd: the closed loop; another iterative planner: that planner on the filters' beliefs.
experiment::TrialRecord run_filter(const CoevalRow& row, const placement::PlannerEntry& planner, const CoevalTrial& t,
                                   FilterRow f) {
  const placement::Scenario& scenario = t.settings.placement.scenario;
  if (planner.name == "gd") {
    return detail::closed_loop_record(t.settings, t.sweep, t.point, t.trial, row.name,
                                      filter_closed_loop(t.coevaluation, scenario, t.beacon_noise_m, f));
  }
  const placement::PlacementSettings p = exact_positions(t);
  const localization::SimulatorConfig sim = detail::simulator_config(t.coevaluation, scenario, t.beacon_noise_m);
  const fusion::EstimatorConfig estimator{f.kind, detail::filter_config(t.coevaluation, sim), false, {}};
  FilterPositionSource source(scenario, sim, estimator, scenario.num_uavs, t.seed);
  placement::Swarm swarm(t.model, t.start_m, p.errors, t.seed);
  swarm.set_position_estimator([&source](int m, const Eigen::Vector3d& q) { return source.estimate(m, q); });
  const experiment::Algorithm a(planner.name);
  const std::unique_ptr<placement::Planner> planned = experiment::make_planner(p, a);
  experiment::TrialRecord r = t.record(
      row, placement::run_placement(*planned, swarm, experiment::run_options_of(p, a, t.settings.placement.run)));
  source.set_metrics(r);  // after the run: the source's statistics are the run's
  return r;
}

EstimatorEntry filter(const std::string& name, const std::string& summary, std::vector<std::string> keys, FilterRow f) {
  EstimatorEntry e;
  e.name = name;
  e.summary = summary;
  e.keys = std::move(keys);
  e.refuses = [name, f](const placement::PlannerEntry& planner) -> std::optional<std::string> {
    if (auto why = needs_positions(planner, name)) return why;
    if (!f.fallback) return needs_gd(planner, name, "switches off the closed loop's BF fallback");
    if (f.refine) return needs_gd(planner, name, "refines with the closed loop's CSI");
    return std::nullopt;
  };
  e.run = [f](const CoevalRow& row, const placement::PlannerEntry& planner, const CoevalTrial& t) {
    return run_filter(row, planner, t, f);
  };
  e.closed_loop = [f](const CoevaluationSettings& c, const placement::Scenario& scenario, double v) {
    return filter_closed_loop(c, scenario, v, f);
  };
  return e;
}

}  // namespace

std::vector<EstimatorEntry> builtin_estimators() {
  using localization::FilterKind;
  return {truth(),
          gauss(),
          gauss_matched(),
          gauss_shape_matched(),
          gauss_split_matched(),
          filter("ekf", "every UAV's EKF on beacon + dead reckoning (gd: the closed loop, BF fallback on)", {},
                 {FilterKind::kEkf, false, true}),
          filter("ekf_nofallback", "gd's closed loop with the EKF and the BF fallback off", {},
                 {FilterKind::kEkf, false, false}),
          filter("pf", "every UAV's particle filter on beacon + dead reckoning (gd: the closed loop)",
                 {"closed_loop.num_particles"}, {FilterKind::kParticle, false, true}),
          filter("ekf_ceres", "gd's closed loop with the EKF and the Ceres CSI refinement",
                 {"closed_loop.window_epochs", "closed_loop.use_csi"}, {FilterKind::kEkf, true, true})};
}

}  // namespace losmimo::coevaluation
