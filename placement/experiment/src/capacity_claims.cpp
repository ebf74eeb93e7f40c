// The capacity-claim columns and their report.md section (capacity_claims.h).
#include "losmimo/placement/experiment/capacity_claims.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "losmimo/placement/common/format.h"

namespace losmimo::experiment {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string fmt(double v, int decimals = 2) { return std::isfinite(v) ? common::format_fixed(v, decimals) : "n/a"; }

const SummaryRow* find_row(const std::vector<SummaryRow>& rows, const std::string& sweep, double value,
                           const std::string& algorithm) {
  for (const SummaryRow& r : rows) {
    if (r.sweep == sweep && r.algorithm == algorithm && (r.value == value || std::abs(r.value - value) < 1e-12))
      return &r;
  }
  return nullptr;
}

double mean_of(const SummaryRow* row, MetricId id) {
  const Estimate* e = row ? row->metric(id) : nullptr;
  return e && e->n > 0 ? e->mean : kNaN;
}

// "0.97 ± 0.01" of a row's metric.
std::string cell(const SummaryRow* row, MetricId id, int decimals) {
  return format_estimate(row ? row->metric(id) : nullptr, decimals);
}

std::string sweep_table(const ExperimentSettings& s, const SweepPoints& sweep, const std::vector<SummaryRow>& rows) {
  using namespace metrics;
  std::ostringstream o;
  o << "### " << sweep.name << "\n\n"
    << "| " << sweep.name << " | algorithm | C / C_max | translation median [m] | p95 [m] | max [m] | max / d_r "
    << "| converged |\n|---|---|---|---|---|---|---|---|\n";
  for (const double v : sweep.values) {
    for (const Algorithm& a : s.algorithms) {
      const SummaryRow* row = find_row(rows, sweep.name, v, to_string(a));
      if (!row) continue;
      o << "| " << common::format_double(v) << " | " << to_string(a) << " | " << cell(row, kCapacityFraction, 3)
        << " | " << cell(row, kTranslationMedianM, 2) << " | " << cell(row, kTranslationP95M, 2) << " | "
        << cell(row, kTranslationMaxM, 2) << " | " << cell(row, kTranslationMaxPerSpacing, 2) << " | "
        << fmt(row->converged_fraction, 2) << " |\n";
    }
  }
  return o.str();
}

// The capacity planner's range over the sweep's points: "0.95 (at 0) to 0.99 (at 0.18)".
std::string cap_range(const SweepPoints& sweep, const std::vector<SummaryRow>& rows, MetricId id, int decimals) {
  double lo = kNaN, hi = kNaN, v_lo = 0.0, v_hi = 0.0;
  for (const double v : sweep.values) {
    const double m = mean_of(find_row(rows, sweep.name, v, to_string(Algorithm::kCap)), id);
    if (!std::isfinite(m)) continue;
    if (!std::isfinite(lo) || m < lo) lo = m, v_lo = v;
    if (!std::isfinite(hi) || m > hi) hi = m, v_hi = v;
  }
  if (!std::isfinite(lo)) return "n/a";
  return fmt(lo, decimals) + " (at " + common::format_double(v_lo) + ") to " + fmt(hi, decimals) + " (at " +
         common::format_double(v_hi) + ")";
}

}  // namespace

const ExtensionMetrics& capacity_claim_metrics() {
  static const ExtensionMetrics kTable = {metrics::kCapacityFraction, metrics::kTranslationMedianM,
                                          metrics::kTranslationP95M, metrics::kTranslationMaxM,
                                          metrics::kTranslationMaxPerSpacing};
  return kTable;
}

double median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double nearest_rank_quantile(std::vector<double> values, double q) {
  if (values.empty() || !(q > 0.0 && q <= 1.0)) return kNaN;
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::max<std::size_t>(rank, 1) - 1];
}

MetricValues capacity_claim_values(const placement::Scenario& scenario, placement::CapPower power,
                                   const Eigen::MatrixXcd& H_los, const Eigen::Matrix3Xd& start_m,
                                   const Eigen::Matrix3Xd& final_m) {
  const double noise_variance = scenario.noise_variance();
  const double bound =
      placement::orthogonal_capacity_bps_hz(scenario.num_uavs, scenario.num_bs_antennas(), noise_variance, power);
  std::vector<double> translation_m(static_cast<std::size_t>(final_m.cols()));
  for (Eigen::Index n = 0; n < final_m.cols(); ++n) {
    translation_m[static_cast<std::size_t>(n)] = (final_m.col(n) - start_m.col(n)).norm();
  }
  const double slot_spacing_m =
      scenario.wavelength_m() * scenario.range_m() / (scenario.bs_rows * scenario.bs_spacing_m);
  const double largest_m = translation_m.empty() ? kNaN : *std::max_element(translation_m.begin(), translation_m.end());
  MetricValues v;
  v.set(metrics::kCapacityFraction, placement::capacity_bps_hz(H_los, noise_variance, power) / bound);
  v.set(metrics::kTranslationMedianM, median(translation_m));
  v.set(metrics::kTranslationP95M, nearest_rank_quantile(translation_m, 0.95));
  v.set(metrics::kTranslationMaxM, largest_m);
  v.set(metrics::kTranslationMaxPerSpacing, largest_m / slot_spacing_m);
  return v;
}

std::vector<double> capacity_claim_columns(const TrialRecord& r) {
  std::vector<double> columns;
  for (const ExtensionMetric& m : capacity_claim_metrics()) {
    const std::optional<double> v = r.capacity_claims.find(m);
    if (!v) {
      throw std::logic_error("capacity_claim_columns: the " + r.sweep + " record of " + r.algorithm + " (trial " +
                             std::to_string(r.trial) + ") leaves " + m.name + " unset");
    }
    columns.push_back(*v);
  }
  return columns;
}

std::string capacity_claims_report_section(const ExperimentSettings& s, const std::vector<SummaryRow>& rows) {
  if (!s.capacity_columns) return "";
  const placement::Scenario& sc = s.placement.scenario;
  std::ostringstream o;
  o << "## Capacity and translation (capacity_columns)\n\n"
    << "C / C_max: capacity of the LoS channel at the final positions under [cap] power = "
    << placement::to_string(s.placement.cap.power)
    << ", over the single-user bound C_max = min(Nr, Nt) log2(1 + SNR max(Nr, Nt)) (equal power; "
    << "placement/capacity.h). Translation: each UAV's distance from its start to its final position "
    << "(median, 95th percentile and largest over the swarm, then averaged over the trials); d_r = lambda R / (n "
    << "d_t) is the receive URA's slot spacing ("
    << fmt(sc.wavelength_m() * sc.range_m() / (sc.bs_rows * sc.bs_spacing_m), 2) << " m for the configured "
    << sc.bs_rows << " x " << sc.bs_cols << " array). Means ± 95% CI over " << s.trials << " trials.\n\n";
  const bool cap = std::find(s.algorithms.begin(), s.algorithms.end(), Algorithm::kCap) != s.algorithms.end();
  for (const SweepPoints& sweep : s.sweeps) {
    o << sweep_table(s, sweep, rows) << "\n";
    if (!cap) continue;
    o << "cap over this sweep: C / C_max " << cap_range(sweep, rows, metrics::kCapacityFraction, 3)
      << "; largest translation " << cap_range(sweep, rows, metrics::kTranslationMaxM, 2) << " m, i.e. "
      << cap_range(sweep, rows, metrics::kTranslationMaxPerSpacing, 2) << " slot spacings.\n\n";
  }
  if (!cap) o << "No `cap` in [experiment] algorithms: no verdict on the capacity planner.\n";
  return o.str();
}

}  // namespace losmimo::experiment
