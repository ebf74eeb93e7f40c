// The channel sweeps (experiment/channel_sweeps.h): their "off" points are the pure LoS runs, each
// swept key changes what it should and nothing else, and bad sweep values stop before any work
// with the key named.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "losmimo/placement/common/ini_config.h"
#include "losmimo/placement/experiment/channel_sweeps.h"
#include "losmimo/placement/experiment/settings.h"
#include "losmimo/placement/experiment/trial.h"
#include "losmimo/placement/channel.h"
#include "losmimo/placement/metrics.h"

namespace losmimo::experiment {
namespace {

constexpr int kTrial = 1;
constexpr double kSameSlot_m = 1e-9;  // the same position up to rounding

// A small, fast experiment: errors on, a short cap, the given extra lines.
ExperimentSettings settings_of(const std::string& extra, bool errors = true) {
  const std::string text =
      std::string("[placement]\nmax_iterations = 40\n[errors]\n") +
      (errors ? "sigma_loc_m = 0.05\nsigma_act_m = 0.02\n" : "sigma_loc_m = 0\nsigma_act_m = 0\n") +
      "[experiment]\ntrials = 2\nalgorithms = gd, bf, ura\n" + extra;
  return load_experiment_settings(common::IniConfig::from_string(text, "c.ini"), channel_sweep_extensions());
}

std::string error_of(const std::string& extra) {
  try {
    const ExperimentSettings s = settings_of(extra);
    for (const ExperimentExtension& e : channel_sweep_extensions()) {
      if (s.sweep(e.sweep)) e.load_values(s);
    }
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "accepted";
}

// Everything a record holds but its sweep name, value and seed.
void expect_same_run(const TrialRecord& a, const TrialRecord& b, const std::string& what) {
  EXPECT_EQ(a.algorithm, b.algorithm) << what;
  EXPECT_EQ(a.iterations, b.iterations) << what << " " << a.algorithm;
  EXPECT_EQ(a.status, b.status) << what << " " << a.algorithm;
  EXPECT_TRUE(a.final_m == b.final_m) << what << " " << a.algorithm;
  EXPECT_EQ(a.dist_total_m, b.dist_total_m) << what << " " << a.algorithm;
  EXPECT_EQ(a.final_icn, b.final_icn) << what << " " << a.algorithm;
  EXPECT_EQ(a.sum_rate_zf_bps_hz, b.sum_rate_zf_bps_hz) << what << " " << a.algorithm;
  EXPECT_EQ(a.mean_sinr_nv_db, b.mean_sinr_nv_db) << what << " " << a.algorithm;
}

TEST(ChannelSweeps, OffPointsWithoutErrors_EqualTheBuiltInSweepsRuns) {
  // Without errors no draw depends on the seed, so every sweep's "off" point is the same run.
  const ExperimentSettings s = settings_of(
      "sweeps = sigma_loc_m, rician_k_db, csi_snr_db, bs_antennas\nsigma_loc_values_m = 0\n"
      "rician_k_db_values = inf\ncsi_snr_db_values = inf\nbs_antennas_values = 16\n",
      false);
  const std::vector<TrialRecord> today = run_trial(s, kSweepSigmaLoc, 0, kTrial);
  for (const std::string& sweep : {kSweepRicianK, kSweepCsiSnr, kSweepBsAntennas}) {
    const std::vector<TrialRecord> channel = run_channel_sweep_trial(s, sweep, 0, kTrial);
    ASSERT_EQ(channel.size(), today.size());
    for (std::size_t i = 0; i < today.size(); ++i) {
      expect_same_run(today[i], channel[i], sweep);
      // The extra columns: the LoS values are the reported ones, and the stop test saw them too.
      const MetricValues& x = channel[i].extension;
      EXPECT_EQ(extension_columns(channel[i], channel_sweep_metrics()).size(), 4u);  // every one set
      EXPECT_EQ(x.at(kFinalIcnLos), channel[i].final_icn) << sweep;
      EXPECT_EQ(x.at(kFinalIcnMeasured), channel[i].final_icn) << sweep;
      EXPECT_EQ(x.at(kSumRateNvLosBpsHz), channel[i].sum_rate_nv_bps_hz) << sweep;
      EXPECT_EQ(x.at(kSumRateZfLosBpsHz), channel[i].sum_rate_zf_bps_hz) << sweep;
    }
  }
}

TEST(ChannelSweeps, FadingEvalDraws_ChangeOnlyTheReportedMetrics) {
  // GIVEN K = 10 dB with 4 or 9 evaluation draws
  const std::string sweep = "sweeps = rician_k_db\nrician_k_db_values = 10\n";
  const ExperimentSettings few = settings_of(sweep + "[channel]\nfading_eval_draws = 4\n");
  const ExperimentSettings more = settings_of(sweep + "[channel]\nfading_eval_draws = 9\n");
  const std::vector<TrialRecord> a = run_channel_sweep_trial(few, kSweepRicianK, 0, kTrial);
  const std::vector<TrialRecord> b = run_channel_sweep_trial(more, kSweepRicianK, 0, kTrial);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    // THEN the runs and the LoS metrics are the same; the faded means are not
    EXPECT_TRUE(a[i].final_m == b[i].final_m) << a[i].algorithm;
    EXPECT_EQ(a[i].iterations, b[i].iterations) << a[i].algorithm;
    EXPECT_EQ(extension_columns(a[i], channel_sweep_metrics()), extension_columns(b[i], channel_sweep_metrics()))
        << a[i].algorithm;
    EXPECT_NE(a[i].final_icn, b[i].final_icn) << a[i].algorithm;
  }
  // AND where the LoS channel is well conditioned (the URA's, ICN ~1) the faded ICN is below it:
  // scatter spreads equal singular values (of an ill-conditioned channel it may raise the ICN)
  int well_conditioned = 0;
  for (const TrialRecord& r : a) {
    if (r.extension.at(kFinalIcnLos) < 0.9) continue;
    ++well_conditioned;
    EXPECT_LT(r.final_icn, r.extension.at(kFinalIcnLos)) << r.algorithm;
  }
  EXPECT_GT(well_conditioned, 0);
}

TEST(ChannelSweeps, RicianK_ChangesTheMeasuringMoversAndTheReportedChannelOnly) {
  // GIVEN no errors (no draw depends on the point's seed), K = 10 dB against pure LoS
  const ExperimentSettings s = settings_of("sweeps = rician_k_db\nrician_k_db_values = 10, inf\n", false);
  const std::vector<TrialRecord> faded = run_channel_sweep_trial(s, kSweepRicianK, 0, kTrial);
  const std::vector<TrialRecord> los = run_channel_sweep_trial(s, kSweepRicianK, 1, kTrial);
  ASSERT_EQ(faded.size(), los.size());
  for (std::size_t i = 0; i < faded.size(); ++i) {
    EXPECT_TRUE(faded[i].start_m == los[i].start_m);
    if (faded[i].algorithm == "ura") {
      // THEN the URA (it measures nothing) lands on the same slots (it retries toward them
      // while the measured ICN stays low: rounding only), the same LoS metrics, and the faded
      // ICN below them
      EXPECT_LT((faded[i].final_m - los[i].final_m).cwiseAbs().maxCoeff(), kSameSlot_m);
      EXPECT_NEAR(faded[i].extension.at(kFinalIcnLos), los[i].final_icn, 1e-9);
      EXPECT_LT(faded[i].final_icn, los[i].final_icn);
    } else {
      // AND GD and BF, which see measured CSI, move differently
      EXPECT_FALSE(faded[i].final_m == los[i].final_m) << faded[i].algorithm;
    }
  }
}

TEST(ChannelSweeps, CsiNoise_ChangesTheRunsButReportsTheTrueChannel) {
  const ExperimentSettings s = settings_of("sweeps = csi_snr_db\ncsi_snr_db_values = 10, inf\n", false);
  const std::vector<TrialRecord> noisy = run_channel_sweep_trial(s, kSweepCsiSnr, 0, kTrial);
  const std::vector<TrialRecord> perfect = run_channel_sweep_trial(s, kSweepCsiSnr, 1, kTrial);
  const placement::ChannelModel model(s.placement.scenario);
  for (std::size_t i = 0; i < noisy.size(); ++i) {
    // THEN the metrics are those of the LoS channel at the final positions (no fading)
    const placement::LinkMetrics m =
        placement::evaluate_link(model.matrix(noisy[i].final_m), s.placement.scenario.noise_variance());
    EXPECT_EQ(noisy[i].final_icn, m.icn) << noisy[i].algorithm;
    EXPECT_EQ(noisy[i].extension.at(kFinalIcnLos), m.icn) << noisy[i].algorithm;
    // AND the measured ICN the stop test saw is below the true one
    EXPECT_LT(noisy[i].extension.at(kFinalIcnMeasured), noisy[i].final_icn) << noisy[i].algorithm;
    // AND the movers moved differently; the URA (no measurement) did not
    if (noisy[i].algorithm == "ura") {
      EXPECT_LT((noisy[i].final_m - perfect[i].final_m).cwiseAbs().maxCoeff(), kSameSlot_m);
    } else {
      EXPECT_FALSE(noisy[i].final_m == perfect[i].final_m) << noisy[i].algorithm;
    }
  }
}

TEST(ChannelSweeps, BsAntennas_RunsSixteenStreamsPerUavOnALargerArray) {
  // Without errors: the URA's slots are then exact (errors of 5 cm cost it ~0.1 of ICN).
  const ExperimentSettings s = settings_of("sweeps = bs_antennas\nbs_antennas_values = 64\n", false);
  for (const TrialRecord& r : run_channel_sweep_trial(s, kSweepBsAntennas, 0, kTrial)) {
    EXPECT_EQ(r.final_m.cols(), 16);
    if (r.algorithm == "ura") {
      EXPECT_GT(r.final_icn, 0.99);
    }
    // The single-user bound per UAV stream: 10 log10(64 SNR) = 28.06 dB in the far field.
    EXPECT_NEAR(r.mean_sinr_mf_db, 10.0 * std::log10(64.0 * 10.0), 0.1) << r.algorithm;
  }
}

TEST(ChannelSweeps, EveryRefusedValue_NamesFileLineAndKey) {
  for (const auto& k : channel_sweep_keys().keys()) {
    ASSERT_FALSE(k.refused.empty()) << k.key;
    for (const std::string& bad : k.refused) {
      // The sweep key is line 9 of the text, the swept values line 10.
      const std::string msg = error_of("sweeps = rician_k_db, csi_snr_db, bs_antennas\n" + k.key + " = " + bad + "\n");
      EXPECT_EQ(msg.rfind("c.ini:10: [experiment] " + k.key + ": ", 0), 0u) << bad << " -> " << msg;
    }
  }
}

TEST(ChannelSweeps, BadValues_StopBeforeAnyWorkNamingTheKey) {
  EXPECT_NE(error_of("sweeps = rician_k_db\nrician_k_db_values = 0, nan\n").find("[experiment] rician_k_db_values"),
            std::string::npos);
  EXPECT_NE(error_of("sweeps = csi_snr_db\ncsi_snr_db_values = -inf\n").find("[experiment] csi_snr_db_values"),
            std::string::npos);
  EXPECT_EQ(error_of("sweeps = bs_antennas\nbs_antennas_values = 16, 63\n"),
            "c.ini:10: [experiment] bs_antennas_values: 63 is not the antenna count of a square array n x n with n "
            "in [1, 64]");
  EXPECT_NE(error_of("sweeps = bs_antennas\nbs_antennas_values = 9\n").find("9 antennas < scenario.num_uavs = 16"),
            std::string::npos);
  EXPECT_NE(error_of("[channel]\ncoherence_iterations = 0\n").find("[channel] coherence_iterations"),
            std::string::npos);
  EXPECT_NE(error_of("[channel]\nrician_k_db = nan\n").find("[channel] rician_k_db"), std::string::npos);
  EXPECT_EQ(error_of("sweeps = rician_k_db, csi_snr_db, bs_antennas\n"), "accepted");  // the defaults
}

}  // namespace
}  // namespace losmimo::experiment
