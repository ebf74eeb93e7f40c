#pragma once
// The closed loop: placement driven by estimated, not true, positions.
//
// One swarm iteration i (i = 1, 2, ...), after the paper's master/drone pseudocode:
//  1. Localization, epoch k = i - 1 (epoch 0 is taken in start()). Every UAV m
//     - measures its dead-reckoning displacement since epoch k - 1 (SensorSimulator::
//       measure_displacement of the true net displacement the Swarm applied, probe flights
//       included: the error model sees the net motion only);
//     - receives the BS beacon at its true position (SensorSimulator::measure_beacon; outages
//       from SimulatorConfig::outages for every UAV plus ClosedLoopConfig::outages per UAV);
//     - with refinement and refinement.use_csi, measures its CSI row at its true position
//       (simulate_csi, noise Scenario::noise_variance());
//     - runs one epoch of its UavEstimator (estimation_step.h: screening, filter, refinement,
//       health), whose belief (refined when refinement is on) placement uses.
//  2. Placement, one UAV at a time in index order (the others' rows are current):
//     - belief not degraded (or fallback off): GD, r = GradientDescentPlanner::plan_move at the
//       belief mean (GdBeliefMode::kMean) or the mean of plan_move over the belief's six
//       unscented sigma points mu +- sqrt(3) L e_j, P = L L^T (kSigmaPoints: the expected move
//       under the belief);
//     - belief degraded (Belief::degraded: beacon timeout or covariance too large) and fallback
//       on: BF, BruteForcePlanner::step_uav with BF's step schedule and per-UAV compass
//       contraction (bf.h); the UAV returns to GD as soon as its belief is no longer degraded.
//     The Swarm applies the actuation error (placement::ErrorModel::sigma_act_m); its
//     sigma_loc_m is not used: the beliefs replace the Gaussian localization model.
//     Stall escape (stall.h, GdOptions::escape): the most redundant UAV in GD mode searches its
//     lateral period around its belief mean, as GradientDescentPlanner does; a redundant UAV in
//     BF mode is skipped.
//  3. run_placement (placement/run.h) evaluates the ICN and stops at the target.
//
// Faults. Every measurement is screened before it reaches the filter, the refinement or
// placement (estimation_step.h), and the master watches every UAV:
//  - a non-finite or implausible beacon (localization::is_plausible: range outside
//    (0, filter.max_beacon_range_m], elevation beyond +-pi/2) or CSI row is dropped, a non-finite
//    dead-reckoning displacement is passed to the filter as missing (the filter then predicts
//    with d = 0 and missing_displacement_sigma_m) and to the refinement as none; each is counted
//    per UAV in ClosedLoopStats (rejected_*). The observer sees what the filter consumed.
//  - a UAV that delivers no measurement and does not move for unresponsive_after_iterations
//    iterations in a row ends the run: fault() = kUavUnresponsive, "UAV 3: no measurement and
//    no motion for 3 iterations (since iteration 5)". The measurements of iteration i are those
//    of epoch i - 1 (epoch 0 is start()'s). A UAV dead from iteration k is found at iteration
//    k + unresponsive_after_iterations - 1.
//  - after every epoch the estimation step's health check (estimation_step.h) ends the run
//    before placement uses an unhealthy belief, with kNumericalFault, "UAV 2: EKF belief
//    mean_m(0) = nan at epoch 7".
//  Faults can be injected (ClosedLoopConfig::faults, UavFault): an unresponsive UAV stops
//  measuring and moving (its commands are lost: it hovers where it is); the NaN faults corrupt
//  one component of the measurement as delivered (the simulators draw as usual, so the other
//  UAVs' runs do not change). Faults draw no random numbers: a run with faults that never
//  become active is the run without them.
//
// Randomness: one run seed; every UAV's simulator, filter and CSI generator and the Swarm get
// their own std::mt19937_64 seeds derived from it (SplitMix64), so a run depends on the seed
// only, in any thread.
// Initial belief (epoch 0): the estimation step's epoch-0 rule (localization/initial_belief.h):
// the beacon-only fix when the UAV has a plausible beacon at epoch 0, otherwise the start cube as
// a prior (mean at its centre, 1-sigma cube_side_m / sqrt(12) per axis, degraded).

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <limits>
#include <vector>

#include "losmimo/fusion/estimation_step.h"
#include "losmimo/fusion/refinement.h"
#include "losmimo/localization/position/estimation_errors.h"
#include "losmimo/localization/position/filter.h"
#include "losmimo/localization/position/simulator.h"
#include "losmimo/placement/bf.h"
#include "losmimo/placement/gd.h"
#include "losmimo/placement/run.h"
#include "losmimo/placement/swarm_shape.h"
#include "losmimo/placement/settings.h"
#include "losmimo/placement/stall.h"

namespace losmimo::fusion {

// Where GD evaluates its move from the belief N(mu, P).
// Measured (paper scenario, sigma_act 0.02 m, 20 seeded starts, beacon cross-range 0.1 m /
// 0.18 m at 1 km; every run converged): mean iterations to ICN 0.95, lateral RMSE of the
// beliefs placement used
//   EKF, mean 95 / 110 (0.052 / 0.075 m);  EKF, sigma points 93 / 110 (0.052 / 0.075 m);
//   EKF + Ceres (CSI), mean 75 / 80 (0.048 / 0.064 m);  PF, mean 95 / 115 (0.053 / 0.076 m).
// Sigma points do not help: the filtered error is small and correlated over iterations, and
// averaging the backtracked move over +-sqrt(3) sigma only blurs it. What helps is a better
// mean: the refinement's.
// tests/fusion/closed_loop_variants_test.cpp asserts, at both noise levels and the same seeds:
// every variant converges from every start (20 starts for the EKF modes, 8 for EKF + Ceres and
// PF); sigma points save at most 10% of the mean's iterations and of its lateral RMSE; the
// refinement's lateral RMSE is below the EKF's own in every run and below the EKF-only
// variant's, in fewer iterations on average.
enum class GdBeliefMode {
  kMean,         // plan_move at mu
  kSigmaPoints,  // mean of plan_move at mu +- sqrt(3) L e_j, j = 1..3
};
std::string to_string(GdBeliefMode mode);
// "mean" or "sigma_points"; throws std::invalid_argument otherwise.
GdBeliefMode gd_belief_mode_from_string(const std::string& text);

// UAV `uav` has no beacon during `window` (epochs; epoch k is localized at the start of
// iteration k + 1).
struct UavBeaconOutage {
  int uav = 0;
  localization::OutageWindow window;
};

// An injected fault of one UAV, active in iterations from_iteration .. from_iteration +
// num_iterations - 1 (num_iterations = 0: to the end of the run). Iteration i localizes epoch
// i - 1: kUnresponsive from iteration 1 means no measurement from epoch 0 on (the UAV starts from
// the start-cube prior, as in a beacon outage).
enum class UavFaultKind {
  kUnresponsive,     // no beacon, displacement or CSI; commanded moves are not flown
  kNanBeacon,        // every delivered beacon has range_m = NaN
  kNanDisplacement,  // the dead-reckoning reading's x is NaN
  kNanCsi,           // the CSI row's first entry is NaN (needs refine and refinement.use_csi)
};
// "unresponsive", "nan_beacon", "nan_displacement", "nan_csi".
std::string to_string(UavFaultKind kind);
// The inverse of to_string; throws std::invalid_argument naming the text otherwise.
UavFaultKind uav_fault_kind_from_string(const std::string& text);

struct UavFault {
  UavFaultKind kind = UavFaultKind::kUnresponsive;
  int uav = 0;
  int from_iteration = 1;  // >= 1
  int num_iterations = 0;  // >= 0; 0: until the end
  bool active(int iteration) const {
    return iteration >= from_iteration && (num_iterations == 0 || iteration < from_iteration + num_iterations);
  }
};

struct ClosedLoopConfig {
  localization::FilterKind filter_kind = localization::FilterKind::kEkf;
  localization::FilterConfig filter;        // what the filter assumes
  localization::SimulatorConfig simulator;  // the truth; sigma_act_m unused (the Swarm's)
  bool refine = false;                      // Ceres sliding-window refinement (refinement.h)
  RefinementConfig refinement;
  bool fallback_to_bf = true;  // degraded belief -> BF for that iteration
  GdBeliefMode gd_mode = GdBeliefMode::kMean;
  std::vector<UavBeaconOutage> outages;  // per UAV, on top of simulator.outages
  std::vector<UavFault> faults;          // injected faults (tests, what-if runs); none
  // The master declares a UAV unresponsive after this many iterations in a row without a
  // measurement or a motion from it, in [1, 1000].
  int unresponsive_after_iterations = 3;
};

// The values each field accepts (validate() and the [closed_loop] keys); the nested configs' are
// filter_range, simulator_range and refinement_range.
namespace closed_loop_range {
inline constexpr common::Range unresponsive_after_iterations = common::Range::closed(1, 1000);
inline constexpr common::Range uav =
    common::Range::closed(0, 2147483647);  // an index; < the swarm's size: require_uavs_in_swarm
inline constexpr common::Range fault_from_iteration = common::Range::closed(1, 1e7);
inline constexpr common::Range fault_num_iterations = common::Range::closed(0, 1e7);  // 0: to the end
}  // namespace closed_loop_range

// Throws common::FieldError naming the first bad field and its value (the nested configs
// through their own validate()). UAV indices are checked against the swarm by
// require_uavs_in_swarm.
void validate(const ClosedLoopConfig& config);

// Every UAV index of a valid config (outages, then faults) is below num_uavs, the swarm's size;
// else throws common::FieldError "closed_loop.outages[1].uav = 16: must be < the number of UAVs
// (16)". ClosedLoopPlanner::start and load_closed_loop_config check it.
void require_uavs_in_swarm(const ClosedLoopConfig& config, int num_uavs);

// The filter and sensor config that match a simulator: the filter assumes the true sensor noise.
ClosedLoopConfig matched_closed_loop_config(const localization::SimulatorConfig& simulator,
                                            const placement::Scenario& scenario);

enum class UavMode : char { kGd = 'G', kBf = 'B' };

// Localization and mode statistics of one run. Errors are the belief means placement used
// (refined when refinement is on) against the true positions, over every epoch and UAV.
struct ClosedLoopStats {
  int num_epochs = 0;           // per UAV, epoch 0 included
  double rmse_m = 0.0;          // 3-D
  double lateral_rmse_m = 0.0;  // y and z (across the line of sight)
  double average_nees = 0.0;    // e^T P^-1 e, 3 dof (3 when consistent)
  double filter_rmse_m = 0.0;   // the same for the filter's own beliefs
  double filter_lateral_rmse_m = 0.0;
  double filter_average_nees = 0.0;
  // The swarm's split of the beliefs placement used, per epoch (placement/swarm_shape.h): the RMS
  // of the common lateral offset and the lateral shape residual's RMSE.
  double common_lateral_rms_m = 0.0;
  double shape_lateral_rmse_m = 0.0;
  // Mean over those epochs of the shape residual's NEES over its degrees of freedom (1 when
  // consistent; placement::shape_nees_per_dof); NaN when no epoch had one.
  double shape_nees_per_dof = std::numeric_limits<double>::quiet_NaN();
  double beacon_only_rmse_m = 0.0;  // beacon_fix of every received beacon (0: none)
  double beacon_only_lateral_rmse_m = 0.0;
  int num_beacons = 0;
  std::vector<int> gd_iterations;            // per UAV
  std::vector<int> bf_fallback_iterations;   // per UAV
  std::vector<int> last_fallback_iteration;  // per UAV, 0 = never
  std::vector<std::string> mode_trace;       // [iteration - 1][uav]: 'G' or 'B'
  int escapes = 0;                           // successful stall escapes
  int refinement_covariance_fallbacks = 0;   // CovarianceSource::kDeadReckoning results
  // Measurements the master dropped, per UAV: non-finite, or beacons failing
  // localization::is_plausible (see "Faults" above).
  std::vector<int> rejected_beacons;
  std::vector<int> rejected_displacements;
  std::vector<int> rejected_csi;
  std::vector<int> silent_iterations;  // per UAV: iterations without a measurement or motion
  int rejected_measurements() const;   // the sum of the three rejected_* over every UAV
};

// Optional observer of a closed-loop run (e.g. the rawlog recorder, rawlog/recorder.h). It sees
// copies of what every UAV measured and believed, and every move, in the order they happen:
//   start():      on_start, then on_epoch(epoch 0) for every UAV;
//   iteration i:  on_epoch(epoch i - 1) for every UAV (i > 1), on_move for every UAV, then
//                 on_move for a successful stall escape, then on_iteration_end(i).
// It cannot change the run: without an observer, and with any observer, the run is the same.
struct EpochObservation {
  int epoch = 0;
  int uav = 0;
  Eigen::Vector3d true_position_m = Eigen::Vector3d::Zero();
  // Dead reckoning since the previous epoch, as the filter consumed it (none at epoch 0).
  std::optional<Eigen::Vector3d> measured_displacement_m;
  std::optional<localization::BeaconMeasurement> beacon;  // as the filter consumed it
  std::optional<CsiMeasurement> csi;                      // the row the refinement used (refine and use_csi only)
  localization::Belief filter_belief;                     // the filter's belief after this epoch
  localization::Belief belief;                            // what placement uses (refined, or the filter's)
};

struct MoveObservation {
  int iteration = 0;
  int uav = 0;
  UavMode mode = UavMode::kGd;
  bool escape = false;  // a stall escape (GD mode), after the iteration's regular moves
  // GD: the planned move r; BF: b times the chosen probe direction (zero when it stays).
  Eigen::Vector3d commanded_m = Eigen::Vector3d::Zero();
  // True net displacement over the UAV's turn (BF probe flights' actuation errors included).
  Eigen::Vector3d actual_m = Eigen::Vector3d::Zero();
};

class ClosedLoopObserver {
 public:
  virtual ~ClosedLoopObserver() = default;
  // filter_seeds[m]: the seed of UAV m's filter (make_filter), for an exact offline replay.
  virtual void on_start(const std::vector<std::uint64_t>& /*filter_seeds*/) {}
  virtual void on_epoch(const EpochObservation& /*observation*/) {}
  virtual void on_move(const MoveObservation& /*move*/) {}
  virtual void on_iteration_end(int /*iteration*/, const placement::Swarm& /*swarm*/) {}
};

class ClosedLoopPlanner : public placement::Planner {
 public:
  ClosedLoopPlanner(const placement::Scenario& scenario, const placement::GdOptions& gd, const placement::BfOptions& bf,
                    const ClosedLoopConfig& config, std::uint64_t seed);
  ~ClosedLoopPlanner() override;
  ClosedLoopPlanner(const ClosedLoopPlanner&) = delete;
  ClosedLoopPlanner& operator=(const ClosedLoopPlanner&) = delete;

  // "gd+ekf", "gd+pf+ceres", ... ("+sp" for sigma points).
  std::string name() const override;
  // Builds the per-UAV sensors and filters (fresh seeds) and localizes epoch 0.
  void start(placement::Swarm& swarm) override;
  void iterate(placement::Swarm& swarm, int iteration) override;
  // An unresponsive UAV or a non-finite belief (see "Faults" above); once set, iterate() does
  // nothing more.
  std::optional<placement::PlannerFault> fault() const override { return fault_; }

  // The beliefs placement uses now, one per UAV.
  const std::vector<localization::Belief>& beliefs() const { return beliefs_; }
  ClosedLoopStats stats() const;
  // Not owned; nullptr (the default) for none. Set before start().
  void set_observer(ClosedLoopObserver* observer) { observer_ = observer; }

 private:
  struct Uav;
  void localize(placement::Swarm& swarm, int epoch);
  Eigen::Vector3d plan_gd(const placement::Swarm& swarm, int m, int iteration) const;
  bool try_escape(placement::Swarm& swarm);
  bool fault_active(UavFaultKind kind, int m, int iteration) const;
  // UAV m's CSI row at iteration `iteration` (none without use_csi), with any injected fault;
  // the estimator screens it.
  std::vector<CsiMeasurement> measure_csi(int m, const Eigen::Vector3d& q_m, int iteration, std::mt19937_64& rng) const;
  bool unresponsive(int m, int iteration) const { return fault_active(UavFaultKind::kUnresponsive, m, iteration); }
  // Takes UAV m's epoch: its belief for placement, counters, a fault from an unhealthy belief
  // (kNumericalFault), the observer and the error statistics.
  void record_epoch(int m, int epoch, const Eigen::Vector3d& q_m, const EpochEstimate& estimate);
  // End of iteration i: silence bookkeeping and the unresponsive-UAV rule.
  void watch_uavs(int iteration);

  placement::Scenario scenario_;
  placement::GdOptions gd_options_;
  placement::BfOptions bf_options_;
  ClosedLoopConfig config_;
  std::uint64_t seed_;
  placement::ChannelModel model_;
  placement::GradientDescentPlanner gd_;
  placement::StallDetector stall_;
  int escape_rank_ = 0;
  std::vector<Uav> uavs_;  // per-UAV sensors, filter, refiner (closed_loop.cpp)
  std::vector<localization::Belief> beliefs_;
  ClosedLoopObserver* observer_ = nullptr;
  int escape_iteration_ = 0;       // the iteration try_escape runs in (for the observer)
  std::vector<char> heard_;        // per UAV: a measurement or a motion in the current iteration
  std::vector<int> silent_since_;  // per UAV: first iteration of the current silence, 0: none
  std::optional<placement::PlannerFault> fault_;

  // Accumulated statistics (see ClosedLoopStats): placement's beliefs, the filters' and the
  // beacon-only fixes, against the true positions.
  localization::ErrorAccumulator placed_errors_, filter_errors_, beacon_only_errors_;
  placement::SwarmShapeAccumulator placed_shape_;
  // One epoch of the beliefs placement uses, every UAV, into placed_shape_.
  void record_shape(const placement::Swarm& swarm);
  ClosedLoopStats modes_;  // the per-UAV and per-iteration fields only
};

// One closed-loop run with the given settings: scenario, GD and BF options, run options
// (target ICN, iteration cap; [gd]'s own target_icn / max_iterations over [placement]'s, since
// the closed loop is a GD planner) and errors.sigma_act_m (errors.sigma_loc_m is not used).
struct ClosedLoopRun {
  placement::RunResult run;
  ClosedLoopStats stats;
};
// `observer` (optional, not owned) sees the run as ClosedLoopObserver describes.
ClosedLoopRun run_closed_loop(const placement::PlacementSettings& settings, const Eigen::Matrix3Xd& start_m,
                              const ClosedLoopConfig& config, std::uint64_t seed,
                              ClosedLoopObserver* observer = nullptr);

}  // namespace losmimo::fusion
