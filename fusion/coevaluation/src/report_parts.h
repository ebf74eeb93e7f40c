#pragma once
// What the co-evaluation's report sources (report.cpp, matched_report.cpp,
// misalignment_report.cpp) share: number formats, row lookup, gnuplot data blocks and scripts.
#include <filesystem>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::coevaluation::report_detail {

// A dat() column that is the row's own field, not a metric.
inline constexpr experiment::MetricId kConvergedFraction{"converged_fraction"};

// v with `precision` decimals; an estimate as experiment::format_estimate writes it.
std::string fmt(double v, int precision = 2);
std::string fmt_estimate(const experiment::Estimate* e, int precision = 2);

// The algorithms of a sweep, in the order the rows have them.
std::vector<std::string> algorithms_of(const std::vector<experiment::SummaryRow>& rows, const std::string& sweep);
// The row of (sweep, value, algorithm), nullptr when absent.
const experiment::SummaryRow* find_row(const std::vector<experiment::SummaryRow>& rows, const std::string& sweep,
                                       double value, const std::string& algorithm);
// The algorithm's curve colour, "#rrggbb" (grey for one without its own).
const char* color(const std::string& algorithm);
// "k/n": trials that converged of the row's trials.
std::string converged(const experiment::SummaryRow& r);

// One gnuplot data block per algorithm: value, then mean and ci95 of each metric
// (kConvergedFraction is the row's own field, with ci 0).
std::string dat(const std::vector<experiment::SummaryRow>& rows, const std::string& sweep,
                const std::vector<std::string>& algorithms, const std::vector<experiment::MetricId>& columns);
// A pngcairo terminal writing `png`, grid on, key outside, 'nan' as missing.
std::string gp_header(const std::string& png, int width = 1000, int height = 650);
// Two curves per algorithm from data columns (2,3) solid and (4,5) dotted.
std::string two_metric_plot(const std::string& dat_file, const std::vector<std::string>& algorithms,
                            const std::string& solid, const std::string& dotted);
// Runs gnuplot on each stem when plots are on; returns warnings.
std::vector<std::string> render(const experiment::ExperimentSettings& s, const std::filesystem::path& dir,
                                const std::vector<std::string>& stems);

// gd_ekf against its matched Gaussian rows (gd_gauss_matched, gd_gauss_shape_matched,
// gd_gauss_split_matched) at every value of `sweep`: one table per matched row present, with
// the paired travel and iteration differences and a verdict; empty when none is present.
std::string matched_error_sections(const experiment::ExperimentSettings& s,
                                   const std::vector<experiment::SummaryRow>& rows, const std::string& sweep,
                                   const std::vector<double>& values);

}  // namespace losmimo::coevaluation::report_detail
