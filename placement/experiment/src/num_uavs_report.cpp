// The swarm-size sweep's figures and report.md section (num_uavs_sweep.h).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/gnuplot.h"
#include "losmimo/placement/experiment/metrics.h"
#include "losmimo/placement/experiment/num_uavs_sweep.h"
#include "losmimo/placement/experiment/report.h"

namespace losmimo::experiment {

namespace {
namespace fs = std::filesystem;

// The figure's panels: metric, title, in num_uavs.dat's column order.
const std::vector<std::pair<MetricId, const char*>>& panels() {
  static const std::vector<std::pair<MetricId, const char*>> kPanels = {
      {metrics::kFinalIcn, "ICN at the final positions"},
      {metrics::kSumRateZfBpsHz, "ZF sum rate [bit/s/Hz]"},
      {metrics::kSumRateNvBpsHz, "NV sum rate [bit/s/Hz]"},
      {metrics::kDistTotalM, "distance flown per UAV [m] (placement and BF probes)"},
      {metrics::kIterations, "iterations"},
  };
  return kPanels;
}

std::string fmt(double v, int decimals = 2) { return std::isfinite(v) ? common::format_fixed(v, decimals) : "n/a"; }
std::string csv(double v) { return common::format_g(v, common::kCsvDigits); }

const SummaryRow* find_row(const std::vector<SummaryRow>& rows, double value, const std::string& algorithm) {
  for (const SummaryRow& r : rows) {
    if (r.sweep == kSweepNumUavs && r.algorithm == algorithm && r.value == value) return &r;
  }
  return nullptr;
}

std::string cell(const SummaryRow* row, MetricId id, int decimals) {
  return format_estimate(row ? row->metric(id) : nullptr, decimals);
}

double mean_of(const SummaryRow* row, MetricId id) {
  const Estimate* e = row ? row->metric(id) : nullptr;
  return e && e->n > 0 ? e->mean : std::nan("");
}

// Seconds per iteration of (point, algorithm) in this process, NaN when untimed or 0 iterations.
double seconds_per_iteration(const NumUavsTiming& timing, int point, const Algorithm& a) {
  const std::unique_ptr<NumUavsTiming::Entry> e = timing.find(point, to_string(a));
  return e && e->iterations > 0 ? e->wall_s / static_cast<double>(e->iterations) : std::nan("");
}

std::string plot_lines(const ExperimentSettings& s, const std::string& dat, int column) {
  std::ostringstream g;
  for (std::size_t i = 0; i < s.algorithms.size(); ++i) {
    g << (i ? ", " : "") << "'" << dat << "' index " << i << " using 1:" << column << ":" << column + 1
      << " with yerrorlines lw 2 lc rgb '" << algorithm_color(s.algorithms[i]) << "' title '"
      << to_string(s.algorithms[i]) << "' noenhanced";
  }
  return g.str();
}

// The x range of a log2 axis over the sweep's points, half a factor of 2 beyond each end (also
// for a single point, where gnuplot finds no range of its own).
std::string log_xrange(const SweepPoints& p) {
  const auto [lo, hi] = std::minmax_element(p.values.begin(), p.values.end());
  return "set xrange [" + csv(*lo / std::sqrt(2.0)) + ":" + csv(*hi * std::sqrt(2.0)) + "]\n";
}

// num_uavs.dat / .gp: the panels' means and CIs against Nr (reproducible).
void write_metrics_figure(const ExperimentSettings& s, const SweepPoints& p, const std::vector<SummaryRow>& rows,
                          const fs::path& dir) {
  std::ostringstream dat;
  for (const Algorithm& a : s.algorithms) {
    dat << "# algorithm " << to_string(a) << ": num_uavs";
    for (const auto& [m, title] : panels()) dat << " " << m.name << "_mean " << m.name << "_ci95";
    dat << " converged_fraction\n";
    for (const double v : p.values) {
      const SummaryRow* r = find_row(rows, v, to_string(a));
      if (!r) continue;
      dat << csv(v);
      for (const auto& [m, title] : panels()) {
        const Estimate* e = r->metric(m);
        dat << " " << csv(e && std::isfinite(e->mean) ? e->mean : std::nan("")) << " "
            << csv(e && std::isfinite(e->ci95) ? e->ci95 : 0.0);
      }
      dat << " " << csv(r->converged_fraction) << "\n";
    }
    dat << "\n\n";
  }
  common::write_file_atomically((dir / "num_uavs.dat").string(), dat.str());
  std::ostringstream g;
  g << "set terminal pngcairo size 1300,1200 enhanced font 'Sans,10'\nset output 'num_uavs.png'\n"
    << "set grid\nset key top left font ',9'\nset datafile missing 'nan'\nset logscale x 2\n"
    << log_xrange(p) << "set xlabel 'UAVs N_r'\nset multiplot layout 3,2 title 'num\\_uavs: means and 95% CI over "
    << s.trials << " trials'\n";
  for (std::size_t m = 0; m < panels().size(); ++m) {
    g << "set title '" << panels()[m].second << "'\nset ylabel ''\n"
      << (m == 0 ? "set yrange [0:1.05]\n" : "set autoscale y\n") << "plot "
      << plot_lines(s, "num_uavs.dat", 2 + 2 * static_cast<int>(m)) << "\n";
  }
  g << "unset multiplot\n";
  common::write_file_atomically((dir / "num_uavs.gp").string(), g.str());
}

// num_uavs_timing.dat / .gp: seconds per iteration against Nr (this process's runs; not
// reproducible, hence not a .csv and not in the summaries).
void write_timing_figure(const ExperimentSettings& s, const SweepPoints& p, const NumUavsTiming& timing,
                         const fs::path& dir) {
  std::ostringstream dat;
  for (const Algorithm& a : s.algorithms) {
    dat << "# algorithm " << to_string(a) << ": num_uavs seconds_per_iteration\n";
    for (std::size_t i = 0; i < p.values.size(); ++i) {
      dat << csv(p.values[i]) << " " << csv(seconds_per_iteration(timing, static_cast<int>(i), a)) << "\n";
    }
    dat << "\n\n";
  }
  common::write_file_atomically((dir / "num_uavs_timing.dat").string(), dat.str());
  std::ostringstream g;
  g << "set terminal pngcairo size 900,600 enhanced font 'Sans,10'\nset output 'num_uavs_timing.png'\n"
    << "set grid\nset key top left\nset datafile missing 'nan'\nset logscale xy\n"
    << log_xrange(p) << "set title 'wall time per iteration (this run, " << s.trials << " trials, not reproducible)'\n"
    << "set xlabel 'UAVs N_r'\nset ylabel 's per iteration'\nplot ";
  for (std::size_t i = 0; i < s.algorithms.size(); ++i) {
    g << (i ? ", " : "") << "'num_uavs_timing.dat' index " << i << " using 1:2 with linespoints lw 2 lc rgb '"
      << algorithm_color(s.algorithms[i]) << "' title '" << to_string(s.algorithms[i]) << "' noenhanced";
  }
  common::write_file_atomically((dir / "num_uavs_timing.gp").string(), g.str() + "\n");
}

std::string results_table(const ExperimentSettings& s, const SweepPoints& p, const NumUavsSweepSettings& c,
                          const std::vector<SummaryRow>& rows) {
  std::ostringstream o;
  o << "| Nr | Nt | algorithm | ICN | ZF sum rate | NV sum rate | MF SINR [dB] | flown per UAV [m] | iterations "
       "| converged |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const double v : p.values) {
    const int n = static_cast<int>(v);
    const int nt = num_uavs_scenario(s.placement.scenario, c.array, n).num_bs_antennas();
    for (const Algorithm& a : s.algorithms) {
      const SummaryRow* r = find_row(rows, v, to_string(a));
      o << "| " << n << " | " << nt << " | " << to_string(a) << " | ";
      if (!r) {
        o << (runs_at(c, a, n) ? "no rows" : "not run (Nr > num_uavs_cap_max)") << " | | | | | | |\n";
        continue;
      }
      o << cell(r, metrics::kFinalIcn, 3) << " | " << cell(r, metrics::kSumRateZfBpsHz, 1) << " | "
        << cell(r, metrics::kSumRateNvBpsHz, 1) << " | " << cell(r, metrics::kSinrMfDb, 1) << " | "
        << cell(r, metrics::kDistTotalM, 2) << " | " << cell(r, metrics::kIterations, 0) << " | "
        << fmt(r->converged_fraction, 2) << " |\n";
    }
  }
  return o.str();
}

// BF's convergence against Nr: converged share, ICN, iterations against the cap, probe flights.
std::string bf_convergence(const ExperimentSettings& s, const SweepPoints& p, const std::vector<SummaryRow>& rows) {
  if (std::find(s.algorithms.begin(), s.algorithms.end(), Algorithm::kBf) == s.algorithms.end()) return "";
  const int cap = run_options_of(s.placement, Algorithm::kBf, s.placement.run).max_iterations;
  std::ostringstream o;
  o << "\nBF's convergence (iteration cap " << cap << ", target ICN "
    << common::format_double(run_options_of(s.placement, Algorithm::kBf, s.placement.run).target_icn)
    << "; each iteration every UAV flies 6 probes and measures 7 candidates, so 6 Nr probe flights per "
       "iteration):\n\n| Nr | converged | ICN | iterations | iterations / cap | probe flights per iteration | "
       "probe distance per UAV [m] |\n|---|---|---|---|---|---|---|\n";
  for (const double v : p.values) {
    const SummaryRow* r = find_row(rows, v, to_string(Algorithm::kBf));
    if (!r) continue;
    o << "| " << static_cast<int>(v) << " | " << fmt(r->converged_fraction, 2) << " | "
      << cell(r, metrics::kFinalIcn, 3) << " | " << cell(r, metrics::kIterations, 0) << " | "
      << fmt(mean_of(r, metrics::kIterations) / cap, 2) << " | " << 6 * static_cast<int>(v) << " | "
      << cell(r, metrics::kProbeDistM, 1) << " |\n";
  }
  return o.str();
}

std::string timing_table(const ExperimentSettings& s, const SweepPoints& p, const NumUavsTiming& timing) {
  std::ostringstream o;
  o << "\nTiming (this process's runs, wall clock on its threads: not reproducible, so not in trials.csv or "
       "summary.csv; num_uavs_timing.png):\n\n| Nr | algorithm | runs timed | s per iteration | s per run "
       "|\n|---|---|---|---|---|\n";
  bool any = false;
  for (std::size_t i = 0; i < p.values.size(); ++i) {
    for (const Algorithm& a : s.algorithms) {
      const std::unique_ptr<NumUavsTiming::Entry> e = timing.find(static_cast<int>(i), to_string(a));
      if (!e) continue;
      any = true;
      o << "| " << static_cast<int>(p.values[i]) << " | " << to_string(a) << " | " << e->runs << " | "
        << (e->iterations > 0 ? common::format_g(e->wall_s / static_cast<double>(e->iterations), 3) : "n/a") << " | "
        << common::format_g(e->wall_s / e->runs, 3) << " |\n";
    }
  }
  if (!any) return "\nTiming: none recorded by this process (a merged or fully resumed run).\n";
  return o.str();
}

}  // namespace

std::vector<std::string> write_num_uavs_figure(const ExperimentSettings& s, const std::vector<SummaryRow>& rows,
                                               const NumUavsTiming& timing, const std::string& out_dir) {
  const SweepPoints* p = s.sweep(kSweepNumUavs);
  if (!p) return {};
  const fs::path dir(out_dir);
  write_metrics_figure(s, *p, rows, dir);
  write_timing_figure(s, *p, timing, dir);
  if (!s.plots) return {};
  return common::render_gnuplot(dir.string(), {"num_uavs", "num_uavs_timing"},
                                "num_uavs.gp and num_uavs_timing.gp were written but not rendered (apt-get install "
                                "gnuplot-nox, then run gnuplot on them in the output folder)");
}

std::string num_uavs_report_section(const ExperimentSettings& s, const std::vector<SummaryRow>& rows,
                                    const NumUavsTiming& timing) {
  const SweepPoints* p = s.sweep(kSweepNumUavs);
  if (!p) return "";
  const NumUavsSweepSettings c = load_num_uavs_sweep_settings(s);
  const placement::Scenario& sc = s.placement.scenario;
  std::ostringstream o;
  o << "## Swarm size (num_uavs)\n\n"
    << "![num_uavs](num_uavs.png) ![num_uavs_timing](num_uavs_timing.png)\n\n"
    << "BS array: " << to_string(c.array)
    << (c.array == NumUavsArray::kSquare
            ? " (n x n, the smallest n with n^2 >= Nr)"
            : " (the configured " + std::to_string(sc.bs_rows) + " x " + std::to_string(sc.bs_cols) + ")")
    << "; antenna spacing " << common::format_double(sc.bs_spacing_m) << " m, "
    << common::format_double(sc.carrier_hz / 1e9) << " GHz, R = " << common::format_double(sc.range_m()) << " m, SNR "
    << common::format_double(sc.snr_db) << " dB per link; start cube " << common::format_double(sc.cube_side_m)
    << " m; sigma_loc " << common::format_double(s.placement.errors.sigma_loc_m) << " m, sigma_act "
    << common::format_double(s.placement.errors.sigma_act_m) << " m; " << s.trials
    << " trials per point; cap runs up to Nr = " << c.cap_max_uavs
    << " (num_uavs_cap_max). Means ± 95% CI; ICN and sum rates at the final positions.\n\n"
    << results_table(s, *p, c, rows) << bf_convergence(s, *p, rows) << timing_table(s, *p, timing);
  return o.str();
}

}  // namespace losmimo::experiment
