// The golden missions' bounds (golden_invariants.h) follow from each mission's config: recomputed
// from theory, never from a replay's output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "losmimo/placement/channel.h"
#include "losmimo/placement/metrics.h"
#include "rawlog/golden_invariants.h"
#include "rawlog/rawlog_test_util.h"
#include "support/chi_square.h"

namespace losmimo::rawlog::golden {
namespace {

using test_support::load_log;
using test_support::source_path;

constexpr double kSlack = 2e-3;  // relative: the files state 4 significant digits
constexpr double kConfidence = 0.99;

// What the bounds of a mission must be, from its config and the logged trajectory's ranges.
struct Theory {
  int uavs = 0;
  int epochs = 0;
  int beacons = 0;
  int outage_uav_epochs = 0;
  int timed_out_uav_epochs = 0;
  double uav_epochs = 0.0;
  test_support::Chi2Band nees;
  double range_rmse_min_m = 0.0;
  double rmse_max_m = 0.0;
  double start_icn = 0.0;
  double target_icn = 0.0;
};

// The theory assumes a beacon every epoch outside the per-UAV outages, no outliers, and the
// filter matched to the truth (the test asserts it first).
Theory theory_of(const MissionLog& log) {
  const MissionConfig& config = *log.config;
  const fusion::ClosedLoopConfig& cl = config.closed_loop;
  const localization::SimulatorConfig& truth = cl.simulator;
  Theory t;
  t.uavs = log.num_uavs;
  t.epochs = static_cast<int>(log.epochs.size());
  double range_max_m = 0.0;
  for (const auto& row : log.epochs)
    for (const LoggedUavEpoch& e : row)
      if (e.truth_m) range_max_m = std::max(range_max_m, e.truth_m->norm());
  // Beacons: every UAV-epoch outside the outage windows. Fallback: at least the outage
  // epochs from the degraded_after_epochs-th on (a UAV without a beacon at epoch 0 starts
  // from the degraded start-cube prior: all of them), at most every outage epoch.
  t.beacons = t.uavs * t.epochs;
  for (const fusion::UavBeaconOutage& o : cl.outages) {
    const int first = std::min(o.window.first_epoch, t.epochs);
    const int end = std::min(o.window.first_epoch + o.window.num_epochs, t.epochs);
    t.outage_uav_epochs += end - first;
    const int degraded_from = first == 0 ? 0 : first + cl.filter.degraded_after_epochs - 1;
    t.timed_out_uav_epochs += std::max(0, end - degraded_from);
  }
  t.beacons -= t.outage_uav_epochs;
  t.uav_epochs = static_cast<double>(t.uavs) * t.epochs;
  // NEES: the average of `uavs` independent chi2(3) (one epoch; or every epoch, if each UAV's
  // NEES were fully correlated over epochs, the widest case) at kConfidence.
  t.nees = test_support::chi2_average_band(3, t.uavs, kConfidence);
  // Line of sight: at best the steady-state Kalman variance of a random walk with the dead
  // reckoning's floor (q = floor^2) measured by the range (r = sigma_r^2) every epoch,
  // p = (-q + sqrt(q^2 + 4 q r)) / 2; times the lower 0.5% quantile of chi2(uavs) / uavs.
  const double q = truth.dr_sigma_floor_m * truth.dr_sigma_floor_m;
  const double r = truth.sigma_range_m * truth.sigma_range_m;
  const double p_los_m2 = 0.5 * (-q + std::sqrt(q * q + 4.0 * q * r));
  t.range_rmse_min_m = std::sqrt(p_los_m2 * test_support::chi2_quantile(t.uavs, 0.5 * (1.0 - kConfidence)) / t.uavs);
  // 3-D: at worst the beacon-only fix (range sigma along, range x angle sigma across, at the
  // largest logged range), times the upper 0.5% quantile of chi2(3 uavs) / (3 uavs).
  const double lateral_sigma_m = range_max_m * truth.sigma_angle_rad;
  const double beacon_only_rmse_m = std::sqrt(r + 2.0 * lateral_sigma_m * lateral_sigma_m);
  t.rmse_max_m = beacon_only_rmse_m *
                 std::sqrt(test_support::chi2_quantile(3.0 * t.uavs, 0.5 * (1.0 + kConfidence)) / (3.0 * t.uavs));
  // Final ICN: converged runs reached the target; capped runs did not, but beat the start.
  const placement::Scenario& scenario = config.placement.scenario;
  t.start_icn = placement::evaluate_link(placement::ChannelModel(scenario).matrix(mission_start_positions_m(config)),
                                         scenario.noise_variance())
                    .icn;
  t.target_icn = config.placement.run.target_icn;
  return t;
}

// A file value must be the theory's, rounded outward by at most kSlack.
void expect_low(const Bounds& b, const std::string& key, double theory, const std::string& where) {
  const double v = std::stod(b.at(key).value);
  EXPECT_LE(v, theory * (1.0 + 1e-12)) << where << key;
  EXPECT_GE(v, theory * (1.0 - kSlack)) << where << key;
}
void expect_high(const Bounds& b, const std::string& key, double theory, const std::string& where) {
  const double v = std::stod(b.at(key).value);
  EXPECT_GE(v, theory * (1.0 - 1e-12)) << where << key;
  EXPECT_LE(v, theory * (1.0 + kSlack)) << where << key;
}

// One variant's bounds against the theory of its mission's log.
void expect_bounds_follow(const Bounds& b, const Theory& t, const MissionLog& log, const std::string& where) {
  EXPECT_EQ(b.at("status").value, log.run_end.status) << where;
  EXPECT_EQ(std::stoi(b.at("epochs").value), t.epochs) << where;
  if (log.run_end.status == "converged") {
    EXPECT_EQ(std::stod(b.at("final_icn_min").value), t.target_icn) << where;
    EXPECT_EQ(std::stod(b.at("final_icn_max").value), 1.0) << where;
  } else {
    EXPECT_EQ(t.epochs, log.config->placement.run.max_iterations) << where;
    expect_low(b, "final_icn_min", t.start_icn, where);
    EXPECT_EQ(std::stod(b.at("final_icn_max").value), t.target_icn) << where;
  }
  expect_low(b, "nees_epoch_low", t.nees.low, where);
  expect_high(b, "nees_epoch_high", t.nees.high, where);
  expect_low(b, "nees_mean_low", t.nees.low, where);
  expect_high(b, "nees_mean_high", t.nees.high, where);
  EXPECT_EQ(std::stod(b.at("nees_epoch_min_fraction").value), 0.9) << where;
  expect_low(b, "range_rmse_min_m", t.range_rmse_min_m, where);
  expect_high(b, "rmse_max_m", t.rmse_max_m, where);
  EXPECT_EQ(std::stoi(b.at("beacons").value), t.beacons) << where;
  if (t.outage_uav_epochs == 0) {
    EXPECT_EQ(std::stod(b.at("fallback_fraction_min").value), 0.0) << where;
    EXPECT_EQ(std::stod(b.at("fallback_fraction_max").value), 0.0) << where;
  } else {
    expect_low(b, "fallback_fraction_min", t.timed_out_uav_epochs / t.uav_epochs, where);
    expect_high(b, "fallback_fraction_max", t.outage_uav_epochs / t.uav_epochs, where);
  }
}

// The bounds recomputed from each mission's config (and the logged trajectory's ranges), never
// from a replay's output.
TEST(GoldenInvariants, Bounds_FollowFromTheMissionsConfig) {
  for (const std::string& mission : shipped_missions()) {
    const std::string dir = source_path("datasets/missions/" + mission);
    const InvariantsFile file = read_invariants(dir + "/invariants.ini");
    const MissionLog log = load_log(dir + "/mission.rawlog");
    ASSERT_TRUE(log.config) << mission;
    const fusion::ClosedLoopConfig& cl = log.config->closed_loop;
    const localization::SimulatorConfig& truth = cl.simulator;
    // The theory's assumptions.
    ASSERT_EQ(truth.beacon_period_epochs, 1) << mission;
    ASSERT_TRUE(truth.outages.empty()) << mission;
    ASSERT_EQ(truth.outlier_fraction, 0.0) << mission;
    ASSERT_EQ(cl.filter.noise.sigma_range_m, truth.sigma_range_m) << mission;
    ASSERT_EQ(cl.filter.noise.sigma_angle_rad, truth.sigma_angle_rad) << mission;
    const Theory t = theory_of(log);
    for (const std::string& v : listed_variants(file)) {
      expect_bounds_follow(bounds_of(file, v), t, log, mission + " [" + v + "] ");
    }
  }
}

}  // namespace
}  // namespace losmimo::rawlog::golden
