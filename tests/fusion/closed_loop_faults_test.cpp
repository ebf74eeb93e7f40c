// Faults in the closed loop: an unresponsive UAV is found by the master and ends the
// run with kUavUnresponsive; NaN beacons, displacements and CSI rows are dropped before the
// filter, the refinement and placement, and so are implausible beacons (beyond
// max_beacon_range_m); a non-finite filter state ends the run with
// kNumericalFault. Paper scenario (16 UAVs, 4 x 4 BS, 1 km). Seeded, never retried.
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "losmimo/fusion/closed_loop.h"
#include "losmimo/localization/position/robustness.h"
#include "losmimo/placement/common/input_error.h"
#include "fusion/closed_loop_fixtures.h"

namespace losmimo::fusion {
namespace {

using test_support::contains;
using test_support::LoopRecorder;
using test_support::nominal_config;
using test_support::paper_settings;
using test_support::start_positions;

// One run through ClosedLoopPlanner and run_placement, keeping the planner's final beliefs.
struct Outcome {
  placement::RunResult run;
  ClosedLoopStats stats;
  std::vector<localization::Belief> beliefs;
};
Outcome run(const placement::PlacementSettings& settings, const ClosedLoopConfig& config, std::uint64_t seed,
            ClosedLoopObserver* observer = nullptr) {
  const placement::ChannelModel model(settings.scenario);
  placement::ErrorModel errors = settings.errors;
  errors.sigma_loc_m = 0.0;
  placement::Swarm swarm(model, start_positions(settings.scenario, 100 + seed), errors, seed);
  ClosedLoopPlanner planner(settings.scenario, settings.gd, settings.bf, config, 200 + seed);
  planner.set_observer(observer);
  Outcome out;
  out.run = placement::run_placement(planner, swarm, settings.run);
  out.stats = planner.stats();
  out.beliefs = planner.beliefs();
  return out;
}

void expect_finite_beliefs(const Outcome& o) {
  for (std::size_t m = 0; m < o.beliefs.size(); ++m) {
    EXPECT_FALSE(localization::health_problem(o.beliefs[m]).has_value()) << "UAV " << m;
  }
}

TEST(ClosedLoopFaults, UavUnresponsiveFromIteration5_EndsTheRunNamingItWithinNPlus1Iterations) {
  // GIVEN: UAV 4 stops responding at iteration 5; the master's threshold is 3 iterations.
  const placement::PlacementSettings settings = paper_settings(600);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  constexpr int kUav = 4, kFrom = 5, kThreshold = 3;
  config.unresponsive_after_iterations = kThreshold;
  config.faults.push_back({UavFaultKind::kUnresponsive, kUav, kFrom, 0});
  LoopRecorder recorder;
  // WHEN
  const Outcome o = run(settings, config, 1, &recorder);
  // THEN: found at iteration 5 + 3 - 1 = 7, not at the cap, with UAV, duration and start.
  EXPECT_EQ(o.run.status, placement::RunStatus::kUavUnresponsive);
  EXPECT_EQ(o.run.iterations, kFrom + kThreshold - 1);
  EXPECT_LE(o.run.iterations, kFrom + kThreshold);
  EXPECT_EQ(o.run.fault_uav, kUav);
  EXPECT_EQ(o.run.fault, "UAV 4: no measurement and no motion for 3 iterations (since iteration 5) at iteration 7");
  EXPECT_EQ(placement::to_string(o.run.status), "uav_unresponsive");
  // The dead UAV hovered: no motion after iteration 4, and no epoch from it after epoch 3.
  ASSERT_TRUE(recorder.positions_after.count(kFrom - 1));
  EXPECT_EQ(o.run.final_m.col(kUav), recorder.positions_after[kFrom - 1].col(kUav));
  for (const EpochObservation& e : recorder.epochs) {
    if (e.uav == kUav) {
      EXPECT_LT(e.epoch, kFrom - 1);
    }
  }
  for (int m = 0; m < settings.scenario.num_uavs; ++m) {
    EXPECT_EQ(o.stats.silent_iterations[m], m == kUav ? kThreshold : 0) << "UAV " << m;
    if (m != kUav) {
      EXPECT_NE(o.run.final_m.col(m), recorder.positions_after[kFrom - 1].col(m));
    }
  }
  EXPECT_EQ(o.stats.mode_trace[kFrom - 1][kUav], '-');
  expect_finite_beliefs(o);
}

TEST(ClosedLoopFaults, UavUnresponsiveFromTheStartWithThreshold1_IsFoundAtIteration1) {
  const placement::PlacementSettings settings = paper_settings(100);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.unresponsive_after_iterations = 1;
  config.faults.push_back({UavFaultKind::kUnresponsive, 15, 1, 0});
  const Outcome o = run(settings, config, 2);
  EXPECT_EQ(o.run.status, placement::RunStatus::kUavUnresponsive);
  EXPECT_EQ(o.run.iterations, 1);
  EXPECT_EQ(o.run.fault, "UAV 15: no measurement and no motion for 1 iteration (since iteration 1) at iteration 1");
}

TEST(ClosedLoopFaults, UavSilentForFewerIterationsThanTheThreshold_IsNotFlagged) {
  // GIVEN: UAV 2 is silent for iterations 5 and 6 only; threshold 3.
  const placement::PlacementSettings settings = paper_settings(40);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.faults.push_back({UavFaultKind::kUnresponsive, 2, 5, 2});
  // WHEN
  const Outcome o = run(settings, config, 3);
  // THEN: the run goes on (to the target or the cap) and the silence is counted.
  EXPECT_FALSE(o.run.faulted()) << o.run.fault;
  EXPECT_GT(o.run.iterations, 7);
  EXPECT_EQ(o.stats.silent_iterations[2], 2);
  expect_finite_beliefs(o);
}

TEST(ClosedLoopFaults, NoFaults_NoSilenceNoRejectionAndTheSameRunAsWithAnEmptyFaultList) {
  const placement::PlacementSettings settings = paper_settings(60);
  const ClosedLoopConfig config = nominal_config(settings.scenario);
  ClosedLoopConfig config_other_threshold = config;
  config_other_threshold.unresponsive_after_iterations = 1;  // never triggers without faults
  const Outcome a = run(settings, config, 4);
  const Outcome b = run(settings, config_other_threshold, 4);
  EXPECT_FALSE(a.run.faulted());
  EXPECT_FALSE(b.run.faulted());
  EXPECT_EQ(a.run.iterations, b.run.iterations);
  EXPECT_EQ(a.run.final_m, b.run.final_m);
  EXPECT_EQ(a.stats.rejected_measurements(), 0);
  for (int n : a.stats.silent_iterations) EXPECT_EQ(n, 0);
}

TEST(ClosedLoopFaults, NanBeacon_IsRejectedBeforeTheFilterAndTheRunContinuesFinite) {
  // GIVEN: UAV 1's beacons have a NaN range from iteration 3 (epoch 2) on.
  const placement::PlacementSettings settings = paper_settings(40);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.faults.push_back({UavFaultKind::kNanBeacon, 1, 3, 0});
  LoopRecorder recorder;
  // WHEN
  const Outcome o = run(settings, config, 5, &recorder);
  // THEN: one rejection per epoch 2 .. iterations - 1, the filter never saw them, and the UAV
  // (beacon-less) falls back to BF once its belief is degraded; nothing is non-finite.
  EXPECT_FALSE(o.run.faulted()) << o.run.fault;
  EXPECT_EQ(o.stats.rejected_beacons[1], o.run.iterations - 2);
  EXPECT_EQ(o.stats.rejected_measurements(), o.run.iterations - 2);
  for (const EpochObservation& e : recorder.epochs) {
    if (e.beacon) {
      EXPECT_TRUE(localization::is_finite(*e.beacon));
    }
    if (e.uav == 1 && e.epoch >= 2) {
      EXPECT_FALSE(e.beacon.has_value()) << "epoch " << e.epoch;
    }
  }
  if (o.run.iterations > 2 + config.filter.degraded_after_epochs) {
    EXPECT_GT(o.stats.bf_fallback_iterations[1], 0);
  }
  expect_finite_beliefs(o);
  EXPECT_TRUE(o.run.final_m.allFinite());
}

TEST(ClosedLoopFaults, NanDisplacement_IsRejectedAndTheFilterPredictsWithoutIt) {
  // GIVEN: UAV 6's dead reckoning reads NaN in iterations 4 .. 8.
  const placement::PlacementSettings settings = paper_settings(40);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.faults.push_back({UavFaultKind::kNanDisplacement, 6, 4, 5});
  LoopRecorder recorder;
  // WHEN
  const Outcome o = run(settings, config, 6, &recorder);
  // THEN
  EXPECT_FALSE(o.run.faulted()) << o.run.fault;
  ASSERT_GT(o.run.iterations, 8);
  EXPECT_EQ(o.stats.rejected_displacements[6], 5);
  for (const EpochObservation& e : recorder.epochs) {
    if (e.measured_displacement_m) {
      EXPECT_TRUE(e.measured_displacement_m->allFinite());
    }
    if (e.uav == 6 && e.epoch >= 3 && e.epoch <= 7) {
      EXPECT_FALSE(e.measured_displacement_m.has_value());
    }
  }
  expect_finite_beliefs(o);
}

TEST(ClosedLoopFaults, NanCsi_IsRejectedBeforeTheRefinement) {
  // GIVEN: refinement with CSI; UAV 0's CSI row has a NaN entry from iteration 2 (epoch 1) on.
  const placement::PlacementSettings settings = paper_settings(8);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.refine = true;
  config.faults.push_back({UavFaultKind::kNanCsi, 0, 2, 0});
  LoopRecorder recorder;
  // WHEN
  const Outcome o = run(settings, config, 7, &recorder);
  // THEN: UAV 0 refines without CSI from epoch 1 on; every row the refinement used is finite.
  EXPECT_FALSE(o.run.faulted()) << o.run.fault;
  EXPECT_EQ(o.stats.rejected_csi[0], o.run.iterations - 1);
  for (const EpochObservation& e : recorder.epochs) {
    if (e.csi) {
      EXPECT_TRUE(e.csi->y.allFinite());
    }
    if (e.uav == 0) {
      EXPECT_EQ(e.csi.has_value(), e.epoch == 0) << "epoch " << e.epoch;
    }
    if (e.uav != 0) {
      EXPECT_TRUE(e.csi.has_value());
    }
  }
  expect_finite_beliefs(o);
}

TEST(ClosedLoopFaults, FilterStateOverflow_EndsTheRunWithANumericalFaultNamingUavAndEpoch) {
  // GIVEN: no beacon at epoch 0 (prior), then only absurd beacons (range ~ N(r, (1e300 m)^2)),
  // with the plausibility screen opened (a sensor without a range limit): gated twice, then the
  // reset rule takes a beacon fix whose covariance overflows.
  const placement::PlacementSettings settings = paper_settings(100);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.simulator.outlier_fraction = 1.0;
  config.simulator.outlier_sigma_range_m = 1e300;
  config.filter.max_beacon_range_m = std::numeric_limits<double>::max();
  config.filter.reset_after_rejections = 2;
  for (int m = 0; m < settings.scenario.num_uavs; ++m) config.outages.push_back({m, {0, 1}});
  // WHEN
  const Outcome o = run(settings, config, 8);
  // THEN
  EXPECT_EQ(o.run.status, placement::RunStatus::kNumericalFault);
  EXPECT_GE(o.run.fault_uav, 0);
  EXPECT_LE(o.run.iterations, 20);
  EXPECT_TRUE(contains(o.run.fault, "UAV " + std::to_string(o.run.fault_uav) + ": EKF ")) << o.run.fault;
  EXPECT_TRUE(contains(o.run.fault, "non-finite")) << o.run.fault;
  EXPECT_TRUE(contains(o.run.fault, " at epoch ")) << o.run.fault;
  EXPECT_TRUE(o.run.final_m.allFinite());
}

TEST(ClosedLoopFaults, AbsurdBeacons_AreDroppedByTheMasterAndTheRunGoesOn) {
  // GIVEN: every beacon absurd (range ~ N(r, (1e300 m)^2)), epoch 0 included, and the default
  // plausibility screen (max_beacon_range_m = 1e5 m).
  const placement::PlacementSettings settings = paper_settings(30);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.simulator.outlier_fraction = 1.0;
  config.simulator.outlier_sigma_range_m = 1e300;
  LoopRecorder recorder;
  // WHEN
  const Outcome o = run(settings, config, 9, &recorder);
  // THEN: no fault; not one beacon reached the filter or the refinement; each was counted
  // (all but a vanishing fraction of N(r, 1e300^2) draws lie beyond 1e5 m).
  EXPECT_NE(o.run.status, placement::RunStatus::kNumericalFault) << o.run.fault;
  ASSERT_FALSE(recorder.epochs.empty());
  for (const EpochObservation& e : recorder.epochs) {
    EXPECT_FALSE(e.beacon.has_value()) << "epoch " << e.epoch << ", UAV " << e.uav;
  }
  const int uavs = settings.scenario.num_uavs;
  for (int m = 0; m < uavs; ++m) {
    // one beacon per epoch (beacon_period_epochs = 1), epochs 0..iterations - 1
    EXPECT_EQ(o.stats.rejected_beacons[m], o.run.iterations) << "UAV " << m;
  }
  expect_finite_beliefs(o);
  EXPECT_TRUE(o.run.final_m.allFinite());
}

TEST(ClosedLoopFaults, AbsurdBeaconAtEpoch0WithTheScreenOpened_EndsTheRunAtIteration0) {
  const placement::PlacementSettings settings = paper_settings(100);
  ClosedLoopConfig config = nominal_config(settings.scenario);
  config.simulator.outlier_fraction = 1.0;
  config.simulator.outlier_sigma_range_m = 1e300;
  config.filter.max_beacon_range_m = std::numeric_limits<double>::max();
  const Outcome o = run(settings, config, 9);
  EXPECT_EQ(o.run.status, placement::RunStatus::kNumericalFault);
  EXPECT_EQ(o.run.iterations, 0);
  EXPECT_TRUE(contains(o.run.fault, ": initial beacon fix ")) << o.run.fault;
  EXPECT_TRUE(contains(o.run.fault, "at epoch 0 at iteration 0")) << o.run.fault;
}

TEST(ClosedLoopFaults, BadFaultSettings_AreRejectedNamingTheField) {
  const placement::Scenario scenario;
  const auto message = [&](const ClosedLoopConfig& c) {
    try {
      validate(c);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  ClosedLoopConfig c = nominal_config(scenario);
  c.unresponsive_after_iterations = 0;
  EXPECT_EQ(message(c), "closed_loop.unresponsive_after_iterations = 0: must be in [1, 1000]");
  c = nominal_config(scenario);
  c.faults.push_back({UavFaultKind::kUnresponsive, 1, 0, 0});
  EXPECT_EQ(message(c), "closed_loop.faults[0].from_iteration = 0: must be in [1, 10000000]");
  c = nominal_config(scenario);
  c.faults.push_back({UavFaultKind::kNanBeacon, 1, 1, -1});
  EXPECT_EQ(message(c), "closed_loop.faults[0].num_iterations = -1: must be in [0, 10000000]");
  c = nominal_config(scenario);
  c.faults.push_back({UavFaultKind::kNanCsi, 1, 1, 0});
  EXPECT_TRUE(contains(message(c), "faults[0] = nan_csi: needs refine = true")) << message(c);
  // A UAV index beyond the swarm is found at start().
  const placement::PlacementSettings settings = paper_settings(10);
  c = nominal_config(scenario);
  c.faults.push_back({UavFaultKind::kUnresponsive, 16, 1, 0});
  EXPECT_THROW(run(settings, c, 1), std::invalid_argument);
  EXPECT_EQ(uav_fault_kind_from_string("nan_displacement"), UavFaultKind::kNanDisplacement);
  EXPECT_THROW(uav_fault_kind_from_string("dead"), std::invalid_argument);
}

}  // namespace
}  // namespace losmimo::fusion
