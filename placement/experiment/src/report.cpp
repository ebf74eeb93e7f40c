#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/gnuplot.h"
#include "losmimo/placement/experiment/capacity_claims.h"
#include "losmimo/placement/experiment/readings.h"
#include "losmimo/placement/experiment/report.h"

#include "losmimo/placement/experiment/shards.h"
#include "losmimo/placement/ura.h"
#include "report_parts.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <sstream>
#include <thread>

namespace losmimo::experiment {

namespace {
namespace fs = std::filesystem;

std::string fmt(double v, int precision = 3) { return common::format_fixed(v, precision); }

}  // namespace

const char* algorithm_color(const Algorithm& a) { return a.entry().plot_color.c_str(); }

std::vector<PaperValue> paper_values() {
  const std::string R = "random", GD = "gd", BF = "bf", URA = "ura";
  const std::string L = kSweepSigmaLoc;
  const std::string T = kSweepSigmaAct;
  return {
      {"Sec 4", "random start NV SINR [dB]", L, 0.0, R, metrics::kSinrNvDb, 0.3, 0.5},
      {"Sec 4", "random start ZF SINR [dB]", L, 0.0, R, metrics::kSinrZfDb, -5.5, 0.5},
      {"Sec 4", "MF SINR [dB]", L, 0.0, R, metrics::kSinrMfDb, 22.0, 0.5},
      {"Fig 1", "GD iterations to ICN 0.95", L, 0.0, GD, metrics::kIterationsToIcn095, 78, 5},
      {"Fig 1", "BF iterations to ICN 0.95", L, 0.0, BF, metrics::kIterationsToIcn095, 63, 5},
      {"Fig 2a", "GD distance to ICN 0.5 [m], sigma_loc 0", L, 0.0, GD, metrics::kDistToIcn050M, 5.0, 0.5},
      {"Fig 2a", "GD distance to ICN 0.5 [m], sigma_loc 0.18", L, 0.18, GD, metrics::kDistToIcn050M, 7.5, 0.5},
      {"Fig 2a", "GD distance to ICN 0.95 [m], sigma_loc 0", L, 0.0, GD, metrics::kDistToIcn095M, 15.3, 0.5},
      {"Fig 2a", "GD distance to ICN 0.95 [m], sigma_loc 0.18", L, 0.18, GD, metrics::kDistToIcn095M, 19.5, 0.5},
      {"Fig 2a", "BF distance to ICN 0.5 [m], sigma_loc 0", L, 0.0, BF, metrics::kDistToIcn050M, 8.3, 0.5},
      {"Fig 2a", "BF distance to ICN 0.95 [m], sigma_loc 0", L, 0.0, BF, metrics::kDistToIcn095M, 20.2, 0.5},
      {"Fig 2a", "URA distance to ICN 0.5 [m], sigma_loc 0", L, 0.0, URA, metrics::kDistToIcn050M, 10.3, 0.5},
      {"Fig 2a", "URA distance to ICN 0.95 [m], sigma_loc 0", L, 0.0, URA, metrics::kDistToIcn095M, 10.3, 0.5},
      {"Fig 2a", "URA distance to ICN 0.95 [m], sigma_loc 0.18", L, 0.18, URA, metrics::kDistToIcn095M, 30.0, 0.5},
      {"Fig 2b", "BF final NV SINR [dB], sigma_loc 0.18", L, 0.18, BF, metrics::kSinrNvDb, 22.0, 0.5},
      {"Fig 2b", "GD final NV SINR [dB], sigma_loc 0", L, 0.0, GD, metrics::kSinrNvDb, 20.5, 0.5},
      {"Fig 2b", "GD final NV SINR [dB], sigma_loc 0.18", L, 0.18, GD, metrics::kSinrNvDb, 16.5, 0.5},
      {"Fig 2b", "GD final ZF SINR [dB], sigma_loc 0.18", L, 0.18, GD, metrics::kSinrZfDb, 19.0, 0.5},
      {"Fig 2b", "URA final NV SINR [dB], sigma_loc 0", L, 0.0, URA, metrics::kSinrNvDb, 22.0, 0.5},
      {"Fig 2b", "URA final NV SINR [dB], sigma_loc 0.18", L, 0.18, URA, metrics::kSinrNvDb, 15.5, 0.5},
      {"Fig 2b", "URA final ZF SINR [dB], sigma_loc 0.18", L, 0.18, URA, metrics::kSinrZfDb, 22.0, 0.5},
      {"Fig 3", "GD final NV SINR [dB], sigma_act 0.18", T, 0.18, GD, metrics::kSinrNvDb, 15.5, 0.5},
      {"Fig 3", "GD final ZF SINR [dB], sigma_act 0.18", T, 0.18, GD, metrics::kSinrZfDb, 21.0, 0.5},
      {"Fig 3", "BF final NV SINR [dB], sigma_act 0", T, 0.0, BF, metrics::kSinrNvDb, 22.0, 0.5},
      {"Fig 3", "BF final NV SINR [dB], sigma_act 0.02", T, 0.02, BF, metrics::kSinrNvDb, 12.3, 0.5},
      {"Fig 3", "BF final NV SINR [dB], sigma_act 0.04", T, 0.04, BF, metrics::kSinrNvDb, 3.0, 0.5},
      {"Fig 3", "BF final NV SINR [dB], sigma_act 0.06", T, 0.06, BF, metrics::kSinrNvDb, 1.5, 0.5},
  };
}

std::string describe(const RunTiming& t) {
  std::ostringstream o;
  const auto threads = [](int n) { return std::to_string(n) + (n == 1 ? " thread" : " threads"); };
  if (t.shards <= 0) {
    o << threads(t.threads) << ", " << fmt(t.wall_s, 1) << " s wall";
    if (!t.isa.empty()) o << ", " << t.isa << " kernels";
    return o.str();
  }
  o << "merged from " << t.shards << (t.shards == 1 ? " shard" : " shards");
  if (t.timed_shards == t.shards) {
    o << " of "
      << (t.min_shard_threads == t.max_shard_threads
              ? threads(t.min_shard_threads)
              : std::to_string(t.min_shard_threads) + " to " + threads(t.max_shard_threads))
      << ": slowest " << fmt(t.slowest_shard_wall_s, 1) << " s wall, " << fmt(t.shards_wall_s, 1)
      << " s wall summed over shards";
  } else {
    o << " (their timing was not recorded)";
  }
  o << "; merge " << fmt(t.wall_s, 1) << " s";
  if (t.shard_isas.size() == 1) {
    o << "; " << t.shard_isas.begin()->first << " kernels";
  } else if (t.shard_isas.size() > 1) {
    o << "; kernels " << isa_counts(t.shard_isas, "shard");
  }
  return o.str();
}

namespace {

// report.md's opening: trial count, seed, timing, how values are compared, the figures.
std::string report_header(const ExperimentSettings& s, const std::vector<std::string>& stems, const RunTiming& timing) {
  std::ostringstream md;
  md << "# losmimo-experiment report\n\n"
     << s.trials << " random starts per sweep point, seed " << s.seed << ", " << describe(timing)
     << ". Configuration: `config.ini`. Means with 95% confidence half-widths "
     << "(Student t) over the trials where the quantity is defined (n). A value agrees with the "
     << "paper when it is within the CI plus the resolution at which the paper's plot can be read "
     << "(0.5 dB, 0.5 m, 5 iterations).\n\n";
  if (!stems.empty()) {
    md << "Figures:";
    for (const std::string& stem : stems) md << " ![" << stem << "](" << stem << ".png)";
    md << "\n\n";
  }
  return md.str();
}

// How many paper values the table judged, and how many of those agree.
struct Agreement {
  int values = 0, not_run = 0, not_judged = 0, judged = 0, agree = 0;
};

// The line under the table: the agreement count with its sample size, and why a small sample
// agrees more easily.
std::string agreement_line(const ExperimentSettings& s, const Agreement& a) {
  std::ostringstream md;
  md << "\n**" << a.agree << " of " << a.judged << " judged values agree** with the paper, from " << s.trials
     << (s.trials == 1 ? " start" : " starts") << " per point";
  if (a.not_run > 0) md << "; " << a.not_run << " of the " << a.values << " not run here";
  if (a.not_judged > 0) md << "; " << a.not_judged << " not judged (a single trial has no confidence interval)";
  md << ". A value agrees within its 95% CI plus the plot's resolution, and the CI narrows as 1 / sqrt(n): "
     << "with fewer starts more values agree only because their intervals are wide";
  if (s.trials < 500) md << " (the paper's figures use 500 starts; this run has " << s.trials << ")";
  md << ".\n";
  return md.str();
}

// The table of paper values against the measured means; each disagreement, with its Why line
// from the readings, goes to `differences`. A value from one trial has no CI: shown, not judged.
std::string paper_table(const ExperimentSettings& s, const std::vector<SummaryRow>& rows,
                        const ReadingResults& readings, std::vector<std::string>& differences, Agreement& count) {
  std::ostringstream md;
  md << "| # | figure | quantity | paper | measured | 95% CI | n | agrees |\n|---|---|---|---|---|---|---|---|\n";
  int number = 0;
  for (const PaperValue& p : paper_values()) {
    ++number;
    ++count.values;
    if (!s.sweep(p.sweep)) {
      ++count.not_run;
      continue;
    }
    const SummaryRow* row = report_parts::find_row(rows, p.sweep, p.value, p.algorithm);
    const Estimate* e = row ? row->metric(p.metric) : nullptr;
    // Without milestone columns, Fig 1's counts are the runs' iterations (equal when they stop at 0.95).
    if (row && !e && p.metric == metrics::kIterationsToIcn095) e = row->metric(metrics::kIterations);
    const std::string head =
        "| " + std::to_string(number) + " | " + p.figure + " | " + p.quantity + " | " + fmt(p.paper, 1) + " | ";
    if (!e) {
      md << head << "not run | | | |\n";
      ++count.not_run;
      continue;
    }
    const std::string label =
        "#" + std::to_string(number) + " " + p.figure + ", " + p.quantity + ": paper " + fmt(p.paper, 1);
    if (row->trials < 2 || e->n == 1 || (e->n > 1 && !std::isfinite(e->ci95))) {
      md << head << (e->n > 0 ? fmt(e->mean, 2) : "never reached in " + std::to_string(row->trials) + " trial(s)")
         << " | undefined | " << e->n << " | not judged (no CI) |\n";
      ++count.not_judged;
      continue;
    }
    ++count.judged;
    if (e->n == 0) {
      md << head << "never reached in " << row->trials << " trials | | 0 | **no** |\n";
      differences.push_back(label + ", never reached here within the iteration cap. Why: " +
                            explain_difference(p, number, readings) + ".");
      continue;
    }
    const bool agreement = agrees(*e, p);
    if (agreement) ++count.agree;
    const double ci = e->ci95;
    md << head << fmt(e->mean, 2) << " | ±" << fmt(ci, 2) << " | " << e->n << " | " << (agreement ? "yes" : "**no**")
       << " |\n";
    if (!agreement) {
      differences.push_back(label + ", measured " + fmt(e->mean, 2) + " ± " + fmt(ci, 2) +
                            ". Why: " + explain_difference(p, number, readings) + ".");
    }
  }
  return md.str();
}

// The abstract's claims: capacity ratio and SINR gain over random placement at the first
// sigma_loc point (empty without that sweep or a random baseline).
std::string abstract_claims(const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  const SweepPoints* loc = s.sweep(kSweepSigmaLoc);
  const SummaryRow* random0 =
      loc ? report_parts::find_row(rows, kSweepSigmaLoc, loc->values.front(), "random") : nullptr;
  if (!random0) return "";
  std::ostringstream md;
  md << "\n## The abstract's claims (at sigma_loc = " << loc->values.front() << ")\n\n"
     << "| algorithm | NV sum rate / random | NV SINR gain over random [dB] |\n|---|---|---|\n";
  const Estimate* r_rate = random0->metric(metrics::kSumRateNvBpsHz);
  const Estimate* r_sinr = random0->metric(metrics::kSinrNvDb);
  for (const Algorithm& a : s.algorithms) {
    if (a == Algorithm::kRandom) continue;
    const SummaryRow* row = report_parts::find_row(rows, kSweepSigmaLoc, loc->values.front(), to_string(a));
    if (!row) continue;
    md << "| " << to_string(a) << " | " << fmt(row->metric(metrics::kSumRateNvBpsHz)->mean / r_rate->mean, 2)
       << "x (paper: up to 6x) | " << fmt(row->metric(metrics::kSinrNvDb)->mean - r_sinr->mean, 1)
       << " (paper: >= 15) |\n";
  }
  return md.str();
}

}  // namespace

ReportOutcome write_figures_and_report(const ExperimentSettings& s, const ExperimentExtensions& extensions,
                                       const ExperimentResults& results, const std::vector<SummaryRow>& rows,
                                       const std::string& out_dir, const RunTiming& timing) {
  ReportOutcome outcome;
  const fs::path dir(out_dir);
  const std::vector<std::string> stems = report_parts::write_builtin_figures(s, results, rows, out_dir);
  if (s.plots) {
    for (std::string& w : common::render_gnuplot(
             dir.string(), stems,
             "the fig*.gp scripts were written but not rendered (apt-get install gnuplot-nox, then run gnuplot "
             "fig*.gp in the output folder)")) {
      outcome.warnings.push_back(std::move(w));
    }
  }
  for (const ExperimentExtension& e : extensions) {
    if (!s.sweep(e.sweep) || !e.figures) continue;
    for (std::string& w : e.figures(s, rows, out_dir)) outcome.warnings.push_back(std::move(w));
  }

  std::ostringstream md;
  md << report_header(s, stems, timing);
  std::vector<std::string> differences;
  const bool builtin = s.sweep(kSweepSigmaLoc) || s.sweep(kSweepSigmaAct);
  // The readings' paired runs (none unless [experiment] readings): the Why lines' measurements.
  const ReadingResults readings =
      builtin ? measure_readings(
                    s, extensions,
                    s.threads > 0 ? s.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())))
              : ReadingResults{};
  if (!readings.empty()) {
    common::write_stream_atomically((dir / "readings.csv").string(),
                                    [&](std::ostream& o) { write_readings_csv(o, readings); });
  }
  Agreement agreement;
  if (builtin) md << paper_table(s, rows, readings, differences, agreement) << agreement_line(s, agreement);
  md << abstract_claims(s, rows);
  if (builtin) md << "\n## Differences larger than the confidence interval\n\n";
  if (builtin && differences.empty())
    md << (agreement.judged == 0 ? "None judged: no paper value was measured "
                                   "with a confidence interval in this run.\n"
                                 : "None.\n");
  for (const std::string& d : differences) md << "- " << d << "\n";
  if (!readings.empty()) md << "\n" << readings_section(readings);
  for (const ExperimentExtension& e : extensions) {
    if (s.sweep(e.sweep) && e.report_section) md << "\n" << e.report_section(s, rows);
  }
  if (s.capacity_columns) md << "\n" << capacity_claims_report_section(s, rows);
  common::write_file_atomically((dir / "report.md").string(), md.str());
  return outcome;
}

}  // namespace losmimo::experiment
