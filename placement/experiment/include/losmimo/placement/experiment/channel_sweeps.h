#pragma once
// Three sweeps beyond the paper's LoS channel (placement/channel_conditions.h), added to
// `losmimo-experiment` as extensions (extension.h), off unless listed in [experiment] sweeps:
//   rician_k_db   the Rician K-factor [dB] (inf: pure LoS), [experiment] rician_k_db_values
//   csi_snr_db    the CSI estimation SNR [dB] (inf: perfect CSI), [experiment] csi_snr_db_values
//   bs_antennas   the BS array size n x n (16, 64, 256 antennas) at the configured swarm size,
//                 [experiment] bs_antennas_values (perfect squares)
// At every point each of the [experiment] algorithms runs from trial t's start (common random
// numbers: the same start, the same scatter draws scaled by b(K), the same evaluation draws for
// every algorithm and point). The other [channel] keys apply as configured; the swept key is
// replaced by the point's value.
//
// Extra columns (trials.csv, summary.csv): channel_sweep_metrics() below, on top of the usual
// ones (which with fading are the true channel's means over [channel] fading_eval_draws scatter
// draws at the final positions).
// Each sweep writes <sweep>.png (.dat, .gp) and a report.md section comparing GD, BF and both
// URAs, with a sentence on each claim of the follow-up paper (Hanna, Krijestorac, Cabric, JSAC
// 2021; only its abstract was available) that the numbers support or contradict.

#include <limits>
#include <string>
#include <vector>

#include "losmimo/placement/common/key_table.h"
#include "losmimo/placement/experiment/extension.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::experiment {

inline const std::string kSweepRicianK = "rician_k_db";
inline const std::string kSweepCsiSnr = "csi_snr_db";
inline const std::string kSweepBsAntennas = "bs_antennas";

struct ChannelSweepSettings {
  std::vector<double> rician_k_db_values = {0, 5, 10, 15, 20, 25, 30, std::numeric_limits<double>::infinity()};
  std::vector<double> csi_snr_db_values = {0, 10, 20, 30, 40, std::numeric_limits<double>::infinity()};
  std::vector<int> bs_antennas_values = {16, 64, 256};
};

// The sweep points' keys ([experiment] rician_k_db_values, csi_snr_db_values, bs_antennas_values).
const common::KeyTable<ChannelSweepSettings>& channel_sweep_keys();
// Reads and checks them from settings.config (common::InputError naming the key): values in the
// [channel] ranges, antenna counts perfect squares of a side in [1, 64], and at least num_uavs
// when a URA algorithm runs.
ChannelSweepSettings load_channel_sweep_settings(const ExperimentSettings& settings);

// The extra metrics, declared like the built-in ones (metrics.h).
inline constexpr ExtensionMetric kFinalIcnLos{
    {"final_icn_los"}, "", "ICN of the LoS channel at the final positions (the geometry)"};
inline constexpr ExtensionMetric kFinalIcnMeasured{
    {"final_icn_measured"}, "", "the master's last measured ICN (what the stop test saw)"};
inline constexpr ExtensionMetric kSumRateNvLosBpsHz{
    {"sum_rate_nv_los_bps_hz"}, "bit/s/Hz", "NV sum rate of the LoS channel at the final positions"};
inline constexpr ExtensionMetric kSumRateZfLosBpsHz{
    {"sum_rate_zf_los_bps_hz"}, "bit/s/Hz", "ZF sum rate of the LoS channel at the final positions"};
// Their table, in column order.
const ExtensionMetrics& channel_sweep_metrics();

// Trial `trial` at point `point` of one of the three sweeps: the settings' algorithms.
std::vector<TrialRecord> run_channel_sweep_trial(const ExperimentSettings& settings, const std::string& sweep,
                                                 int point, int trial);

// <sweep>.png with its .dat and .gp (warnings if gnuplot is missing), and the report section.
std::vector<std::string> write_channel_sweep_figure(const ExperimentSettings& settings, const std::string& sweep,
                                                    const std::vector<SummaryRow>& rows, const std::string& out_dir);
std::string channel_sweep_report_section(const ExperimentSettings& settings, const std::string& sweep,
                                         const std::vector<SummaryRow>& rows);

// The three sweeps as extensions, for run_experiment_app next to fusion's.
ExperimentExtensions channel_sweep_extensions();

}  // namespace losmimo::experiment
