#pragma once
// The co-evaluation of estimators and placement: two sweep kinds that fusion adds to
// `losmimo-experiment` (experiment/extension.h). Both are off unless listed in
// `[experiment] sweeps`, e.g. `--set experiment.sweeps=beacon_noise_m,beacon_outage`.
//
// Sweep `beacon_noise_m`: the value v [m] is the beacon-only cross-range error at the swarm
//   range R = |cube_center_m|, per lateral axis (1-sigma). The beacon's angle noise is
//   sigma_angle_rad = v / R (azimuth and elevation); its range noise is [closed_loop]
//   beacon_sigma_range_m whatever v. At every point every algorithm starts from the trial's start
//   (experiment::trial_start_positions_m) with the point's seed (experiment::trial_seed). A row is
//   a (planner, estimator) pair (estimator_registry.h); today's rows by their aliases:
//   - gd_gauss      the paper's GD under its Gaussian localization model with sigma_loc_m = v:
//                   the experiment's own GD run (experiment::run_algorithm: planner, [gd] stop
//                   rule), from the point's seed. Matching: the Gaussian's error
//                   per lateral axis has the same 1-sigma v as the beacon-only fix, so its
//                   2-D lateral RMSE sqrt(2) v equals the beacon-only lateral RMSE that the
//                   closed-loop rows report in beacon_lateral_rmse_m (measured, first order in
//                   sigma_angle). The Gaussian also errs by v along the range, where the
//                   beacon errs by beacon_sigma_range_m; GD is insensitive to that axis (a common
//                   phase of the UAV's row).
//   - gd_gauss_matched  gd_gauss at the error gd_ekf measured in the same trial and point: its
//                   sigma_loc_m per axis is gd_ekf's loc_lateral_rmse_m / sqrt(2), so the two
//                   have the same lateral RMSE (the error GD is sensitive to; along the range
//                   the filter errs by the beacon's range noise, which GD ignores). The fair
//                   comparison for "does integrating the estimator win": at matched error any
//                   difference is the error's structure (correlated, known covariance), not
//                   its size. Runs gd_ekf's closed loop for its RMSE when gd_ekf is not listed.
//                   The experiment's GD as gd_gauss is: run_algorithm, the same seed.
//   - gd_gauss_shape_matched  the same at gd_ekf's shape error (common lateral offset and
//                   rotation about boresight removed, the error the channel sees): its expected
//                   shape RMSE equals gd_ekf's shape_lateral_rmse_m.
//   - gd_ekf, gd_pf, gd_ekf_ceres   the closed loop (closed_loop.h) with the EKF, the particle
//                   filter, and the EKF with Ceres CSI refinement; BF fallback on.
//   - gd_ekf_nofallback             gd_ekf with the BF fallback off.
//   - bf            the experiment's BF run (needs no position; [bf] options and stop rule).
//   - ura_ekf       the experiment's URA planner ([coevaluation] ura_variant, [ura] options and
//                   stop rule) whose position estimates
//                   are EKF beliefs: every UAV runs its own sensors and EKF (as the closed loop
//                   does), one epoch per URA position estimate (the assignment at start, then
//                   one per iteration), through Swarm::set_position_estimator.
//   - centralized   the Ceres solution of eq. 4 with perfect knowledge (centralized.h), which
//                   does not depend on v: solved once per start and reused at every point.
//                   iterations 0; the UAVs are taken to fly straight to it simultaneously, so
//                   dist_to_icn050_m / dist_to_icn095_m are the mean distance flown when the
//                   ICN along that flight (200 steps) first reaches 0.5 / 0.95; converged =
//                   feasible (status iteration_cap when Ceres found no feasible point).
//   The filters assume the true sensor noise, floored at FilterConfig's min_sigma_angle_rad
//   and min_sigma_range_m (1 mm at 1 km): at v = 0 they assume a beacon of 1e-6 rad.
//
// Sweep `beacon_outage`: the value k is the number of UAVs that lose the beacon for epochs
//   outage_first_epoch .. + outage_epochs - 1 (epoch e is localized at iteration e + 1): UAVs
//   floor(i Nr / k), i = 0 .. k-1 (start positions are random, so indices carry no geometry).
//   Beacon noise outage_beacon_noise_m; the filter is degraded after
//   outage_degraded_after_epochs epochs without beacon. Algorithms: gd_ekf (BF fallback) and,
//   for comparison, gd_ekf_nofallback, gd_pf, gd_ekf_ceres.
//
// Sweep `bs_misalignment_rad`: the value is the BS array's azimuth misalignment [rad], which every
//   UAV's beacon bearing reads and no filter knows ([closed_loop] bs_azimuth_bias_rad at that
//   value): it moves every beacon fix laterally by about R x value, the same way (a common-mode
//   error, placement/swarm_shape.h). Beacon noise misalignment_beacon_noise_m at every point, as a
//   beacon_noise_m value. Rows misalignment_algorithms, run as at a beacon_noise_m point: gd_gauss
//   is the paper's model of the beacon noise alone (blind to the misalignment), the matched rows
//   take gd_ekf's absolute, shape, and shape-plus-common errors; bf, which needs no position,
//   is the reference the misalignment cannot reach.
//
// Extra trials.csv / summary.csv columns, the same for every sweep: coevaluation_metrics() below
// (every record sets each, NaN where it does not apply).
//
// Settings: the [coevaluation] keys, and the [closed_loop] keys the closed-loop algorithms share
// with losmimo-record (one spelling: fusion/closed_loop_settings.h): the true beacon range noise,
// dead reckoning, particles and the refinement window and CSI. Each key is declared once in the
// key table in settings.cpp (coevaluation_keys()). [errors] sigma_act_m applies to every
// algorithm; [errors] sigma_loc_m to none (the sweep sets gd_gauss's).

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "losmimo/placement/common/input_error.h"
#include "losmimo/placement/common/key_table.h"
#include "losmimo/fusion/coevaluation/estimator_registry.h"
#include "losmimo/fusion/closed_loop.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/ura.h"

namespace losmimo::coevaluation {

inline const std::string kSweepBeaconNoise = "beacon_noise_m";
inline const std::string kSweepBeaconOutage = "beacon_outage";
inline const std::string kSweepMisalignment = "bs_misalignment_rad";

struct CoevaluationSettings {
  std::vector<double> beacon_noise_values_m = {0.0, 0.02, 0.04, 0.06, 0.08, 0.10, 0.12, 0.14, 0.16, 0.18};
  // The rows (estimator_registry.h), resolved: ura_ekf's planner is ura_variant's URA.
  std::vector<CoevalRow> algorithms = aliased_rows({"gd_gauss", "gd_ekf", "gd_gauss_matched", "gd_gauss_shape_matched",
                                                    "gd_pf", "gd_ekf_ceres", "bf", "ura_ekf", "centralized"});
  // The [closed_loop] keys shared with losmimo-record, as ClosedLoopConfig holds them:
  // simulator.sigma_range_m (the beacon's range 1-sigma at every point), simulator.dr_sigma_*,
  // filter.num_particles, refinement.window_epochs and refinement.use_csi. The rest of a run's
  // config is its algorithm's and its sweep point's (coevaluation_closed_loop_config).
  fusion::ClosedLoopConfig closed_loop;
  placement::UraVariant ura_variant = placement::UraVariant::kRigid;
  std::vector<int> outage_values = {0, 2, 4, 8};  // UAVs without beacon
  // gd's closed loop with a filter estimator only.
  std::vector<CoevalRow> outage_algorithms = aliased_rows({"gd_ekf", "gd_ekf_nofallback"});
  int outage_first_epoch = 10;
  int outage_epochs = 30;
  int outage_degraded_after_epochs = 5;
  double outage_beacon_noise_m = 0.1;  // cross-range 1-sigma at R, as beacon_noise_m's value
  // bs_misalignment_rad: the BS array's azimuth misalignment [rad] at each point (it replaces
  // [closed_loop] bs_azimuth_bias_rad), at beacon noise misalignment_beacon_noise_m.
  std::vector<double> misalignment_values_rad = {0.0, 0.000244140625, 0.00048828125, 0.0009765625, 0.001953125};
  std::vector<CoevalRow> misalignment_algorithms = aliased_rows(
      {"gd_gauss", "gd_ekf", "gd_gauss_matched", "gd_gauss_shape_matched", "gd_gauss_split_matched", "bf"});
  double misalignment_beacon_noise_m = 0.02;
};

// The key table: the [coevaluation] keys, the shared [closed_loop] ones (their entries in
// fusion::closed_loop_keys()) and the old [coevaluation] spellings of those, which are refused.
const common::KeyTable<CoevaluationSettings>& coevaluation_keys();
// The sections and keys it reads (coevaluation_keys().known_keys()).
std::map<std::string, std::set<std::string>> coevaluation_config_keys();
// Reads and validates its keys (absent keys keep their defaults); a bad key or value throws
// common::InputError naming "origin:line: [section] key" and the value.
CoevaluationSettings load_coevaluation_settings(const experiment::ExperimentSettings& settings);
// The settings as INI text: [coevaluation] and the shared [closed_loop] keys, defaults filled in.
std::string to_ini(const CoevaluationSettings& settings);

// The extra metrics, declared like the built-in ones (experiment/metrics.h).
inline constexpr experiment::ExtensionMetric kLocRmse{
    {"loc_rmse_m"},
    "m",
    "3-D RMSE of the position estimates placement used, over every epoch and UAV (gd_gauss: the model's sqrt(3) v, "
    "by construction)"};
inline constexpr experiment::ExtensionMetric kLocLateralRmse{
    {"loc_lateral_rmse_m"}, "m", "the same across the line of sight, sqrt(e_y^2 + e_z^2) (gd_gauss: sqrt(2) v)"};
inline constexpr experiment::ExtensionMetric kCommonLateral{
    {"common_lateral_m"},
    "m",
    "RMS over epochs of the swarm's common lateral offset of those estimates (placement/swarm_shape.h), which the "
    "channel barely sees (the Gaussian rows: the model's expected v sqrt(2 / N), by construction; NaN for truth)"};
inline constexpr experiment::ExtensionMetric kShapeLateralRmse{
    {"shape_lateral_rmse_m"},
    "m",
    "RMSE over epochs and UAVs of their lateral shape residual (common offset and rotation about boresight "
    "removed): the error capacity sees (the Gaussian rows: v sqrt((2N - 3) / N), by construction; NaN for truth)"};
inline constexpr experiment::ExtensionMetric kShapeNees{
    {"shape_nees"},
    "",
    "mean over epochs of the shape residual's NEES over its 2N - 3 degrees of freedom (1 when consistent; NaN for "
    "rows without beliefs: truth and the Gaussian rows)"};
inline constexpr experiment::ExtensionMetric kNees{
    {"nees"}, "", "average e^T P^-1 e of those estimates (3 when consistent)"};
inline constexpr experiment::ExtensionMetric kBfFallbackFraction{
    {"bf_fallback_fraction"}, "", "UAV-iterations in BF fallback / (Nr x iterations) (closed loop only)"};
inline constexpr experiment::ExtensionMetric kBeaconLateralRmse{
    {"beacon_lateral_rmse_m"}, "m", "the beacon-only fixes' lateral RMSE (measured), the matching check"};
inline constexpr experiment::ExtensionMetric kPairedTravelDiff{
    {"paired_travel_diff_m"},
    "m",
    "the matched Gaussian rows only: gd_ekf's dist_to_icn095_m minus its own, same trial and point (NaN when either "
    "did "
    "not reach ICN 0.95); summarised, the paired mean difference with its 95% CI"};
inline constexpr experiment::ExtensionMetric kPairedIterationsDiff{
    {"paired_iterations_diff"}, "iterations", "the matched Gaussian rows only: gd_ekf's iterations minus its own"};
// Their table, in column order.
const experiment::ExtensionMetrics& coevaluation_metrics();

// The closed-loop config of filter estimator `estimator` (ekf, pf, ekf_nofallback, ekf_ceres: one
// with EstimatorEntry::closed_loop) at beacon cross-range error beacon_noise_m [m]
// (sigma_angle_rad = beacon_noise_m / R); std::invalid_argument for another.
fusion::ClosedLoopConfig coevaluation_closed_loop_config(const CoevaluationSettings& settings,
                                                         const placement::Scenario& scenario,
                                                         const std::string& estimator, double beacon_noise_m);

// The UAVs that lose the beacon in the outage sweep: floor(i * num_uavs / num_lost).
std::vector<int> outage_uavs(int num_lost, int num_uavs);

// One trial of each sweep: every configured row's record (extra = the metrics above). `c` is
// load_coevaluation_settings(settings), parsed once per run; the overloads without it parse it.
std::vector<experiment::TrialRecord> run_beacon_noise_trial(const experiment::ExperimentSettings& settings,
                                                            const CoevaluationSettings& c, int point, int trial);
std::vector<experiment::TrialRecord> run_beacon_noise_trial(const experiment::ExperimentSettings& settings, int point,
                                                            int trial);
std::vector<experiment::TrialRecord> run_outage_trial(const experiment::ExperimentSettings& settings,
                                                      const CoevaluationSettings& c, int point, int trial);
std::vector<experiment::TrialRecord> run_outage_trial(const experiment::ExperimentSettings& settings, int point,
                                                      int trial);
std::vector<experiment::TrialRecord> run_misalignment_trial(const experiment::ExperimentSettings& settings,
                                                            const CoevaluationSettings& c, int point, int trial);

// The three extensions (extensions.h lists them); each parses its settings once per run
// (ExperimentExtension::bind).
experiment::ExperimentExtension beacon_noise_extension();
experiment::ExperimentExtension beacon_outage_extension();
experiment::ExperimentExtension misalignment_extension();

}  // namespace losmimo::coevaluation
