#pragma once
// Figures and report.md sections of the co-evaluation sweeps (coevaluation.h), the
// ExperimentExtension figures / report_section hooks.
//
// beacon_noise_m, against the beacon-only cross-range error [m], one curve per algorithm:
//   coeval_sinr.png    final SINR of stream 1 (NV solid, ZF dotted)
//   coeval_travel.png  mean distance per UAV to ICN 0.5 (solid) and 0.95 (dotted)
//   coeval_rmse.png    localization RMSE (lateral solid, 3-D dotted; beacon-only lateral
//                      dashed black) and average NEES (3 = consistent)
// beacon_outage, against the number of UAVs without beacon:
//   outage.png         converged fraction, travel to ICN 0.95 and in total, BF fallback fraction
// bs_misalignment_rad, against the misalignment [mrad]:
//   misalignment.png   lateral and shape RMSE (log scale), final NV SINR, travel to ICN 0.95
// Each .png has its .dat and .gp beside it; gnuplot runs when [experiment] plots is on and
// gnuplot is on PATH, else a warning says the scripts were left.
// Means are over trials where the quantity is defined, with Student-t 95% half-widths.
// The report's 1 dB target check (GD + EKF + Ceres final NV SINR at the largest beacon noise
// against beacon noise 0): loss = mean(0) - mean(max), its half-width sqrt(ci0^2 + ci_max^2)
// (the two points' CIs combined as if independent: the summary keeps no per-trial pairs, and
// the pairing only makes the true interval narrower).

#include <string>
#include <vector>

#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::coevaluation {

std::vector<std::string> write_beacon_noise_figures(const experiment::ExperimentSettings& settings,
                                                    const std::vector<experiment::SummaryRow>& rows,
                                                    const std::string& out_dir);
std::string beacon_noise_report_section(const experiment::ExperimentSettings& settings,
                                        const std::vector<experiment::SummaryRow>& rows);

std::vector<std::string> write_outage_figures(const experiment::ExperimentSettings& settings,
                                              const std::vector<experiment::SummaryRow>& rows,
                                              const std::string& out_dir);
std::string outage_report_section(const experiment::ExperimentSettings& settings,
                                  const std::vector<experiment::SummaryRow>& rows);

std::vector<std::string> write_misalignment_figures(const experiment::ExperimentSettings& settings,
                                                    const std::vector<experiment::SummaryRow>& rows,
                                                    const std::string& out_dir);
// Its table, the matched-error comparisons at every misalignment and error_measure_section.
std::string misalignment_report_section(const experiment::ExperimentSettings& settings,
                                        const std::vector<experiment::SummaryRow>& rows);

// "Which localization error predicts capacity": over the (value, algorithm) means of the
// co-evaluation sweeps in `rows` (beacon_noise_m, bs_misalignment_rad, beacon_outage; each alone
// and all together), Spearman's (and Pearson's) correlation of final ICN, final NV SINR and travel
// to ICN 0.95 with the lateral RMSE and with the shape RMSE, and which correlates more strongly.
// Empty without such rows. The misalignment section has it, else the beacon_noise_m one.
std::string error_measure_section(const std::vector<experiment::SummaryRow>& rows);

}  // namespace losmimo::coevaluation
