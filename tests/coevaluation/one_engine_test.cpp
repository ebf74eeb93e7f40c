// The co-evaluation and the experiment are two views of one engine: the co-evaluation's
// Gaussian GD is the experiment's GD, its stop rules are the experiment's, and with perfect
// sensors the closed loop's GD places exactly as the open-loop GD with perfect knowledge.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/extensions.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/trial.h"
#include "losmimo/fusion/closed_loop.h"

namespace losmimo::coevaluation {
namespace {

// With perfect sensors the EKF's beliefs are the true positions to rounding (measured: RMSE
// 8e-15 and 9e-15 m over the two runs below): the beacon fix's round trip q -> (r, az, el) -> q.
constexpr double kBeliefTolerance_m = 1e-12;
// GD amplifies that rounding: its move depends on the phase 2 pi |q - p| / lambda (lambda = 5 mm),
// and a 1e-14 m change of q moves the planned step by ~1e-10 m within five iterations (measured
// 1.1e-10 m) and by up to 4.7e-8 m over a 75-iteration run. 1e-9 m in positions is therefore not
// reachable by any closed loop whose beliefs are not bitwise the truth; a different GD (another
// step rule, escape or order) differs by centimetres to metres. The bound: lambda / 5000.
constexpr double kPathTolerance_m = 1e-6;

// A beacon-noise sweep over `values`, with the given extra overrides.
experiment::ExperimentSettings settings(const std::string& values, const std::vector<std::string>& sets) {
  common::IniConfig cfg;
  cfg.set_override("experiment.sweeps=beacon_noise_m");
  cfg.set_override("experiment.trials=2");
  cfg.set_override("coevaluation.beacon_noise_values_m=" + values);
  cfg.set_override("placement.max_iterations=150");
  for (const std::string& s : sets) cfg.set_override(s);
  return experiment::load_experiment_settings(cfg, experiment_extensions());
}

// The experiment's GD of the sweep's first point and this trial (its start and seed) at
// Gaussian localization error sigma_m.
placement::RunResult experiments_gd(const experiment::ExperimentSettings& s, int trial, double sigma_m) {
  placement::PlacementSettings p = s.placement;
  p.errors.sigma_loc_m = sigma_m;
  return experiment::run_algorithm(s, p, experiment::Algorithm::kGd, trial,
                                   experiment::trial_start_positions_m(s, trial),
                                   experiment::trial_seed(s, kSweepBeaconNoise, 0, trial), s.placement.run);
}

const experiment::TrialRecord& record_of(const std::vector<experiment::TrialRecord>& records, const std::string& a) {
  for (const experiment::TrialRecord& r : records) {
    if (r.algorithm == a) return r;
  }
  throw std::runtime_error("no record of " + a);
}

TEST(OneEngine, GdGauss_IsTheExperimentsGd_AtTheSameSigmaLocAndSeed) {
  // GIVEN: a beacon-noise point v = 0.1 m, gd_gauss alone.
  const experiment::ExperimentSettings s = settings("0, 0.1", {"coevaluation.algorithms=gd_gauss"});
  for (int trial = 0; trial < 2; ++trial) {
    const std::vector<experiment::TrialRecord> records = run_beacon_noise_trial(s, 1, trial);
    // WHEN: the experiment's GD at sigma_loc 0.1 m from the same start and seed.
    placement::PlacementSettings p = s.placement;
    p.errors.sigma_loc_m = 0.1;
    const placement::RunResult gd = experiment::run_algorithm(
        s, p, experiment::Algorithm::kGd, trial, experiment::trial_start_positions_m(s, trial),
        experiment::trial_seed(s, kSweepBeaconNoise, 1, trial), s.placement.run);
    // THEN: the same run, bit for bit.
    const experiment::TrialRecord& r = record_of(records, "gd_gauss");
    EXPECT_EQ(r.iterations, gd.iterations);
    EXPECT_EQ(r.final_m, gd.final_m);
  }
}

TEST(OneEngine, GdGaussAtZeroNoise_IsTheBuiltInSigmaLocSweepsGd_WithoutActuationError) {
  // GIVEN: no actuation error, so the error seeds (which differ between sweeps) draw nothing
  // that matters; the built-in sigma_loc sweep's point 0 and the co-evaluation's point 0.
  const experiment::ExperimentSettings s =
      settings("0", {"experiment.sweeps=sigma_loc_m, beacon_noise_m", "coevaluation.algorithms=gd_gauss",
                     "errors.sigma_act_m=0", "experiment.sigma_loc_values_m=0", "experiment.algorithms=gd"});
  for (int trial = 0; trial < 2; ++trial) {
    const experiment::TrialRecord coeval = record_of(run_beacon_noise_trial(s, 0, trial), "gd_gauss");
    const experiment::TrialRecord builtin =
        record_of(experiment::run_trial(s, experiment::kSweepSigmaLoc, 0, trial), "gd");
    // THEN: two entry points, one run.
    EXPECT_EQ(coeval.iterations, builtin.iterations);
    EXPECT_EQ(coeval.final_m, builtin.final_m);
    EXPECT_EQ(coeval.final_icn, builtin.final_icn);
  }
}

TEST(OneEngine, GdGaussShapeMatched_IsTheExperimentsGdAtTheSigmaWhoseExpectedShapeErrorIsGdEkfs_BitForBit) {
  // GIVEN: gd_ekf and gd_gauss_shape_matched at beacon noise 0.1 m, 16 UAVs.
  const experiment::ExperimentSettings s = settings("0.1", {"coevaluation.algorithms=gd_ekf, gd_gauss_shape_matched"});
  const int n = s.placement.scenario.num_uavs;
  ASSERT_EQ(n, 16);
  for (int trial = 0; trial < 2; ++trial) {
    const std::vector<experiment::TrialRecord> records = run_beacon_noise_trial(s, 0, trial);
    const experiment::TrialRecord& ekf = record_of(records, "gd_ekf");
    const experiment::TrialRecord& matched = record_of(records, "gd_gauss_shape_matched");
    // WHEN: the experiment's GD at the sigma whose expected shape RMSE, with 2N coordinates less
    // 2 translations and 1 rotation, sigma sqrt(29 / 16), is gd_ekf's measured one.
    const double sigma_m = ekf.extension.at(kShapeLateralRmse) / std::sqrt(29.0 / 16.0);
    ASSERT_GT(sigma_m, 1e-3);
    // (the shape is a part of the lateral error: the matched sigma is below the lateral match)
    EXPECT_LT(ekf.extension.at(kShapeLateralRmse), ekf.extension.at(kLocLateralRmse));
    const placement::RunResult gd = experiments_gd(s, trial, sigma_m);
    // THEN: the row is that run, bit for bit, and reports the model's split at that sigma.
    EXPECT_EQ(matched.iterations, gd.iterations) << "trial " << trial;
    EXPECT_EQ(matched.final_m, gd.final_m) << "trial " << trial;
    EXPECT_NEAR(matched.extension.at(kShapeLateralRmse), ekf.extension.at(kShapeLateralRmse),
                1e-12 * ekf.extension.at(kShapeLateralRmse));
    EXPECT_NEAR(matched.extension.at(kCommonLateral), sigma_m * std::sqrt(2.0 / 16.0), 1e-15);
    EXPECT_EQ(matched.extension.at(kLocLateralRmse), std::sqrt(2.0) * sigma_m);
    EXPECT_TRUE(std::isnan(matched.extension.at(kShapeNees)));
    EXPECT_EQ(matched.extension.at(kPairedIterationsDiff), static_cast<double>(ekf.iterations - gd.iterations));
  }
}

TEST(OneEngine, GdGaussMatched_IsTheExperimentsGdAtGdEkfsMeasuredLateralError_BitForBit) {
  // GIVEN: gd_ekf and gd_gauss_matched at beacon noise 0.1 m.
  const experiment::ExperimentSettings s = settings("0.1", {"coevaluation.algorithms=gd_ekf, gd_gauss_matched"});
  for (int trial = 0; trial < 2; ++trial) {
    const std::vector<experiment::TrialRecord> records = run_beacon_noise_trial(s, 0, trial);
    const experiment::TrialRecord& ekf = record_of(records, "gd_ekf");
    const experiment::TrialRecord& matched = record_of(records, "gd_gauss_matched");
    // WHEN: the experiment's GD, re-run here from the same start and seed at the sigma_loc whose
    // 2-D lateral RMSE is gd_ekf's measured one.
    const double sigma_m = ekf.extension.at(kLocLateralRmse) / std::sqrt(2.0);
    ASSERT_GT(sigma_m, 1e-3);
    const placement::RunResult gd = experiments_gd(s, trial, sigma_m);
    // THEN: the matched row is that run, bit for bit, and reports that sigma.
    EXPECT_EQ(matched.iterations, gd.iterations) << "trial " << trial;
    EXPECT_EQ(matched.final_m, gd.final_m) << "trial " << trial;
    EXPECT_EQ(matched.extension.at(kLocLateralRmse), std::sqrt(2.0) * sigma_m);
    EXPECT_EQ(matched.extension.at(kPairedIterationsDiff), static_cast<double>(ekf.iterations - gd.iterations));
    // THEN (negative control): the same GD without the error places differently.
    const placement::RunResult exact = experiments_gd(s, trial, 0.0);
    EXPECT_NE(exact.final_m, gd.final_m) << "trial " << trial;
  }
}

TEST(OneEngine, AlgorithmStopRules_ActInTheCoevaluation) {
  // GIVEN: [gd], [bf] and [ura] iteration caps far below what the runs need at this noise.
  const experiment::ExperimentSettings s =
      settings("0.1", {"coevaluation.algorithms=gd_gauss, gd_ekf, gd_gauss_matched, bf, ura_ekf", "gd.max_iterations=7",
                       "bf.max_iterations=9", "ura.max_iterations=3", "placement.target_icn=0.999"});
  const std::vector<experiment::TrialRecord> records = run_beacon_noise_trial(s, 0, 0);
  // THEN: every run stops at its own algorithm's cap; the closed loop is a GD planner.
  EXPECT_EQ(record_of(records, "gd_gauss").iterations, 7);
  EXPECT_EQ(record_of(records, "gd_gauss_matched").iterations, 7);
  EXPECT_EQ(record_of(records, "gd_ekf").iterations, 7);
  EXPECT_EQ(record_of(records, "bf").iterations, 9);
  EXPECT_EQ(record_of(records, "ura_ekf").iterations, 3);
  for (const experiment::TrialRecord& r : records) EXPECT_EQ(r.status, "iteration_cap") << r.algorithm;
}

TEST(OneEngine, CapEkf_RunsTheCapacityPlannerUnderItsOwnStopRule) {
  // GIVEN: the capacity planner from EKF beliefs, a [cap] iteration cap below what it needs
  const std::vector<experiment::TrialRecord> capped = run_beacon_noise_trial(
      settings("0.1", {"coevaluation.algorithms=cap_ekf", "cap.max_iterations=4", "placement.target_icn=0.999"}), 0, 0);
  // THEN: it stops at [cap]'s cap
  EXPECT_EQ(record_of(capped, "cap_ekf").iterations, 4);
  EXPECT_EQ(record_of(capped, "cap_ekf").status, "iteration_cap");
  // GIVEN: the default stop rule at beacon noise 0.1 m; THEN: it converges at the capacity bound
  const experiment::ExperimentSettings s = settings("0.1", {"coevaluation.algorithms=cap_ekf"});
  const double bound = 16.0 * std::log2(1.0 + 10.0 * 16.0);  // placement/capacity.h, 10 dB, 16 x 16
  for (int trial = 0; trial < 2; ++trial) {
    const experiment::TrialRecord r = record_of(run_beacon_noise_trial(s, 0, trial), "cap_ekf");
    EXPECT_TRUE(r.converged) << "trial " << trial;
    EXPECT_GT(r.sum_rate_zf_bps_hz / bound, 0.99) << "trial " << trial;
  }
}

TEST(OneEngine, GdEkfWithPerfectSensors_FollowsTheOpenLoopGdWithPerfectKnowledge) {
  // GIVEN: no beacon noise (angle nor range), exact dead reckoning, no outage, no actuation
  // error; the filter assumes its noise floors (1e-6 rad, 1 mm, 0.1 mm per displacement).
  const experiment::ExperimentSettings s =
      settings("0", {"errors.sigma_act_m=0", "closed_loop.beacon_sigma_range_m=0"});
  const CoevaluationSettings c = load_coevaluation_settings(s);
  for (int trial = 0; trial < 2; ++trial) {
    const Eigen::Matrix3Xd start = experiment::trial_start_positions_m(s, trial);
    placement::PlacementSettings p = s.placement;
    p.run.record_path = true;
    // WHEN: the closed loop with the EKF, and the open-loop GD at sigma_loc 0.
    fusion::ClosedLoopConfig config = coevaluation_closed_loop_config(c, p.scenario, "ekf", 0.0);
    config.simulator.dr_sigma_floor_m = 0.0;  // exact dead reckoning (the key refuses 0: a real sensor errs)
    config.simulator.dr_sigma_fraction = 0.0;
    const fusion::ClosedLoopRun closed = fusion::run_closed_loop(p, start, config, 11);
    p.errors = placement::ErrorModel{};
    const placement::RunResult open =
        experiment::run_algorithm(s, p, experiment::Algorithm::kGd, trial, start, 12, p.run);
    // THEN: the same number of iterations and the same positions after every one of them.
    ASSERT_EQ(closed.run.iterations, open.iterations);
    ASSERT_EQ(closed.run.path.size(), open.path.size());
    double worst_m = 0.0;
    for (std::size_t i = 0; i < open.path.size(); ++i)
      worst_m = std::max(worst_m, (closed.run.path[i] - open.path[i]).cwiseAbs().maxCoeff());
    EXPECT_LE(closed.stats.rmse_m, kBeliefTolerance_m) << "trial " << trial;
    EXPECT_LE(worst_m, kPathTolerance_m) << "trial " << trial;
    EXPECT_EQ(closed.stats.bf_fallback_iterations, std::vector<int>(start.cols(), 0));
  }
}

}  // namespace
}  // namespace losmimo::coevaluation
