#pragma once
// The capacity planner's claims as metrics, with [experiment] capacity_columns = true: the
// columns below follow the milestone columns in trials.csv and summary.csv, for every sweep and
// algorithm, and report.md gets a section on them. The claims (Hanna, Krijestorac, Cabric, IEEE
// JSAC 2021, abstract): an online distributed placement that seeks capacity with bounded
// translation of each UAV, robust under Rician fading and motion disturbance.
//
//   capacity_fraction   C(H) / C_max at the final positions. H is the LoS channel there (the
//                       geometry; with fading the sum-rate columns hold the true channel's),
//                       C is capacity.h's capacity_bps_hz and C_max its orthogonal_capacity_bps_hz
//                       under [cap] power. With equal power (Q = I, one unit per BS antenna) the
//                       far-field H has tr(H H^H) = Nr Nt at any positions, so by Jensen
//                         C <= C_max = min(Nr, Nt) log2(1 + SNR max(Nr, Nt)),
//                       reached exactly when the smaller Gram matrix is max(Nr, Nt) I (ICN 1:
//                       orthogonal columns of norm sqrt(Nr) when Nr >= Nt). 1 is the single-user
//                       bound; with gain_model = exact the fraction can pass 1 slightly.
//   translation_median_m, translation_p95_m, translation_max_m
//                       over the swarm's UAVs n, d_n = |q_n(final) - q_n(start)| (true positions,
//                       metres): the median (mean of the two middle values for an even count), the
//                       95th percentile (nearest rank: the ceil(0.95 Nr)-th smallest) and the largest.
//   translation_max_per_spacing
//                       translation_max_m / d_r with d_r = lambda R / (bs_rows d_t), the receive
//                       URA's slot spacing (ura.h): the scale of the lattice an orthogonal swarm
//                       settles on, against which "bounded" is judged.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "losmimo/placement/experiment/metrics.h"
#include "losmimo/placement/experiment/summary.h"
#include "losmimo/placement/capacity.h"
#include "losmimo/placement/scenario.h"

namespace losmimo::experiment {

namespace metrics {
inline constexpr ExtensionMetric kCapacityFraction{
    {"capacity_fraction"}, "", "capacity of the LoS channel at the final positions / the orthogonal bound C_max"};
inline constexpr ExtensionMetric kTranslationMedianM{
    {"translation_median_m"}, "m", "median over the UAVs of the distance from start to final position"};
inline constexpr ExtensionMetric kTranslationP95M{
    {"translation_p95_m"}, "m", "95th percentile (nearest rank) over the UAVs of that distance"};
inline constexpr ExtensionMetric kTranslationMaxM{{"translation_max_m"}, "m", "largest such distance"};
inline constexpr ExtensionMetric kTranslationMaxPerSpacing{
    {"translation_max_per_spacing"}, "", "translation_max_m over the receive URA's slot spacing lambda R / (n d_t)"};
}  // namespace metrics

// Their table, in column order.
const ExtensionMetrics& capacity_claim_metrics();

// The median and the nearest-rank quantile q in (0, 1] of values (NaN when empty).
double median(std::vector<double> values);
double nearest_rank_quantile(std::vector<double> values, double q);

// The values of capacity_claim_metrics() for a run of `scenario` that went from start_m to
// final_m (3 x Nr each), H_los the LoS channel at final_m, C under `power`.
MetricValues capacity_claim_values(const placement::Scenario& scenario, placement::CapPower power,
                                   const Eigen::MatrixXcd& H_los, const Eigen::Matrix3Xd& start_m,
                                   const Eigen::Matrix3Xd& final_m);
// A record's values in table order (TrialRecord::capacity_claims); std::logic_error naming the
// record when one is unset.
std::vector<double> capacity_claim_columns(const TrialRecord& record);

// report.md's section: per sweep, point and moving algorithm the columns' means, then the claims
// with the capacity planner's numbers (empty without [experiment] capacity_columns).
std::string capacity_claims_report_section(const ExperimentSettings& settings, const std::vector<SummaryRow>& rows);

}  // namespace losmimo::experiment
