// What the co-evaluation's report sources share (report_parts.h).
#include "report_parts.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "losmimo/placement/common/format.h"
#include "losmimo/placement/common/gnuplot.h"

namespace losmimo::coevaluation::report_detail {

namespace fs = std::filesystem;
using experiment::Estimate;
using experiment::MetricId;
using experiment::SummaryRow;

std::string fmt(double v, int precision) { return common::format_fixed(v, precision); }

std::string fmt_estimate(const Estimate* e, int precision) { return experiment::format_estimate(e, precision); }

// The algorithms of a sweep, in the order the rows have them.
std::vector<std::string> algorithms_of(const std::vector<SummaryRow>& rows, const std::string& sweep) {
  std::vector<std::string> out;
  for (const SummaryRow& r : rows) {
    if (r.sweep == sweep && std::find(out.begin(), out.end(), r.algorithm) == out.end()) out.push_back(r.algorithm);
  }
  return out;
}

const SummaryRow* find_row(const std::vector<SummaryRow>& rows, const std::string& sweep, double value,
                           const std::string& algorithm) {
  for (const SummaryRow& r : rows) {
    if (r.sweep == sweep && r.value == value && r.algorithm == algorithm) return &r;
  }
  return nullptr;
}

const char* color(const std::string& algorithm) {
  static const std::pair<const char*, const char*> kColors[] = {{"gd_gauss", "#1f77b4"},
                                                                {"gd_ekf", "#ff7f0e"},
                                                                {"gd_pf", "#2ca02c"},
                                                                {"gd_ekf_ceres", "#d62728"},
                                                                {"bf", "#9467bd"},
                                                                {"ura_ekf", "#8c564b"},
                                                                {"centralized", "#000000"},
                                                                {"gd_ekf_nofallback", "#e377c2"},
                                                                {"gd_gauss_matched", "#17becf"},
                                                                {"gd_gauss_shape_matched", "#bcbd22"},
                                                                {"gd_gauss_split_matched", "#aec7e8"}};
  for (const auto& [name, c] : kColors) {
    if (algorithm == name) return c;
  }
  return "#7f7f7f";
}

std::string converged(const SummaryRow& r) {
  return std::to_string(std::lround(r.trials * r.converged_fraction)) + "/" + std::to_string(r.trials);
}

// One gnuplot data block per algorithm: value, then mean and ci95 of each metric
// (kConvergedFraction is the row's own field, with ci 0).
std::string dat(const std::vector<SummaryRow>& rows, const std::string& sweep,
                const std::vector<std::string>& algorithms, const std::vector<MetricId>& columns) {
  std::ostringstream o;
  o.precision(10);
  for (const std::string& a : algorithms) {
    o << "# algorithm " << a << ": value";
    for (const MetricId m : columns) o << " " << m.name << "_mean " << m.name << "_ci95";
    o << "\n";
    for (const SummaryRow& r : rows) {
      if (r.sweep != sweep || r.algorithm != a) continue;
      o << r.value;
      for (const MetricId m : columns) {
        if (m == kConvergedFraction) {
          o << " " << r.converged_fraction << " 0";
          continue;
        }
        const Estimate* e = r.metric(m);
        const bool ok = e && e->n > 0 && std::isfinite(e->mean);
        o << " " << (ok ? e->mean : NAN) << " " << (ok && std::isfinite(e->ci95) ? e->ci95 : 0.0);
      }
      o << "\n";
    }
    o << "\n\n";
  }
  return o.str();
}

std::string gp_header(const std::string& png, int width, int height) {
  std::ostringstream o;
  o << "set terminal pngcairo size " << width << "," << height << " noenhanced font 'Sans,11'\n"
    << "set output '" << png << "'\nset grid\nset key outside right\nset datafile missing 'nan'\n";
  return o.str();
}

// Two curves per algorithm from data columns (2,3) solid and (4,5) dotted.
std::string two_metric_plot(const std::string& dat_file, const std::vector<std::string>& algorithms,
                            const std::string& solid, const std::string& dotted) {
  std::ostringstream g;
  g << "plot ";
  for (std::size_t i = 0; i < algorithms.size(); ++i) {
    const std::string c = color(algorithms[i]);
    g << (i ? ", " : "") << "'" << dat_file << "' index " << i << " using 1:2:3 with yerrorlines lw 2 dt 1 lc rgb '"
      << c << "' title '" << algorithms[i] << " " << solid << "', '' index " << i
      << " using 1:4:5 with yerrorlines lw 2 dt 3 lc rgb '" << c << "' title '" << algorithms[i] << " " << dotted
      << "'";
  }
  return g.str();
}

// Runs gnuplot on each stem when plots are on; returns warnings.
std::vector<std::string> render(const experiment::ExperimentSettings& s, const fs::path& dir,
                                const std::vector<std::string>& stems) {
  if (!s.plots) return {};
  return common::render_gnuplot(dir.string(), stems, "the co-evaluation .gp scripts were written but not rendered");
}

}  // namespace losmimo::coevaluation::report_detail
