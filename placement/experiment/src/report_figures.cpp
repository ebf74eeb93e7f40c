// The built-in sweeps' figures: Fig 1a/1b (traces), Fig 2a (distances), Fig 2b and Fig 3 (final
// SINR), and the path figure (paths.cpp), as .dat data and .gp scripts (report.h).
#include <cmath>
#include <filesystem>
#include <sstream>
#include <tuple>

#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/experiment/paths.h"
#include "losmimo/placement/experiment/report.h"
#include "report_parts.h"

namespace losmimo::experiment::report_parts {

namespace {
namespace fs = std::filesystem;

// Fig 1: ICN (1a) and SINR (1b) against iteration of trial 0's traced runs; their stems.
std::vector<std::string> write_fig1(const std::vector<TracedRun>& traces, const fs::path& dir) {
  if (traces.empty()) return {};
  std::ostringstream dat;
  std::vector<Algorithm> traced;
  for (const TracedRun& t : traces) {
    if (t.trial != 0 || !t.fig1()) continue;
    traced.push_back(t.algorithm);
    dat << "# " << to_string(t.algorithm) << ": iteration icn sinr_nv_db sinr_zf_db sinr_mf_db\n";
    for (const placement::IterationRecord& r : t.result.trace) {
      dat << r.iteration << " " << r.icn << " " << r.sinr_nv_db << " " << r.sinr_zf_db << " " << r.sinr_mf_db << "\n";
    }
    dat << "\n\n";
  }
  common::write_file_atomically((dir / "fig1.dat").string(), dat.str());
  std::ostringstream a, b;
  a << gp_header("fig1a.png", "Fig 1a: ICN against iteration (no errors)", "iteration", "ICN")
    << "set yrange [0:1]\nplot ";
  b << gp_header("fig1b.png", "Fig 1b: SINR of stream 1 against iteration (NV solid, ZF dashed, MF dash-dot)",
                 "iteration", "SINR [dB]")
    << "plot ";
  for (std::size_t i = 0; i < traced.size(); ++i) {
    const std::string c = algorithm_color(traced[i]);
    const std::string name = to_string(traced[i]);
    a << (i ? ", " : "") << "'fig1.dat' index " << i << " using 1:2 with lines lw 2 lc rgb '" << c << "' title '"
      << name << "' noenhanced";
    b << (i ? ", " : "") << "'fig1.dat' index " << i << " using 1:3 with lines lw 2 dt 1 lc rgb '" << c << "' title '"
      << name << " NV' noenhanced, '' index " << i << " using 1:4 with lines lw 2 dt 2 lc rgb '" << c << "' title '"
      << name << " ZF' noenhanced, '' index " << i << " using 1:5 with lines lw 1 dt 4 lc rgb '#9467bd' title '" << name
      << " MF'";
  }
  common::write_file_atomically((dir / "fig1a.gp").string(), a.str() + "\n");
  common::write_file_atomically((dir / "fig1b.gp").string(), b.str() + "\n");
  return {"fig1a", "fig1b"};
}

// Fig 2a: the movers' distances to ICN 0.5 and 0.95 against sigma_loc.
void write_fig2a(const std::vector<SummaryRow>& rows, const std::vector<Algorithm>& movers, const fs::path& dir) {
  common::write_file_atomically(
      (dir / "fig2a.dat").string(),
      sweep_dat(rows, kSweepSigmaLoc, movers, {metrics::kDistToIcn050M, metrics::kDistToIcn095M}));
  std::ostringstream g;
  g << gp_header("fig2a.png", "Fig 2a: mean distance per UAV to ICN 0.5 (solid) and 0.95 (dotted)",
                 "localization error sigma_{loc} [m]", "distance per UAV [m]")
    << "plot ";
  for (std::size_t i = 0; i < movers.size(); ++i) {
    const std::string c = algorithm_color(movers[i]);
    const std::string name = to_string(movers[i]);
    g << (i ? ", " : "") << "'fig2a.dat' index " << i << " using 1:2:3 with yerrorlines lw 2 dt 1 lc rgb '" << c
      << "' title '" << name << " ICN 0.5' noenhanced, '' index " << i
      << " using 1:4:5 with yerrorlines lw 2 dt 3 lc rgb '" << c << "' title '" << name << " ICN 0.95' noenhanced";
  }
  common::write_file_atomically((dir / "fig2a.gp").string(), g.str() + "\n");
}

// Fig 2b (sigma_loc) or Fig 3 (sigma_act): every algorithm's final SINR against the sweep.
void write_sinr_figure(const ExperimentSettings& s, const std::vector<SummaryRow>& rows, const std::string& sweep,
                       const std::string& stem, const std::string& xlabel, const fs::path& dir) {
  common::write_file_atomically(
      (dir / (stem + ".dat")).string(),
      sweep_dat(rows, sweep, s.algorithms, {metrics::kSinrNvDb, metrics::kSinrZfDb, metrics::kSinrMfDb}));
  std::ostringstream g;
  g << gp_header(stem + ".png",
                 (stem == "fig2b" ? "Fig 2b" : "Fig 3") +
                     std::string(": final SINR of stream 1 (NV solid, ZF dotted, MF dash-dot purple)"),
                 xlabel, "SINR [dB]")
    << "plot ";
  for (std::size_t i = 0; i < s.algorithms.size(); ++i) {
    const std::string c = algorithm_color(s.algorithms[i]);
    const std::string name = to_string(s.algorithms[i]);
    g << (i ? ", " : "") << "'" << stem << ".dat' index " << i << " using 1:2:3 with yerrorlines lw 2 dt 1 lc rgb '"
      << c << "' title '" << name << " NV' noenhanced, '' index " << i
      << " using 1:4:5 with yerrorlines lw 2 dt 3 lc rgb '" << c << "' title '" << name << " ZF' noenhanced";
    if (i == 0) g << ", '' index 0 using 1:6 with lines lw 1 dt 4 lc rgb '#9467bd' title 'MF'";
  }
  common::write_file_atomically((dir / (stem + ".gp")).string(), g.str() + "\n");
}

}  // namespace

const SummaryRow* find_row(const std::vector<SummaryRow>& rows, const std::string& sweep, double value,
                           const std::string& a) {
  for (const SummaryRow& r : rows) {
    if (r.sweep == sweep && std::abs(r.value - value) < 1e-12 && r.algorithm == a) return &r;
  }
  return nullptr;
}

std::string sweep_dat(const std::vector<SummaryRow>& rows, const std::string& sweep,
                      const std::vector<Algorithm>& algorithms, const std::vector<MetricId>& metrics) {
  std::ostringstream o;
  for (const Algorithm& a : algorithms) {
    o << "# algorithm " << to_string(a) << ": value";
    for (const MetricId m : metrics) o << " " << m.name << "_mean " << m.name << "_ci95";
    o << "\n";
    for (const SummaryRow& r : rows) {
      if (r.sweep != sweep || r.algorithm != to_string(a)) continue;
      o << r.value;
      for (const MetricId m : metrics) {
        const Estimate* e = r.metric(m);
        o << " " << (e && std::isfinite(e->mean) ? e->mean : NAN) << " "
          << (e && std::isfinite(e->ci95) ? e->ci95 : 0.0);
      }
      o << "\n";
    }
    o << "\n\n";
  }
  return o.str();
}

std::string gp_header(const std::string& png, const std::string& title, const std::string& xlabel,
                      const std::string& ylabel) {
  std::ostringstream o;
  o << "set terminal pngcairo size 1000,650 enhanced font 'Sans,11'\n"
    << "set output '" << png << "'\n"
    << "set title '" << title << "'\nset xlabel '" << xlabel << "'\nset ylabel '" << ylabel << "'\n"
    << "set grid\nset key outside right\nset datafile missing 'nan'\n";
  return o.str();
}

std::vector<std::string> write_builtin_figures(const ExperimentSettings& s, const ExperimentResults& results,
                                               const std::vector<SummaryRow>& rows, const std::string& out_dir) {
  const fs::path dir(out_dir);
  std::vector<Algorithm> movers;
  for (const Algorithm& a : s.algorithms) {
    if (a != Algorithm::kRandom) movers.push_back(a);
  }
  std::vector<std::string> stems = write_fig1(results.traces, dir);
  const std::string paths_stem = s.paths ? write_path_figure(s, results.traces, out_dir) : "";
  if (s.sweep(kSweepSigmaLoc)) {
    write_fig2a(rows, movers, dir);
    stems.push_back("fig2a");
  }
  for (const auto& [sweep, stem, xlabel] : {std::tuple<std::string, std::string, std::string>{
                                                kSweepSigmaLoc, "fig2b", "localization error sigma_{loc} [m]"},
                                            {kSweepSigmaAct, "fig3", "actuation error sigma_{act} [m]"}}) {
    if (!s.sweep(sweep)) continue;
    stems.push_back(stem);
    write_sinr_figure(s, rows, sweep, stem, xlabel, dir);
  }
  if (!paths_stem.empty()) stems.push_back(paths_stem);
  return stems;
}

}  // namespace losmimo::experiment::report_parts
