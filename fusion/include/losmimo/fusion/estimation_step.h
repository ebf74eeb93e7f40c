#pragma once
// One UAV's estimation, one epoch at a time: the single step that the closed loop, the mission
// replay and the co-evaluation's URA position source all run.
//
// Epoch 0 (start()):
//   1. screen: a beacon failing localization::is_plausible (non-finite, range outside
//      (0, max_beacon_range_m], elevation beyond +-pi/2) is dropped and counted;
//   2. the epoch-0 rule (initial_belief.h): the beacon fix, or the start-cube prior; the beacon
//      counts as consumed only when the filter starts from it;
//   3. the filter starts from that belief (make_filter with the given seed).
// Epoch k > 0 (step()):
//   1. screen: a non-finite dead-reckoning displacement is counted and treated as missing (the
//      filter predicts with d = 0 and missing_displacement_sigma_m; the refinement starts a new
//      window); an implausible beacon is dropped and counted as at epoch 0;
//   2. the filter's epoch: predict with d, fuse the beacon through its gate (filter.h).
// Both, with refinement on: CSI rows with a non-finite entry are dropped and counted; the
//   filter's belief, the consumed displacement, beacon and CSI rows go into the UAV's
//   SlidingWindowRefiner, whose result is the belief placement uses (the filter keeps running on
//   its own beliefs). Without refinement CSI rows are ignored and the filter's belief is used.
// Health (every epoch): the first of
//   "initial beacon fix <problem>"              (epoch 0: the fix itself was unhealthy),
//   "<EKF|PF> belief <problem>"                 (localization::health_problem),
//   "<EKF|PF> state became non-finite (covariance reset)"  (FilterCounters::non_finite_state),
//   "refined belief <problem>"
// is reported in EpochEstimate::health_problem; the caller decides (the closed loop stops).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "losmimo/fusion/csi.h"
#include "losmimo/fusion/refinement.h"
#include "losmimo/localization/position/filter.h"
#include "losmimo/localization/position/initial_belief.h"
#include "losmimo/localization/position/measurements.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::fusion {

struct EstimatorConfig {
  localization::FilterKind filter_kind = localization::FilterKind::kEkf;
  localization::FilterConfig filter;
  bool refine = false;
  RefinementConfig refinement;
};

// What arrived from the UAV for one epoch, before screening.
struct EpochMeasurements {
  // Dead reckoning since the previous epoch (ignored at epoch 0); none or non-finite: missing.
  std::optional<Eigen::Vector3d> displacement_m;
  std::optional<localization::BeaconMeasurement> beacon;
  std::vector<CsiMeasurement> csi;  // used with refine and refinement.use_csi only
};

// The outcome of one epoch.
struct EpochEstimate {
  localization::Belief filter_belief;  // the filter's belief after this epoch
  localization::Belief belief;         // what placement uses: refined, or the filter's
  // The measurements as the estimator consumed them (after screening).
  std::optional<Eigen::Vector3d> displacement_m;
  std::optional<localization::BeaconMeasurement> beacon;
  std::vector<CsiMeasurement> csi;
  // The beacon-only position of a beacon that passed the screen (also when the filter's gate
  // or the epoch-0 health rule then refused it): the beacon-only statistics' sample.
  std::optional<Eigen::Vector3d> beacon_fix_m;
  bool rejected_beacon = false;                 // implausible (screen 1)
  bool rejected_displacement = false;           // non-finite
  int rejected_csi = 0;                         // rows with a non-finite entry
  bool refinement_covariance_fallback = false;  // CovarianceSource::kDeadReckoning
  // Epoch 0 only: where the filter's start came from.
  localization::InitialBeliefSource initial_source = localization::InitialBeliefSource::kPriorNoBeacon;
  std::optional<std::string> health_problem;  // see "Health" above; nullopt when healthy
};

class UavEstimator {
 public:
  // `prior`: the belief without a beacon (normally start_cube_prior). `filter_seed` drives the
  // particle filter's draws (the EKF draws none). Validates the config (common::FieldError).
  UavEstimator(const placement::Scenario& scenario, const EstimatorConfig& config, const localization::Belief& prior,
               std::uint64_t filter_seed);
  ~UavEstimator();
  UavEstimator(UavEstimator&&) noexcept;
  UavEstimator& operator=(UavEstimator&&) noexcept;

  // Epoch 0 (once, first).
  EpochEstimate start(EpochMeasurements measurements);
  // Epoch k > 0 (throws std::logic_error before start()).
  EpochEstimate step(EpochMeasurements measurements);

  bool started() const { return filter_ != nullptr; }
  const localization::PositionFilter& filter() const;
  const EstimatorConfig& config() const { return config_; }

 private:
  // Refinement (when on), health check; fills the rest of `out` from filter_belief.
  void finish(EpochMeasurements& measurements, EpochEstimate& out);

  EstimatorConfig config_;
  localization::Belief prior_;
  std::uint64_t filter_seed_;
  std::unique_ptr<localization::PositionFilter> filter_;
  std::optional<SlidingWindowRefiner> refiner_;
  placement::Scenario scenario_;
};

}  // namespace losmimo::fusion
