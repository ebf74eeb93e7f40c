#pragma once
// Pieces shared by report.cpp (report.md) and report_figures.cpp (the built-in sweeps' figures).

#include <string>
#include <vector>

#include "losmimo/placement/experiment/engine.h"
#include "losmimo/placement/experiment/metrics.h"
#include "losmimo/placement/experiment/summary.h"

namespace losmimo::experiment::report_parts {

// The row of (sweep, value, algorithm), nullptr if absent.
const SummaryRow* find_row(const std::vector<SummaryRow>& rows, const std::string& sweep, double value,
                           const std::string& algorithm);

// Gnuplot data block per algorithm of a sweep: value and (mean, ci) of the given metrics.
std::string sweep_dat(const std::vector<SummaryRow>& rows, const std::string& sweep,
                      const std::vector<Algorithm>& algorithms, const std::vector<MetricId>& metrics);

// The opening lines of every figure script: terminal, output, title, axis labels, grid.
std::string gp_header(const std::string& png, const std::string& title, const std::string& xlabel,
                      const std::string& ylabel);

// Writes the built-in sweeps' figure data and scripts (Fig 1 from the traced runs, the path
// figure, Fig 2a, Fig 2b, Fig 3, each only when its sweep or runs exist) into out_dir and
// returns their stems in report.md's order, for rendering.
std::vector<std::string> write_builtin_figures(const ExperimentSettings& settings, const ExperimentResults& results,
                                               const std::vector<SummaryRow>& rows, const std::string& out_dir);

}  // namespace losmimo::experiment::report_parts
