#pragma once
// Figures (gnuplot) and report.md of an experiment run.
//   fig1a.png  ICN vs iteration (GD, BF; Fig 1 traced runs)
//   fig1b.png  SINR NV / ZF / MF vs iteration
//   fig2a.png  mean distance per UAV to ICN 0.5 (solid) and 0.95 (dotted) vs sigma_loc
//   fig2b.png  final SINR (NV solid, ZF dotted, MF dash-dot) vs sigma_loc, random start too
//   fig3.png   final SINR vs sigma_act
// Each figure's data (.dat) and script (.gp) sit beside it; gnuplot (Debian gnuplot-nox) is run
// when it is on PATH, else the scripts are left for the user and a warning says so.
// report.md puts every value read from the paper's figures beside the measured mean and its
// 95% confidence interval; a value agrees when |measured - paper| <= CI + the resolution at
// which it can be read off the paper's plot; every other difference gets a line saying why.

#include <string>
#include <vector>

#include "losmimo/placement/experiment.h"

namespace losmimo::placement {

struct ReportOutcome {
  std::vector<std::string> warnings;
};

// Figures of sweeps that did not run are skipped; extensions add their figures and sections.
ReportOutcome write_figures_and_report(const ExperimentSettings& settings, const ExperimentExtensions& extensions,
                                       const ExperimentResults& results,
                                       const std::vector<SummaryRow>& summary, const std::string& out_dir,
                                       double wall_s, int threads);

// One paper-vs-measured comparison line of report.md.
struct PaperValue {
  std::string figure;    // "Fig 2a"
  std::string quantity;  // human label
  std::string sweep;
  double value;          // sweep point
  std::string algorithm;
  std::string metric;    // a summary_metric_names() entry
  double paper;
  double resolution;     // how precisely the value can be read off the paper's figure
  std::string why;       // the explanation used if the measured value differs
};
std::vector<PaperValue> paper_values();

}  // namespace losmimo::placement
