// The channel sweeps' figures and report.md sections (channel_sweeps.h).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "losmimo/placement/common/atomic_file.h"
#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/gnuplot.h"
#include "losmimo/placement/experiment/channel_sweeps.h"
#include "losmimo/placement/experiment/metrics.h"
#include "losmimo/placement/experiment/report.h"
#include "losmimo/placement/channel_conditions.h"

namespace losmimo::experiment {

namespace {
namespace fs = std::filesystem;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A claim "supported" by a ratio at least this (gain over random placement; share of a URA's rate).
constexpr double kSignificantGain = 1.2;
constexpr double kCloseToUra = 0.9;

std::string fmt(double v, int decimals = 2) { return common::format_fixed(v, decimals); }

const SummaryRow* find_row(const std::vector<SummaryRow>& rows, const std::string& sweep, double value,
                           const std::string& algorithm) {
  for (const SummaryRow& r : rows) {
    if (r.sweep == sweep && r.algorithm == algorithm && (r.value == value || std::abs(r.value - value) < 1e-12))
      return &r;
  }
  return nullptr;
}

// The mean of a metric at (sweep, value, algorithm), NaN if absent.
double mean(const std::vector<SummaryRow>& rows, const std::string& sweep, double value, const std::string& algorithm,
            MetricId metric) {
  const SummaryRow* r = find_row(rows, sweep, value, algorithm);
  const Estimate* e = r ? r->metric(metric) : nullptr;
  return e ? e->mean : std::nan("");
}

bool runs(const ExperimentSettings& s, const Algorithm& a) {
  return std::find(s.algorithms.begin(), s.algorithms.end(), a) != s.algorithms.end();
}

std::string value_label(const std::string& sweep, double v) {
  if (sweep == kSweepBsAntennas) {
    const int side = static_cast<int>(std::lround(std::sqrt(v)));
    return std::to_string(static_cast<int>(v)) + " (" + std::to_string(side) + "x" + std::to_string(side) + ")";
  }
  return placement::format_db_or_inf(v);
}

std::string axis_label(const std::string& sweep) {
  if (sweep == kSweepRicianK) return "Rician K-factor [dB] (inf: pure LoS)";
  if (sweep == kSweepCsiSnr) return "CSI estimation SNR [dB] (inf: perfect CSI)";
  return "BS antennas (n x n array)";
}

// The plotted abscissa: inf one step to the right of the largest finite value.
double plotted_x(const std::vector<double>& values, double v) {
  if (v != kInf) return v;
  std::vector<double> finite;
  for (const double x : values) {
    if (x != kInf) finite.push_back(x);
  }
  if (finite.empty()) return 0.0;
  const auto [lo, hi] = std::minmax_element(finite.begin(), finite.end());
  const double step = finite.size() > 1 ? (*hi - *lo) / static_cast<double>(finite.size() - 1) : 10.0;
  return *hi + std::max(step, 1.0);
}

std::string setup_line(const ExperimentSettings& s, const std::string& sweep) {
  const placement::Scenario& sc = s.placement.scenario;
  const placement::ChannelSettings& c = s.placement.channel;
  std::ostringstream o;
  o << sc.num_uavs << " UAVs, ";
  if (sweep != kSweepBsAntennas) o << "BS " << sc.bs_rows << " x " << sc.bs_cols << ", ";
  o << "antenna spacing " << common::format_double(sc.bs_spacing_m) << " m, "
    << common::format_double(sc.carrier_hz / 1e9) << " GHz, R = " << common::format_double(sc.range_m()) << " m, SNR "
    << common::format_double(sc.snr_db) << " dB per link, " << to_string(sc.gain_model) << " gain";
  if (sweep != kSweepRicianK) o << ", Rician K " << placement::format_db_or_inf(c.rician_k_db) << " dB";
  if (sweep != kSweepCsiSnr) o << ", CSI SNR " << placement::format_db_or_inf(c.csi_snr_db) << " dB";
  o << ", coherence block " << c.coherence_iterations << " iteration(s); sigma_loc "
    << common::format_double(s.placement.errors.sigma_loc_m) << " m, sigma_act "
    << common::format_double(s.placement.errors.sigma_act_m) << " m; " << s.trials
    << " trials per point, stop at measured ICN " << common::format_double(s.placement.run.target_icn) << " or "
    << s.placement.run.max_iterations << " iterations";
  return o.str();
}

// "GD 1.85x, BF 1.80x" of f(algorithm) over the movers that ran.
template <typename F>
std::string per_mover(const ExperimentSettings& s, F f) {
  std::string out;
  for (const Algorithm& a : {Algorithm::kGd, Algorithm::kBf}) {
    if (runs(s, a)) out += (out.empty() ? "" : ", ") + to_string(a) + " " + f(to_string(a));
  }
  return out;
}

std::string claims_header() {
  return "Claims of the follow-up paper (Hanna, Krijestorac, Cabric, *UAV Swarm Position Optimization for High "
         "Capacity MIMO Backhaul*, IEEE JSAC 2021). Only its abstract could be found, so each claim below is a "
         "sentence of the abstract, and each verdict holds for the setup above only:\n\n";
}

std::string rician_claims(const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  const SweepPoints& p = *s.sweep(kSweepRicianK);
  std::vector<double> finite;
  for (const double v : p.values) {
    if (v != kInf) finite.push_back(v);
  }
  std::ostringstream o;
  o << claims_header();
  if (finite.empty() || !runs(s, Algorithm::kRandom)) {
    return o.str() + "- No finite K-factor (or no `random` baseline) in this run: no verdict.\n";
  }
  const double k_lo = *std::min_element(finite.begin(), finite.end());
  const std::string S = kSweepRicianK;
  const MetricId zf = metrics::kSumRateZfBpsHz;
  int held = 0, points = 0;
  for (const double k : finite) {
    bool all = true;
    for (const Algorithm& a : {Algorithm::kGd, Algorithm::kBf}) {
      if (!runs(s, a)) continue;
      const double gain = mean(rows, S, k, to_string(a), zf) / mean(rows, S, k, "random", zf);
      const double vs_ura =
          runs(s, Algorithm::kUra) ? mean(rows, S, k, to_string(a), zf) / mean(rows, S, k, "ura", zf) : 1.0;
      all = all && gain >= kSignificantGain && vs_ura >= kCloseToUra;
    }
    held += all ? 1 : 0;
    ++points;
  }
  const std::string verdict = held == points ? "**supports**" : held > 0 ? "**partly supports**" : "**contradicts**";
  o << "- C5, \"the approaches are robust in a Rician channel\": " << verdict << " (capacity). At K = " << fmt(k_lo, 0)
    << " dB the ergodic ZF sum rate over random placement is " << per_mover(s, [&](const std::string& a) {
         return fmt(mean(rows, S, k_lo, a, zf) / mean(rows, S, k_lo, "random", zf)) + "x";
       });
  if (runs(s, Algorithm::kUra)) {
    o << ", and over the rigid URA's " << per_mover(s, [&](const std::string& a) {
      return fmt(mean(rows, S, k_lo, a, zf) / mean(rows, S, k_lo, "ura", zf)) + "x";
    });
  }
  o << "; the criterion (>= " << fmt(kSignificantGain, 1) << "x random and >= " << fmt(kCloseToUra, 1)
    << "x the URA, both GD and BF) holds at " << held << " of " << points << " finite K values.\n";
  // The cost: the measured-CSI stop test cannot certify ICN 0.95 under strong scatter.
  const SummaryRow* gd_lo = find_row(rows, S, k_lo, "gd");
  const SummaryRow* bf_lo = find_row(rows, S, k_lo, "bf");
  if (gd_lo || bf_lo) {
    o << "- C3, \"at the cost of a bounded translation\", under fading: at K = " << fmt(k_lo, 0) << " dB "
      << per_mover(s,
                   [&](const std::string& a) {
                     const SummaryRow* r = find_row(rows, S, k_lo, a);
                     return "converged in " + fmt(100.0 * r->converged_fraction, 0) + "% of runs and flew " +
                            fmt(mean(rows, S, k_lo, a, metrics::kDistTotalM)) + " m per UAV";
                   })
      << " (at K = inf: "
      << per_mover(s, [&](const std::string& a) { return fmt(mean(rows, S, kInf, a, metrics::kDistTotalM)) + " m"; })
      << "). The stop test reads measured CSI, whose ICN stays below the target under strong scatter, so runs "
         "go on to the iteration cap: the translation is bounded by the cap, not by convergence. "
      << (mean(rows, S, k_lo, "gd", metrics::kDistTotalM) > 2.0 * mean(rows, S, kInf, "gd", metrics::kDistTotalM)
              ? "**Contradicts** a bounded translation unless the stop rule accounts for the scatter (docs/model.md)."
              : "**Supports** it here.")
      << "\n";
  }
  return o.str();
}

std::string csi_claims(const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  const SweepPoints& p = *s.sweep(kSweepCsiSnr);
  std::ostringstream o;
  o << claims_header();
  const bool has_reference = std::find(p.values.begin(), p.values.end(), kInf) != p.values.end();
  std::vector<double> finite;
  for (const double v : p.values) {
    if (v != kInf) finite.push_back(v);
  }
  if (!has_reference || finite.empty()) {
    return o.str() + "- The sweep needs inf (perfect CSI) and a finite SNR for a verdict.\n";
  }
  std::sort(finite.begin(), finite.end());
  const std::string S = kSweepCsiSnr;
  const MetricId zf = metrics::kSumRateZfBpsHz;
  // The lowest SNR at and above which GD and BF keep kCloseToUra of their perfect-CSI ZF rate.
  double robust_from = kInf;
  for (auto it = finite.rbegin(); it != finite.rend(); ++it) {
    bool all = true;
    for (const Algorithm& a : {Algorithm::kGd, Algorithm::kBf}) {
      if (runs(s, a))
        all = all && mean(rows, S, *it, to_string(a), zf) >= kCloseToUra * mean(rows, S, kInf, to_string(a), zf);
    }
    if (!all) break;
    robust_from = *it;
  }
  const double lo = finite.front();
  o << "- The abstract claims nothing about CSI errors; its closest claim is C5, robustness to disturbances. "
    << (robust_from == lo     ? "**Supports** it for CSI noise down to " + fmt(lo, 0) + " dB"
        : robust_from == kInf ? "**Contradicts** it for CSI noise at every finite SNR swept"
                              : "**Supports** it down to " + fmt(robust_from, 0) + " dB only")
    << " (criterion: GD and BF keep >= " << fmt(kCloseToUra, 1) << "x their perfect-CSI ZF sum rate). At " << fmt(lo, 0)
    << " dB they keep "
    << per_mover(s,
                 [&](const std::string& a) {
                   return fmt(100.0 * mean(rows, S, lo, a, zf) / mean(rows, S, kInf, a, zf), 0) + "%";
                 })
    << "; the URAs, which use positions only, keep "
    << fmt(100.0 * mean(rows, S, lo, "ura", zf) / mean(rows, S, kInf, "ura", zf), 0) << "%.\n";
  return o.str();
}

// C1: random placement against the URA at each array size (needs both).
void bs_claim_random_limited(std::ostream& o, const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  const std::string S = kSweepBsAntennas;
  const SweepPoints& p = *s.sweep(kSweepBsAntennas);
  const MetricId zf = metrics::kSumRateZfBpsHz, nv = metrics::kSumRateNvBpsHz;
  o << "- C1, \"LoS makes the channel highly correlated, which limits the multiplexing gain of random placement\": "
       "random placement reaches ";
  int limited = 0;
  for (std::size_t i = 0; i < p.values.size(); ++i) {
    const double v = p.values[i];
    const double share_zf = mean(rows, S, v, "random", zf) / mean(rows, S, v, "ura", zf);
    const double share_nv = mean(rows, S, v, "random", nv) / mean(rows, S, v, "ura", nv);
    limited += share_zf < 0.5 || share_nv < 0.5 ? 1 : 0;
    o << (i ? "; " : "") << fmt(100.0 * share_zf, 0) << "% (ZF) and " << fmt(100.0 * share_nv, 0)
      << "% (NV) of the URA's sum rate at " << value_label(S, v) << " antennas";
  }
  o << ". "
    << (limited == static_cast<int>(p.values.size()) ? "**Supports** it at every size"
        : limited > 0 ? "**Supports** it where a share is below 50%, **contradicts** it for the other sizes "
                        "(random rows of a large array are nearly orthogonal already)"
                      : "**Contradicts** it at every size swept")
    << ".\n";
}

// C2: the URAs' LoS ICN at the final positions.
void bs_claim_infinite_set(std::ostream& o, const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  const std::string S = kSweepBsAntennas;
  const SweepPoints& p = *s.sweep(kSweepBsAntennas);
  o << "- C2, \"the capacity bound is reached on an infinite set of placements\": the LoS ICN at the final positions "
       "is ";
  std::string parts;
  for (const double v : p.values) {
    for (const std::string a : {"ura", "ura_lattice"}) {
      const double icn = mean(rows, S, v, a, kFinalIcnLos);
      if (std::isfinite(icn)) parts += (parts.empty() ? "" : ", ") + a + " " + fmt(icn, 3) + " at " + value_label(S, v);
    }
  }
  o << parts
    << ". The rigid URA and the lattice URA (each UAV at its own depth, shifted by whole lateral periods) "
       "are different placements with the same bound, and with more antennas than UAVs any "
    << s.placement.scenario.num_uavs << " of the Nt slots do: **supports** it.\n";
}

// C4 and C3: the movers' gain over random placement at the largest array, and their travel.
void bs_claims_gain_and_travel(std::ostream& o, const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  const std::string S = kSweepBsAntennas;
  const SweepPoints& p = *s.sweep(kSweepBsAntennas);
  const MetricId zf = metrics::kSumRateZfBpsHz, nv = metrics::kSumRateNvBpsHz;
  const double big = *std::max_element(p.values.begin(), p.values.end());
  const auto gain = [&](const std::string& a, MetricId m) {
    return mean(rows, S, big, a, m) / mean(rows, S, big, "random", m);
  };
  bool zf_holds = true, nv_holds = true;
  for (const Algorithm& a : {Algorithm::kGd, Algorithm::kBf}) {
    if (!runs(s, a)) continue;
    zf_holds = zf_holds && gain(to_string(a), zf) >= kSignificantGain;
    nv_holds = nv_holds && gain(to_string(a), nv) >= kSignificantGain;
  }
  o << "- C4, \"the capacity increase persists with a massive-MIMO ground station\": at " << value_label(S, big)
    << " antennas the sum rate over random placement is "
    << per_mover(s, [&](const std::string& a) { return fmt(gain(a, zf)) + "x (ZF) / " + fmt(gain(a, nv)) + "x (NV)"; })
    << ". "
    << (zf_holds && nv_holds ? "**Supports** it for both receivers"
        : nv_holds           ? "**Supports** it for the matched filter (NV) only; with zero-forcing the gain vanishes, "
                               "because random rows of a large array are nearly orthogonal (favourable propagation)"
        : zf_holds           ? "**Supports** it for zero-forcing only"
                             : "**Contradicts** it for both receivers")
    << " (criterion: >= " << fmt(kSignificantGain, 1) << "x).\n";
  o << "- C3, \"a significant capacity increase at the cost of a bounded translation\": total distance per UAV "
    << per_mover(s,
                 [&](const std::string& a) {
                   std::string d;
                   for (const double v : p.values)
                     d += (d.empty() ? "" : " / ") + fmt(mean(rows, S, v, a, metrics::kDistTotalM), 1);
                   return d + " m";
                 })
    << " at " <<
      [&] {
        std::string v;
        for (const double x : p.values) v += (v.empty() ? "" : " / ") + value_label(S, x);
        return v;
      }()
    << " antennas, against a " << common::format_double(s.placement.scenario.cube_side_m)
    << " m start cube: bounded, **supports** it where the gain above is significant.\n";
}

std::string bs_claims(const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  std::ostringstream o;
  o << claims_header();
  const bool ura = runs(s, Algorithm::kUra), random = runs(s, Algorithm::kRandom);
  if (ura && random) bs_claim_random_limited(o, s, rows);
  if (ura || runs(s, Algorithm::kUraLattice)) bs_claim_infinite_set(o, s, rows);
  if (random) bs_claims_gain_and_travel(o, s, rows);
  return o.str();
}

}  // namespace

std::vector<std::string> write_channel_sweep_figure(const ExperimentSettings& s, const std::string& sweep,
                                                    const std::vector<SummaryRow>& rows, const std::string& out_dir) {
  const SweepPoints* p = s.sweep(sweep);
  if (!p) return {};
  const fs::path dir(out_dir);
  const std::vector<MetricId> plotted = {metrics::kSumRateZfBpsHz, metrics::kSumRateNvBpsHz, kFinalIcnLos,
                                         metrics::kDistTotalM};
  std::ostringstream dat;
  for (const Algorithm& a : s.algorithms) {
    dat << "# algorithm " << to_string(a) << ": x";
    for (const MetricId m : plotted) dat << " " << m.name << "_mean " << m.name << "_ci95";
    dat << " converged_fraction\n";
    for (const double v : p->values) {
      const SummaryRow* r = find_row(rows, sweep, v, to_string(a));
      if (!r) continue;
      dat << common::format_g(plotted_x(p->values, v), common::kCsvDigits);
      for (const MetricId m : plotted) {
        const Estimate* e = r->metric(m);
        dat << " " << common::format_g(e && std::isfinite(e->mean) ? e->mean : std::nan(""), common::kCsvDigits) << " "
            << common::format_g(e && std::isfinite(e->ci95) ? e->ci95 : 0.0, common::kCsvDigits);
      }
      dat << " " << common::format_g(r->converged_fraction, common::kCsvDigits) << "\n";
    }
    dat << "\n\n";
  }
  common::write_file_atomically((dir / (sweep + ".dat")).string(), dat.str());

  std::ostringstream g;
  g << "set terminal pngcairo size 1300,900 enhanced font 'Sans,10'\nset output '" << sweep << ".png'\n"
    << "set grid\nset key top left font ',9'\nset datafile missing 'nan'\nset xlabel '" << axis_label(sweep) << "'\n";
  if (sweep == kSweepBsAntennas) g << "set logscale x 2\n";
  g << "set xtics (";
  for (std::size_t i = 0; i < p->values.size(); ++i) {
    g << (i ? ", " : "") << "'" << value_label(sweep, p->values[i]) << "' "
      << common::format_g(plotted_x(p->values, p->values[i]), common::kCsvDigits);
  }
  g << ")\nset multiplot layout 2,2 title '" << sweep << ": " << s.placement.scenario.num_uavs
    << " UAVs (means and 95% CI over " << s.trials << " trials)' noenhanced\n";
  const char* const titles[] = {"ergodic ZF sum rate [bit/s/Hz]", "ergodic NV sum rate [bit/s/Hz]",
                                "LoS ICN at the final positions", "distance flown per UAV [m]"};
  for (std::size_t m = 0; m < plotted.size(); ++m) {
    g << "set title '" << titles[m] << "'\nset ylabel ''\n"
      << (m == 2 ? "set yrange [0:1.05]\n" : "set autoscale y\n") << "plot ";
    for (std::size_t i = 0; i < s.algorithms.size(); ++i) {
      g << (i ? ", " : "") << "'" << sweep << ".dat' index " << i << " using 1:" << 2 + 2 * m << ":" << 3 + 2 * m
        << " with yerrorlines lw 2 lc rgb '" << algorithm_color(s.algorithms[i]) << "' title '"
        << to_string(s.algorithms[i]) << "' noenhanced";
    }
    g << "\n";
  }
  g << "unset multiplot\n";
  common::write_file_atomically((dir / (sweep + ".gp")).string(), g.str());
  if (!s.plots) return {};
  return common::render_gnuplot(dir.string(), {sweep},
                                sweep +
                                    ".gp was written but not rendered (apt-get install gnuplot-nox, then run "
                                    "gnuplot " +
                                    sweep + ".gp in the output folder)");
}

std::string channel_sweep_report_section(const ExperimentSettings& s, const std::string& sweep,
                                         const std::vector<SummaryRow>& rows) {
  const SweepPoints* p = s.sweep(sweep);
  if (!p) return {};
  std::ostringstream md;
  const std::string title = sweep == kSweepRicianK  ? "Rician K-factor"
                            : sweep == kSweepCsiSnr ? "CSI estimation noise"
                                                    : "BS array size";
  md << "## " << title << " (`" << sweep << "`)\n\n"
     << "Setup: " << setup_line(s, sweep) << ". Metrics at the final positions use the true channel: with fading, "
     << "the mean over " << s.placement.channel.fading_eval_draws
     << " scatter draws (ergodic sum rates); `LoS ICN` is the geometry's, which also gives the milestones. "
     << "docs/experiment.md explains the columns. ![" << sweep << "](" << sweep << ".png)\n\n"
     << "| "
     << (sweep == kSweepBsAntennas ? "antennas"
         : sweep == kSweepRicianK  ? "K [dB]"
                                   : "CSI SNR [dB]")
     << " | algorithm | ZF sum rate | NV sum rate | ICN | LoS ICN | distance [m] | converged |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const double v : p->values) {
    for (const Algorithm& a : s.algorithms) {
      const SummaryRow* r = find_row(rows, sweep, v, to_string(a));
      if (!r) continue;
      const auto cell = [&](MetricId m, int decimals) { return format_estimate(r->metric(m), decimals); };
      md << "| " << value_label(sweep, v) << " | " << to_string(a) << " | " << cell(metrics::kSumRateZfBpsHz, 1)
         << " | " << cell(metrics::kSumRateNvBpsHz, 1) << " | " << cell(metrics::kFinalIcn, 3) << " | "
         << cell(kFinalIcnLos, 3) << " | " << cell(metrics::kDistTotalM, 1) << " | "
         << fmt(100.0 * r->converged_fraction, 0) << "% |\n";
    }
  }
  md << "\n";
  if (sweep == kSweepRicianK) md << rician_claims(s, rows);
  if (sweep == kSweepCsiSnr) md << csi_claims(s, rows);
  if (sweep == kSweepBsAntennas) md << bs_claims(s, rows);
  return md.str();
}

}  // namespace losmimo::experiment
