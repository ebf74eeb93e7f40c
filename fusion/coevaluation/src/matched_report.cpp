// The matched-error comparisons of the co-evaluation's report (report_parts.h).
#include <cmath>
#include <sstream>

#include "losmimo/fusion/coevaluation/coevaluation.h"
#include "losmimo/placement/swarm_shape.h"
#include "report_parts.h"

namespace losmimo::coevaluation::report_detail {

namespace {

using experiment::Estimate;
using experiment::SummaryRow;
namespace metrics = experiment::metrics;

// The two matched Gaussian rows: at gd_ekf's lateral RMSE and at its shape RMSE.
struct MatchedGaussian {
  const char* alias;
  const char* heading;
  const char* how;                      // how its sigma_loc is taken from gd_ekf's error
  const char* same_error;               // what the two rows share
  experiment::ExtensionMetric matched;  // gd_ekf's metric it matches
  double matched_per_sigma;             // that metric's expected value per unit sigma_loc
};

// gd_ekf against a matched Gaussian row at every value of the sweep: the paired differences of
// the same trials (the row's paired_travel_diff_m and paired_iterations_diff), mean and 95% CI.
std::string matched_error_section(const std::vector<SummaryRow>& rows, const std::string& sweep,
                                  const std::vector<double>& values, const MatchedGaussian& m) {
  const std::string ekf = "gd_ekf", gauss = m.alias;
  std::ostringstream md;
  md << "\n### " << m.heading << "\n\n"
     << "`" << gauss << "` runs the paper's GD with sigma_loc = `" << ekf << "`'s " << m.how
     << " in the same trial, so both place from positions that are off by the same " << m.same_error
     << "; only the error's "
     << "structure differs (the filter's is correlated over iterations and comes with its covariance). Differences "
     << "are paired (same start, same trial): " << ekf << " minus " << gauss << ", over the trials where both "
     << "reached ICN 0.95; negative values favour the estimator.\n\n"
     << "| " << (sweep == kSweepMisalignment ? "BS misalignment [mrad]" : "beacon noise [m]")
     << " | matched sigma_loc [m] | converged (" << ekf << " / " << gauss << ") | travel to ICN "
     << "0.95, " << ekf << " [m] | " << gauss << " [m] | paired difference [m] | iterations, paired difference | "
     << "verdict |\n|---|---|---|---|---|---|---|---|\n";
  int rows_written = 0;
  for (const double v : values) {
    const SummaryRow* a = find_row(rows, sweep, v, ekf);
    const SummaryRow* b = find_row(rows, sweep, v, gauss);
    if (!a || !b) continue;
    const Estimate* travel = b->metric(kPairedTravelDiff);
    const Estimate* sigma = b->metric(m.matched);
    md << "| " << (sweep == kSweepMisalignment ? fmt(1e3 * v, 3) : fmt(v, 3)) << " | "
       << (sigma && sigma->n > 0 ? fmt(sigma->mean / m.matched_per_sigma, 4) : "n/a") << " | " << converged(*a) << " / "
       << converged(*b) << " | " << fmt_estimate(a->metric(metrics::kDistToIcn095M)) << " | "
       << fmt_estimate(b->metric(metrics::kDistToIcn095M)) << " | " << fmt_estimate(travel) << " | "
       << fmt_estimate(b->metric(kPairedIterationsDiff), 1) << " | ";
    if (!travel || travel->n < 2 || !std::isfinite(travel->ci95)) {
      md << "not evaluated (fewer than 2 paired trials)";
    } else if (travel->mean + travel->ci95 < 0.0) {
      md << "**estimator wins** by " << fmt(-travel->mean) << " m";
    } else if (travel->mean - travel->ci95 > 0.0) {
      md << "**Gaussian model wins** by " << fmt(travel->mean) << " m";
    } else {
      md << "no difference established";
    }
    md << " |\n";
    ++rows_written;
  }
  if (rows_written == 0) return {};
  return md.str();
}

}  // namespace

std::string matched_error_sections(const experiment::ExperimentSettings& s, const std::vector<SummaryRow>& rows,
                                   const std::string& sweep, const std::vector<double>& values) {
  const int n = s.placement.scenario.num_uavs;
  const double unit_shape = placement::expected_split_of_independent_errors(n, 1.0).shape_lateral_rmse_m;
  const MatchedGaussian lateral{"gd_gauss_matched",
                                "Integrating the estimator at matched error",
                                "measured lateral RMSE / sqrt(2)",
                                "lateral RMSE",
                                kLocLateralRmse,
                                std::sqrt(2.0)};
  const MatchedGaussian shape{"gd_gauss_shape_matched",
                              "Integrating the estimator at matched shape error",
                              "measured shape RMSE / sqrt((2N - 3) / N) (common lateral offset and rotation about "
                              "boresight removed, placement/swarm_shape.h)",
                              "shape RMSE, the part of the error the channel sees",
                              kShapeLateralRmse,
                              unit_shape};
  const MatchedGaussian split{"gd_gauss_split_matched",
                              "Integrating the estimator at matched shape and common error",
                              "measured shape RMSE as above, plus a common-mode part (one offset per run shared by "
                              "every UAV, placement/swarm.h) at its measured common lateral offset",
                              "shape RMSE and common lateral offset",
                              kShapeLateralRmse,
                              unit_shape};
  return matched_error_section(rows, sweep, values, lateral) + matched_error_section(rows, sweep, values, shape) +
         matched_error_section(rows, sweep, values, split);
}

}  // namespace losmimo::coevaluation::report_detail
