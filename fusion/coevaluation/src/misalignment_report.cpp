// The bs_misalignment_rad sweep's figure and report section, and the report's answer to which
// localization error measure predicts capacity (report.h).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <numeric>
#include <sstream>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/fusion/coevaluation/report.h"
#include "losmimo/placement/common/atomic_file.h"
#include "report_parts.h"

namespace losmimo::coevaluation {

using namespace report_detail;

namespace {

namespace fs = std::filesystem;
using experiment::Estimate;
using experiment::MetricId;
using experiment::SummaryRow;
namespace metrics = experiment::metrics;

double mean_of(const SummaryRow& r, MetricId m) {
  const Estimate* e = r.metric(m);
  return e && e->n > 0 ? e->mean : NAN;
}

// Ranks 1..n, ties at their average rank.
std::vector<double> ranks(const std::vector<double>& x) {
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&x](std::size_t a, std::size_t b) { return x[a] < x[b]; });
  std::vector<double> r(x.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && x[order[j + 1]] == x[order[i]]) ++j;
    for (std::size_t k = i; k <= j; ++k) r[order[k]] = 0.5 * static_cast<double>(i + j) + 1.0;
    i = j + 1;
  }
  return r;
}

// Pearson's correlation of x and y; NaN for fewer than 3 pairs or a constant series.
double pearson(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  const auto constant = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [&v](double e) { return e == v.front(); });
  };
  if (n < 3 || constant(x) || constant(y)) return NAN;
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n, my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxx > 0.0 && syy > 0.0 ? sxy / std::sqrt(sxx * syy) : NAN;
}

double spearman(const std::vector<double>& x, const std::vector<double>& y) { return pearson(ranks(x), ranks(y)); }

std::string fmt_r(double r) { return std::isfinite(r) ? fmt(r, 2) : "n/a"; }

// The co-evaluation sweeps whose rows carry both error measures.
const std::string* const kErrorSweeps[] = {&kSweepBeaconNoise, &kSweepMisalignment, &kSweepBeaconOutage};

struct Outcome {
  MetricId metric;
  const char* label;
};
const Outcome kOutcomes[] = {{metrics::kFinalIcn, "final ICN"},
                             {metrics::kSinrNvDb, "final NV SINR"},
                             {metrics::kDistToIcn095M, "travel to ICN 0.95"}};

// The (sweep value, algorithm) points of `sweeps` where the outcome and both error measures have a
// mean: the error columns x_lateral, x_shape and the outcome y.
struct Points {
  std::vector<double> lateral, shape, outcome;
};
Points points_of(const std::vector<SummaryRow>& rows, const std::vector<std::string>& sweeps, MetricId outcome) {
  Points p;
  for (const SummaryRow& r : rows) {
    if (std::find(sweeps.begin(), sweeps.end(), r.sweep) == sweeps.end()) continue;
    const double lateral = mean_of(r, kLocLateralRmse), shape = mean_of(r, kShapeLateralRmse);
    const double y = mean_of(r, outcome);
    if (!std::isfinite(lateral) || !std::isfinite(shape) || !std::isfinite(y)) continue;
    p.lateral.push_back(lateral);
    p.shape.push_back(shape);
    p.outcome.push_back(y);
  }
  return p;
}

}  // namespace

std::string error_measure_section(const std::vector<SummaryRow>& rows) {
  std::vector<std::string> present;
  for (const std::string* sweep : kErrorSweeps) {
    if (!algorithms_of(rows, *sweep).empty()) present.push_back(*sweep);
  }
  if (present.empty()) return {};
  std::vector<std::pair<std::string, std::vector<std::string>>> groups;
  for (const std::string& sweep : present) groups.push_back({"`" + sweep + "`", {sweep}});
  if (present.size() > 1) groups.push_back({"all of them", present});

  std::ostringstream md;
  md << "\n## Which localization error predicts capacity\n\n"
     << "Each point is one (sweep value, algorithm) mean of the co-evaluation's summary with both error measures "
     << "(the rows with position estimates): the absolute lateral RMSE (`loc_lateral_rmse_m`) and the shape RMSE "
     << "(`shape_lateral_rmse_m`, the common lateral offset and the rotation about boresight removed). The table "
     << "gives Spearman's rank correlation (Pearson's in brackets) of each outcome with each measure; the measure "
     << "with the larger |r| predicts the outcome better. Correlations of means across conditions, not of trials: "
     << "they say which measure orders the conditions, not how much of a single run's loss it explains.\n\n"
     << "| points from | outcome | n | r with lateral RMSE | r with shape RMSE | better predictor |\n"
     << "|---|---|---|---|---|---|\n";
  for (const auto& [label, sweeps] : groups) {
    for (const Outcome& o : kOutcomes) {
      const Points p = points_of(rows, sweeps, o.metric);
      const double r_lat = spearman(p.lateral, p.outcome), r_shape = spearman(p.shape, p.outcome);
      md << "| " << label << " | " << o.label << " | " << p.outcome.size() << " | " << fmt_r(r_lat) << " ("
         << fmt_r(pearson(p.lateral, p.outcome)) << ") | " << fmt_r(r_shape) << " ("
         << fmt_r(pearson(p.shape, p.outcome)) << ") | ";
      if (!std::isfinite(r_lat) || !std::isfinite(r_shape)) {
        md << "not evaluated (fewer than 3 points, or a constant column)";
      } else if (std::abs(r_shape) > std::abs(r_lat)) {
        md << "shape RMSE";
      } else if (std::abs(r_lat) > std::abs(r_shape)) {
        md << "lateral RMSE";
      } else {
        md << "tie";
      }
      md << " |\n";
    }
  }
  // The answer, over the widest group (every sweep's points together when there are several).
  const auto& [widest, widest_sweeps] = groups.back();
  md << "\nOver " << widest << ":";
  for (const Outcome& o : kOutcomes) {
    const Points p = points_of(rows, widest_sweeps, o.metric);
    const double r_lat = spearman(p.lateral, p.outcome), r_shape = spearman(p.shape, p.outcome);
    md << " " << o.label << " is ordered ";
    if (!std::isfinite(r_lat) || !std::isfinite(r_shape)) {
      md << "by neither (not evaluated)";
    } else {
      const bool shape = std::abs(r_shape) > std::abs(r_lat);
      md << "better by the " << (shape ? "shape" : "lateral") << " RMSE (|r| " << fmt(std::abs(shape ? r_shape : r_lat))
         << " against " << fmt(std::abs(shape ? r_lat : r_shape)) << ")";
    }
    md << (&o == &kOutcomes[std::size(kOutcomes) - 1] ? "." : ";");
  }
  md << " The channel itself sees only the shape (a common lateral translation leaves ICN unchanged to second "
     << "order, placement/swarm_shape.h); where the lateral RMSE predicts better, the planner turns the common "
     << "offset into a loss: the paper's GD models a UAV's own channel row at its believed position against the "
     << "others' measured rows, so a common offset it believes in is, to that model, a misfit of the UAV's own "
     << "row. Compare `gd_gauss_shape_matched` with `gd_gauss_split_matched` in the misalignment sweep: the same "
     << "shape error, with and without the common part.\n\nWithin `beacon_noise_m` the errors are independent "
     << "per UAV, so the two measures are nearly proportional and rank the points alike; a common-mode error "
     << "(`bs_misalignment_rad`) separates them.\n";
  return md.str();
}

std::vector<std::string> write_misalignment_figures(const experiment::ExperimentSettings& s,
                                                    const std::vector<SummaryRow>& rows, const std::string& out_dir) {
  const fs::path dir(out_dir);
  const std::vector<std::string> algorithms = algorithms_of(rows, kSweepMisalignment);
  if (algorithms.empty()) return {};
  common::write_file_atomically(
      (dir / "misalignment.dat").string(),
      dat(rows, kSweepMisalignment, algorithms,
          {kLocLateralRmse, kShapeLateralRmse, metrics::kFinalIcn, metrics::kSinrNvDb, metrics::kDistToIcn095M}));
  std::ostringstream g;
  g << gp_header("misalignment.png", 1500, 500)
    << "set multiplot layout 1,3\nset xlabel 'BS azimuth misalignment [mrad]'\n"
    << "set key inside top left\nset title 'Lateral RMSE (solid) and shape RMSE (dotted)'\nset ylabel 'RMSE [m]'\n"
    << "set logscale y\nplot ";
  for (std::size_t i = 0; i < algorithms.size(); ++i) {
    const std::string c = color(algorithms[i]);
    g << (i ? ", " : "") << "'misalignment.dat' index " << i << " using ($1*1000):2 with linespoints lw 2 lc rgb '" << c
      << "' title '" << algorithms[i] << "', '' index " << i << " using ($1*1000):4 with linespoints lw 2 dt 3 lc rgb '"
      << c << "' notitle";
  }
  g << "\nunset logscale y\nset key inside bottom left\nset title 'Final NV SINR of stream 1'\nset ylabel 'SINR [dB]'\n"
    << "plot ";
  for (std::size_t i = 0; i < algorithms.size(); ++i) {
    g << (i ? ", " : "") << "'misalignment.dat' index " << i << " using ($1*1000):8:9 with yerrorlines lw 2 lc rgb '"
      << color(algorithms[i]) << "' title '" << algorithms[i] << "'";
  }
  g << "\nset key inside top left\nset title 'Travel per UAV to ICN 0.95'\nset ylabel 'distance [m]'\nplot ";
  for (std::size_t i = 0; i < algorithms.size(); ++i) {
    g << (i ? ", " : "") << "'misalignment.dat' index " << i << " using ($1*1000):10:11 with yerrorlines lw 2 lc rgb '"
      << color(algorithms[i]) << "' title '" << algorithms[i] << "'";
  }
  g << "\nunset multiplot\n";
  common::write_file_atomically((dir / "misalignment.gp").string(), g.str());
  return render(s, dir, {"misalignment"});
}

std::string misalignment_report_section(const experiment::ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  const CoevaluationSettings c = load_coevaluation_settings(s);
  const std::vector<std::string> algorithms = algorithms_of(rows, kSweepMisalignment);
  const std::vector<double>& values = s.sweep(kSweepMisalignment)->values;
  const double range_m = s.placement.scenario.range_m();
  std::ostringstream md;
  md << "## Co-evaluation: BS array misalignment (`bs_misalignment_rad`)\n\n"
     << "The BS array is turned by the swept azimuth angle: every UAV's beacon bearing reads that much more, and "
     << "no filter knows it, so every beacon fix moves laterally by about R x angle (R = " << fmt(range_m, 0)
     << " m), the same way for every UAV: a common-mode error, which the channel barely sees "
     << "(placement/swarm_shape.h). Beacon noise " << fmt(c.misalignment_beacon_noise_m, 3)
     << " m cross-range at every point. `gd_gauss` is the paper's model of that beacon noise alone (it does not "
     << "see the misalignment); the matched rows take `gd_ekf`'s measured errors, absolute (`gd_gauss_matched`), "
     << "shape only (`gd_gauss_shape_matched`) and shape plus a common-mode part (`gd_gauss_split_matched`). "
     << s.trials << " starts per point with paired seeds.\n\n"
     << "Figure: ![misalignment](misalignment.png)\n\n"
     << "| misalignment [mrad] | algorithm | converged | final ICN | NV SINR [dB] | travel to ICN 0.95 [m] | "
     << "lateral RMSE [m] | common lateral [m] | shape RMSE [m] | shape NEES |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const double v : values) {
    for (const std::string& a : algorithms) {
      const SummaryRow* r = find_row(rows, kSweepMisalignment, v, a);
      if (!r) continue;
      md << "| " << fmt(1e3 * v, 3) << " | " << a << " | " << converged(*r) << " | "
         << fmt_estimate(r->metric(metrics::kFinalIcn), 4) << " | " << fmt_estimate(r->metric(metrics::kSinrNvDb))
         << " | " << fmt_estimate(r->metric(metrics::kDistToIcn095M)) << " | "
         << fmt_estimate(r->metric(kLocLateralRmse), 3) << " | " << fmt_estimate(r->metric(kCommonLateral), 3) << " | "
         << fmt_estimate(r->metric(kShapeLateralRmse), 3) << " | " << fmt_estimate(r->metric(kShapeNees)) << " |\n";
    }
  }
  md << matched_error_sections(s, rows, kSweepMisalignment, values) << error_measure_section(rows);
  return md.str();
}

}  // namespace losmimo::coevaluation
