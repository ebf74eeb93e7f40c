// The closed loop of issue 5: GD placement on filtered beliefs, BF fallback when a belief is
// degraded. Paper scenario (16 UAVs, 4 x 4 BS, 1 km), actuation error 0.02 m. Seeded, never
// retried.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <random>
#include <thread>

#include "losmimo/fusion/closed_loop.h"

namespace losmimo::fusion {
namespace {

constexpr double kSigmaAct_m = 0.02;
constexpr int kMaxIterations = 600;

placement::PlacementSettings paper_settings() {
  placement::PlacementSettings s;
  s.errors.sigma_act_m = kSigmaAct_m;
  s.run.max_iterations = kMaxIterations;
  return s;
}

Eigen::Matrix3Xd start_positions(const placement::Scenario& scenario, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return placement::random_start_positions_m(scenario, rng);
}

ClosedLoopConfig nominal_config(const placement::Scenario& scenario) {
  return matched_closed_loop_config(localization::SimulatorConfig{}, scenario);
}

void print(const std::string& label, const ClosedLoopRun& r) {
  const ClosedLoopStats& s = r.stats;
  int bf = 0;
  for (int n : s.bf_fallback_iterations) bf += n;
  std::cout << "[closed_loop] " << label << ": " << placement::to_string(r.run.status) << " in "
            << r.run.iterations << " it, travel to 0.95 " << r.run.icn095.placement_dist_m
            << " m; rmse " << s.rmse_m << " m (lateral " << s.lateral_rmse_m << "), filter "
            << s.filter_rmse_m << " (lateral " << s.filter_lateral_rmse_m << "), beacon-only "
            << s.beacon_only_rmse_m << " (lateral " << s.beacon_only_lateral_rmse_m
            << "); NEES " << s.average_nees << " (filter " << s.filter_average_nees
            << "); BF iterations " << bf << ", escapes " << s.escapes << "\n";
}

TEST(ClosedLoop, NominalEkf_ConvergesFromMostStartsAndBeatsTheBeaconAlone) {
  // GIVEN: the paper scenario, the default beacon (0.1 m per axis at 1 km), matched EKF.
  const placement::PlacementSettings settings = paper_settings();
  const ClosedLoopConfig config = nominal_config(settings.scenario);
  constexpr int kStarts = 5;
  int converged = 0;
  for (int i = 0; i < kStarts; ++i) {
    // WHEN
    const ClosedLoopRun r =
        run_closed_loop(settings, start_positions(settings.scenario, 100 + i), config, 200 + i);
    print("nominal ekf start " + std::to_string(i), r);
    // THEN: the belief beats a single beacon fix, and nobody needed the fallback.
    if (r.run.converged()) ++converged;
    EXPECT_LT(r.stats.rmse_m, r.stats.beacon_only_rmse_m);
    EXPECT_LT(r.stats.lateral_rmse_m, r.stats.beacon_only_lateral_rmse_m);
    for (int n : r.stats.bf_fallback_iterations) EXPECT_EQ(n, 0);
  }
  EXPECT_GE(converged, 4);
}

TEST(ClosedLoop, BeaconRemovedForOneUavFromTheStart_ThatUavRunsBfAndTheRunConverges) {
  // GIVEN: UAV 3 never receives the beacon; the others are nominal.
  const placement::PlacementSettings settings = paper_settings();
  ClosedLoopConfig config = nominal_config(settings.scenario);
  constexpr int kLost = 3;
  config.outages.push_back({kLost, {0, 1'000'000}});
  // WHEN
  const ClosedLoopRun r =
      run_closed_loop(settings, start_positions(settings.scenario, 100), config, 200);
  print("one UAV without beacon", r);
  // THEN
  EXPECT_TRUE(r.run.converged());
  EXPECT_EQ(r.stats.bf_fallback_iterations[kLost], r.run.iterations);
  EXPECT_EQ(r.stats.gd_iterations[kLost], 0);
  for (int m = 0; m < settings.scenario.num_uavs; ++m) {
    if (m != kLost) {
      EXPECT_EQ(r.stats.bf_fallback_iterations[m], 0) << "UAV " << m;
    }
  }
}

TEST(ClosedLoop, BeaconOutageForFourUavsMidMission_TheyFallBackAndReturnToGd) {
  // GIVEN: UAVs 0, 5, 10, 15 lose the beacon for epochs 10..39; degraded after 5 epochs.
  const placement::PlacementSettings settings = paper_settings();
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.filter.degraded_after_epochs = 5;
  constexpr int kFirst = 10, kEpochs = 30;
  const std::vector<int> lost = {0, 5, 10, 15};
  for (int m : lost) config.outages.push_back({m, {kFirst, kEpochs}});
  // WHEN
  const ClosedLoopRun r =
      run_closed_loop(settings, start_positions(settings.scenario, 101), config, 201);
  print("outage of 4 UAVs", r);
  // THEN: the swarm converges after the outage, so the return to GD is observable.
  ASSERT_TRUE(r.run.converged());
  const int outage_end_iteration = kFirst + kEpochs + 1;  // epoch k is iteration k + 1
  ASSERT_GT(r.run.iterations, outage_end_iteration + 5);
  for (int m = 0; m < settings.scenario.num_uavs; ++m) {
    const bool is_lost = std::find(lost.begin(), lost.end(), m) != lost.end();
    if (!is_lost) {
      EXPECT_EQ(r.stats.bf_fallback_iterations[m], 0) << "UAV " << m;
      continue;
    }
    // Degraded from the 5th epoch without beacon to the first epoch with one again.
    EXPECT_GE(r.stats.bf_fallback_iterations[m], kEpochs - 5) << "UAV " << m;
    EXPECT_LE(r.stats.bf_fallback_iterations[m], kEpochs) << "UAV " << m;
    EXPECT_LE(r.stats.last_fallback_iteration[m], outage_end_iteration) << "UAV " << m;
    for (int it = outage_end_iteration + 1; it <= r.run.iterations; ++it) {
      EXPECT_EQ(r.stats.mode_trace[it - 1][m], static_cast<char>(UavMode::kGd))
          << "UAV " << m << " iteration " << it;
    }
  }
}

}  // namespace
}  // namespace losmimo::fusion
