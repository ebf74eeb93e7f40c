#include "losmimo/fusion/estimation_step.h"

#include <limits>
#include <stdexcept>
#include <utility>

#include "losmimo/localization/position/beacon_model.h"
#include "losmimo/localization/position/robustness.h"

namespace losmimo::fusion {

UavEstimator::UavEstimator(const placement::Scenario& scenario, const EstimatorConfig& config,
                           const localization::Belief& prior, std::uint64_t filter_seed)
    : config_(config), prior_(prior), filter_seed_(filter_seed), scenario_(scenario) {
  localization::validate(config_.filter);
  if (config_.refine) validate(config_.refinement);
}

UavEstimator::~UavEstimator() = default;
UavEstimator::UavEstimator(UavEstimator&&) noexcept = default;
UavEstimator& UavEstimator::operator=(UavEstimator&&) noexcept = default;

const localization::PositionFilter& UavEstimator::filter() const {
  if (!filter_) throw std::logic_error("UavEstimator::filter before start()");
  return *filter_;
}

EpochEstimate UavEstimator::start(EpochMeasurements measurements) {
  if (filter_) throw std::logic_error("UavEstimator::start called twice");
  EpochEstimate out;
  const localization::InitialBelief initial = localization::initial_belief(measurements.beacon, config_.filter, prior_);
  out.initial_source = initial.source;
  out.rejected_beacon = initial.source == localization::InitialBeliefSource::kPriorImplausibleBeacon;
  if (initial.beacon_fix) out.beacon_fix_m = initial.beacon_fix->mean_m;
  if (!initial.beacon_used()) measurements.beacon.reset();
  measurements.displacement_m.reset();  // nothing to predict from at epoch 0
  if (initial.source == localization::InitialBeliefSource::kPriorHealthProblem)
    out.health_problem = "initial beacon fix " + initial.health_problem;
  filter_ = localization::make_filter(config_.filter_kind, config_.filter, initial.belief, filter_seed_);
  if (config_.refine) refiner_.emplace(scenario_, config_.refinement);
  out.filter_belief = initial.belief;
  finish(measurements, out);
  return out;
}

EpochEstimate UavEstimator::step(EpochMeasurements measurements) {
  if (!filter_) throw std::logic_error("UavEstimator::step before start()");
  EpochEstimate out;
  if (measurements.displacement_m && !measurements.displacement_m->allFinite()) {
    out.rejected_displacement = true;
    measurements.displacement_m.reset();
  }
  // Implausible beacons are dropped here, not only inside the filter: the refinement would take
  // them as residuals and the beacon-only statistics as samples.
  if (measurements.beacon && !localization::is_plausible(config_.filter, *measurements.beacon)) {
    out.rejected_beacon = true;
    measurements.beacon.reset();
  }
  if (measurements.beacon)
    out.beacon_fix_m = localization::beacon_to_position(localization::to_vector(*measurements.beacon));
  // A missing displacement is the filter's documented NaN input (filter.h).
  filter_->step(
      measurements.displacement_m.value_or(Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN())),
      measurements.beacon);
  out.filter_belief = filter_->belief();
  finish(measurements, out);
  return out;
}

void UavEstimator::finish(EpochMeasurements& measurements, EpochEstimate& out) {
  out.belief = out.filter_belief;
  std::vector<CsiMeasurement> csi;
  if (refiner_ && config_.refinement.use_csi) {
    for (CsiMeasurement& row : measurements.csi) {
      if (row.y.allFinite()) {
        csi.push_back(std::move(row));
      } else {
        ++out.rejected_csi;
      }
    }
  }
  if (refiner_) {
    out.csi = csi;
    refiner_->add_epoch({out.filter_belief, measurements.displacement_m, measurements.beacon, std::move(csi)});
    const RefinementResult r = refiner_->refine();
    out.refinement_covariance_fallback = r.covariance_source == CovarianceSource::kDeadReckoning;
    out.belief = r.belief;
  }
  out.displacement_m = measurements.displacement_m;
  out.beacon = measurements.beacon;

  if (out.health_problem) return;  // epoch 0's unhealthy fix is the first problem
  const std::string filter = config_.filter_kind == localization::FilterKind::kEkf ? "EKF" : "PF";
  if (const auto problem = localization::health_problem(out.filter_belief)) {
    out.health_problem = filter + " belief " + *problem;
  } else if (filter_->counters().non_finite_state > 0) {
    out.health_problem = filter + " state became non-finite (covariance reset)";
  } else if (refiner_) {
    if (const auto refined = localization::health_problem(out.belief))
      out.health_problem = "refined belief " + *refined;
  }
}

}  // namespace losmimo::fusion
