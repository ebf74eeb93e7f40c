// losmimo-replay of missions with faults: a UAV that dies mid-mission, a UAV
// silent for two iterations, NaN beacons, a filter overflow part-way through an epoch. Each log
// is replayed through replay_mission and apps::run_replay_app (what losmimo-replay calls) and checked
// against the live closed loop run with the same config and seed (its observer), not against the
// log: same beliefs bit for bit, same true positions, same fallbacks, and the status and reason
// the run ended with.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "fusion/closed_loop_fixtures.h"
#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/placement/common/ini_config.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "losmimo/fusion/rawlog/mission/replay.h"
#include "losmimo/placement/metrics.h"
#include "rawlog/rawlog_test_util.h"

namespace losmimo::rawlog {
namespace {

using test_support::contains;
using test_support::load_log;
using test_support::LoopRecorder;
using test_support::read_file;
using test_support::small_mission;
using test_support::temp_path;

constexpr int kSmallUavs = 4;  // small_mission()
// The run's ICN (cached Gram matrix, placement/run.h) against the replay's (H rebuilt from the
// logged positions), as in rawlog_replay_test.cpp.
constexpr double kIcnTolerance = 1e-6;

// The live run of the mission record_mission runs (same settings, start, config and seed).
struct Live {
  fusion::ClosedLoopRun run;
  LoopRecorder seen;
};
Live run_live(const MissionConfig& config) {
  Live live;
  live.run = fusion::run_closed_loop(config.placement, mission_start_positions_m(config), config.closed_loop,
                                     config.seed, &live.seen);
  return live;
}

bool same_bits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0;
}
bool same_bits(const localization::Belief& a, const localization::Belief& b) {
  return same_bits(a.mean_m, b.mean_m) && std::memcmp(a.cov_m2.data(), b.cov_m2.data(), 9 * sizeof(double)) == 0;
}

// Every UAV-epoch the live loop observed is in the replay, not silent, with the loop's true
// position, the filter's belief bit for bit and the mean placement used bit for bit. Returns
// how many were compared.
int expect_replay_matches_live(const ReplayResult& r, const Live& live, int num_uavs) {
  int compared = 0;
  for (const fusion::EpochObservation& e : live.seen.epochs) {
    const std::size_t i = static_cast<std::size_t>(e.epoch * num_uavs + e.uav);
    if (i >= r.estimates.size()) {
      ADD_FAILURE() << "epoch " << e.epoch << " UAV " << e.uav << " missing from the replay";
      continue;
    }
    const ReplayUavEpoch& x = r.estimates[i];
    SCOPED_TRACE("epoch " + std::to_string(e.epoch) + " UAV " + std::to_string(e.uav));
    EXPECT_EQ(x.epoch, e.epoch);
    EXPECT_EQ(x.uav, e.uav);
    EXPECT_FALSE(x.silent);
    EXPECT_TRUE(x.has_truth);
    EXPECT_TRUE(same_bits(x.truth_m, e.true_position_m));
    EXPECT_TRUE(same_bits(x.filter_belief, e.filter_belief));
    EXPECT_TRUE(same_bits(x.belief.mean_m, e.belief.mean_m));
    EXPECT_EQ(x.has_beacon, e.beacon.has_value());
    ++compared;
  }
  return compared;
}

int sum(const std::vector<int>& v) {
  int n = 0;
  for (int x : v) n += x;
  return n;
}

struct AppRun {
  int code = -1;
  std::string out, err, summary_csv;
};
AppRun replay_app(const std::string& path, const std::string& out_dir) {
  std::ostringstream out, err;
  AppRun a;
  a.code = apps::run_replay_app({path, "", false, false, out_dir, false, true}, out, err);
  a.out = out.str();
  a.err = err.str();
  a.summary_csv = read_file(out_dir + "/summary.csv");
  return a;
}

TEST(RawlogReplayFaults, UavDeadFromIteration4_ReplaysUpToTheFaultAndReportsStatusAndReason) {
  for (const bool refine : {false, true}) {
    SCOPED_TRACE(refine ? "pf + ceres" : "ekf");
    // GIVEN: UAV 2 stops responding at iteration 4; the master gives up after 3 silent
    // iterations, at iteration 4 + 3 - 1 = 6. Epoch k is iteration k + 1: UAV 2 reports epochs
    // 0-2 and nothing in epochs 3-5.
    constexpr int kDead = 2, kFrom = 4, kFoundAt = 6;
    const MissionConfig config = small_mission(refine ? "pf" : "ekf", refine, "faults = unresponsive:2:4\n");
    const std::string path = temp_path(std::string("dead_uav_") + (refine ? "pf" : "ekf") + ".rawlog");
    const RecordResult rec = record_mission(config, {path, 6, {}});
    const Live live = run_live(config);
    ASSERT_EQ(live.run.run.status, placement::RunStatus::kUavUnresponsive);
    ASSERT_EQ(live.run.run.iterations, kFoundAt);
    ASSERT_EQ(rec.run.run.final_m, live.run.run.final_m);
    // WHEN
    const MissionLog log = load_log(path);
    const ReplayResult r = replay_mission(log, {});
    // THEN: a complete log that says how the run ended, in the loop's own words.
    EXPECT_TRUE(log.complete) << log.stop_description();
    EXPECT_TRUE(log.run_faulted());
    EXPECT_EQ(log.run_end.status, "uav_unresponsive");
    EXPECT_EQ(log.run_end.fault_uav, kDead);
    EXPECT_EQ(log.run_end.fault,
              "UAV 2: no measurement and no motion for 3 iterations (since iteration 4) at iteration 6");
    ASSERT_EQ(static_cast<int>(log.epochs.size()), kFoundAt);
    // AND: every epoch the loop observed is reproduced bit for bit (6 x 4 - 3 silent).
    EXPECT_EQ(expect_replay_matches_live(r, live, kSmallUavs), kFoundAt * kSmallUavs - 3);
    EXPECT_EQ(r.filter_beliefs_bitwise_equal, kFoundAt * kSmallUavs - 3);
    EXPECT_EQ(r.silent_uav_epochs, 3);
    // AND: the dead UAV's belief is held where the loop left it, at epoch kFrom - 2 = 2.
    const fusion::EpochObservation* last_heard = nullptr;
    for (const fusion::EpochObservation& e : live.seen.epochs)
      if (e.uav == kDead) last_heard = &e;
    ASSERT_NE(last_heard, nullptr);
    EXPECT_EQ(last_heard->epoch, kFrom - 2);
    for (int k = kFrom - 1; k < kFoundAt; ++k) {
      const ReplayUavEpoch& x = r.estimates[static_cast<std::size_t>(k * kSmallUavs + kDead)];
      EXPECT_TRUE(x.silent) << "epoch " << k;
      EXPECT_FALSE(x.has_truth) << "epoch " << k;
      EXPECT_TRUE(same_bits(x.filter_belief, last_heard->filter_belief)) << "epoch " << k;
      EXPECT_TRUE(same_bits(x.belief.mean_m, last_heard->belief.mean_m)) << "epoch " << k;
    }
    // AND: the fallbacks are the loop's (a silent UAV is not commanded, so never a fallback).
    EXPECT_EQ(r.fallback_uav_epochs, sum(live.run.stats.bf_fallback_iterations));
    // AND: the ICN is the run's while every truth is logged, unknown after, and the final row
    // is the ICN of the loop's final positions.
    double icn_sum = 0.0;
    for (int k = 0; k < kFoundAt; ++k) {
      if (k < kFrom - 1) {
        EXPECT_NEAR(r.epochs[k].icn, live.run.run.trace[k].icn, kIcnTolerance) << "epoch " << k;
        icn_sum += live.run.run.trace[k].icn;
      } else {
        EXPECT_TRUE(std::isnan(r.epochs[k].icn)) << "epoch " << k;
      }
    }
    EXPECT_NEAR(r.mean_icn, icn_sum / (kFrom - 1), kIcnTolerance);
    const placement::ChannelModel model(config.placement.scenario);
    ASSERT_TRUE(r.epochs.back().final_positions);
    EXPECT_EQ(r.epochs.back().epoch, kFoundAt);
    EXPECT_NEAR(r.final_icn, placement::inverse_condition_number(model.matrix(live.run.run.final_m)), kIcnTolerance);
    // AND: the app replays it, writes the outputs, prints status and reason, and exits 3.
    const AppRun app = replay_app(path, temp_path(std::string("dead_uav_out_") + (refine ? "pf" : "ekf")));
    EXPECT_EQ(app.code, 3) << app.err;
    EXPECT_TRUE(contains(app.err, "ended by a fault (uav_unresponsive): " + log.run_end.fault)) << app.err;
    EXPECT_TRUE(contains(app.out, "\nstatus = uav_unresponsive\nfault_uav = 2\nfault = " + log.run_end.fault))
        << app.out;
    EXPECT_TRUE(contains(app.summary_csv, "\nstatus,uav_unresponsive\nfault_uav,2\nfault," + log.run_end.fault + "\n"))
        << app.summary_csv;
    EXPECT_TRUE(contains(app.summary_csv, "\nepochs,6\n")) << app.summary_csv;
  }
}

// Regression: the replay stepped a silent UAV's filter with a "missing" displacement, so its
// belief drifted from the loop's and every later belief of that UAV differed (39 of 46 equal).
TEST(RawlogReplayFaults, UavSilentForTwoIterations_EveryLaterBeliefIsReproducedBitwise) {
  for (const std::string filter : {"ekf", "pf"}) {
    SCOPED_TRACE(filter);
    // GIVEN: UAV 3 silent in iterations 4 and 5 (epochs 3, 4), fewer than the 3 that end a run.
    const MissionConfig config = small_mission(filter, filter == "pf", "faults = unresponsive:3:4:2\n");
    const std::string path = temp_path("silent_uav_" + filter + ".rawlog");
    const RecordResult rec = record_mission(config, {path, 6, {}});
    const Live live = run_live(config);
    ASSERT_FALSE(live.run.run.faulted()) << live.run.run.fault;
    ASSERT_GT(rec.epochs, 6);
    // WHEN
    const MissionLog log = load_log(path);
    const ReplayResult r = replay_mission(log, {});
    // THEN
    EXPECT_TRUE(log.complete) << log.stop_description();
    EXPECT_FALSE(log.run_faulted());
    const int observed = rec.epochs * kSmallUavs - 2;
    EXPECT_EQ(expect_replay_matches_live(r, live, kSmallUavs), observed);
    EXPECT_EQ(r.filter_beliefs_compared, observed);
    EXPECT_EQ(r.filter_beliefs_bitwise_equal, observed);
    if (filter == "pf") {
      EXPECT_EQ(r.refined_means_bitwise_equal, observed);
    }
    EXPECT_EQ(r.silent_uav_epochs, 2);
    EXPECT_TRUE(r.estimates[3 * kSmallUavs + 3].silent);
    EXPECT_TRUE(r.estimates[4 * kSmallUavs + 3].silent);
    EXPECT_EQ(r.fallback_uav_epochs, sum(live.run.stats.bf_fallback_iterations));
    EXPECT_NEAR(r.average_nees, live.run.stats.average_nees, 1e-9 * live.run.stats.average_nees);
    // AND: a complete log of a run without a fault: exit 0, no fault rows.
    const AppRun app = replay_app(path, temp_path("silent_uav_out_" + filter));
    EXPECT_EQ(app.code, 0) << app.err;
    EXPECT_TRUE(contains(app.out, "\nstatus = " + placement::to_string(live.run.run.status) + "\n")) << app.out;
    EXPECT_TRUE(contains(app.summary_csv, "\nsilent_uav_epochs,2\n")) << app.summary_csv;
    EXPECT_FALSE(contains(app.summary_csv, "fault")) << app.summary_csv;
  }
}

TEST(RawlogReplayFaults, UavDeadFromTheStart_ItsDegradedPriorIsNeverCountedAsAFallback) {
  // GIVEN: UAV 0 never responds: no beacon at epoch 0, so its belief is the degraded start-cube
  // prior, but the master never commands it (mode '-'): no BF fallback in the loop.
  const MissionConfig config = small_mission("ekf", false, "faults = unresponsive:0:1\n");
  const std::string path = temp_path("dead_from_start.rawlog");
  record_mission(config, {path, 6, {}});
  const Live live = run_live(config);
  ASSERT_EQ(live.run.run.status, placement::RunStatus::kUavUnresponsive);
  ASSERT_EQ(live.run.run.iterations, 3);
  ASSERT_EQ(live.run.stats.bf_fallback_iterations[0], 0);
  // WHEN
  const ReplayResult r = replay_mission(load_log(path), {});
  // THEN: epoch 0 is the loop's (prior included); epochs 1 and 2 hold it; no fallback counted.
  EXPECT_EQ(expect_replay_matches_live(r, live, kSmallUavs), 3 * kSmallUavs - 2);
  EXPECT_TRUE(r.estimates[0].belief.degraded);
  EXPECT_EQ(r.silent_uav_epochs, 2);
  EXPECT_EQ(r.fallback_uav_epochs, sum(live.run.stats.bf_fallback_iterations));
  EXPECT_EQ(r.fallback_uav_epochs, 0);
}

TEST(RawlogReplayFaults, NanBeaconFromIteration3_DroppedByTheMasterAndReplayedIdentically) {
  // GIVEN: UAV 3's beacons read NaN from iteration 3 (epoch 2) on; the master drops them.
  constexpr int kUav = 3, kFirstEpoch = 2;
  const MissionConfig config = small_mission("ekf", false, "faults = nan_beacon:3:3\n");
  const std::string path = temp_path("nan_beacon.rawlog");
  const RecordResult rec = record_mission(config, {path, 6, {}});
  const Live live = run_live(config);
  ASSERT_FALSE(live.run.run.faulted());
  ASSERT_GT(rec.epochs, kFirstEpoch + 2);
  EXPECT_EQ(live.run.stats.rejected_beacons[kUav], rec.epochs - kFirstEpoch);  // counted
  // WHEN
  const MissionLog log = load_log(path);
  const ReplayResult r = replay_mission(log, {});
  // THEN: the log holds no beacon of UAV 3 from epoch 2 on (nothing non-finite), and the others.
  EXPECT_TRUE(log.complete) << log.stop_description();
  for (int k = 0; k < rec.epochs; ++k) {
    EXPECT_EQ(log.epochs[k][kUav].beacon.has_value(), k < kFirstEpoch) << "epoch " << k;
    EXPECT_TRUE(log.epochs[k][0].beacon.has_value()) << "epoch " << k;
  }
  EXPECT_TRUE(log.skipped.empty());
  // AND: identical to the live run, beacon for beacon and belief for belief.
  EXPECT_EQ(expect_replay_matches_live(r, live, kSmallUavs), rec.epochs * kSmallUavs);
  EXPECT_EQ(r.filter_beliefs_bitwise_equal, rec.epochs * kSmallUavs);
  int live_beacons = 0;
  for (const fusion::EpochObservation& e : live.seen.epochs) live_beacons += e.beacon ? 1 : 0;
  EXPECT_EQ(r.num_beacons, live_beacons);
  EXPECT_EQ(r.silent_uav_epochs, 0);
  EXPECT_EQ(r.fallback_uav_epochs, sum(live.run.stats.bf_fallback_iterations));
  EXPECT_NEAR(r.rmse_m, live.run.stats.rmse_m, 1e-12);
  EXPECT_NEAR(r.average_nees, live.run.stats.average_nees, 1e-9 * live.run.stats.average_nees);
  const AppRun app = replay_app(path, temp_path("nan_beacon_out"));
  EXPECT_EQ(app.code, 0) << app.err;
  EXPECT_FALSE(contains(app.summary_csv, "fault")) << app.summary_csv;
}

// The paper scenario (16 UAVs) with absurd beacons (range ~ N(r, (1e300 m)^2), not an INI key)
// and the plausibility screen opened (no range limit)
// for UAV 1 from epoch 1; the other UAVs never get a beacon. UAV 1's filter gates them until its
// reset rule takes a fix whose covariance overflows.
MissionConfig overflow_mission() {
  std::string outages = "1:0:1";
  for (int m = 0; m < 16; ++m) {
    if (m != 1) outages += ", " + std::to_string(m) + ":0:1000000";
  }
  MissionConfig config = load_mission_config(
      common::IniConfig::from_string("[errors]\nsigma_act_m = 0.02\n[placement]\nmax_iterations = 30\n"
                                     "[closed_loop]\noutlier_fraction = 1\noutages = " +
                                         outages + "\n",
                                     "overflow_mission"));
  config.closed_loop.simulator.outlier_sigma_range_m = 1e300;
  config.closed_loop.filter.max_beacon_range_m = std::numeric_limits<double>::max();  // screen opened
  return config;
}

// Regression: UAV 1's overflow stops epoch k after UAV 0, so the epoch holds 4 records for
// 16 UAVs; the reader called that a damaged log and the replay exited 1 ("corrupt").
TEST(RawlogReplayFaults, FilterOverflowPartWayThroughAnEpoch_ReplaysToTheFaultAndExits3) {
  // GIVEN
  const MissionConfig config = overflow_mission();
  const std::string path = temp_path("overflow.rawlog");
  const RecordResult rec = record_mission(config, {path, 6, {}});
  const Live live = run_live(config);
  ASSERT_EQ(live.run.run.status, placement::RunStatus::kNumericalFault);
  ASSERT_EQ(live.run.run.fault_uav, 1) << live.run.run.fault;
  const int last_epoch = live.run.run.iterations - 1;
  ASSERT_GT(last_epoch, 1);
  // WHEN
  const MissionLog log = load_log(path);
  const ReplayResult r = replay_mission(log, {});
  // THEN: complete, with UAV 0 alone in the last epoch, the others silent there.
  EXPECT_TRUE(log.complete) << log.stop_description();
  EXPECT_EQ(log.run_end.status, "numerical_fault");
  EXPECT_EQ(log.run_end.fault_uav, 1);
  EXPECT_EQ(log.run_end.fault, live.run.run.fault);
  EXPECT_TRUE(contains(log.run_end.fault, "UAV 1: EKF ")) << log.run_end.fault;
  EXPECT_TRUE(contains(log.run_end.fault, " at epoch " + std::to_string(last_epoch))) << log.run_end.fault;
  ASSERT_EQ(static_cast<int>(log.epochs.size()), last_epoch + 1);
  constexpr int kUavs = 16;
  EXPECT_EQ(expect_replay_matches_live(r, live, kUavs), last_epoch * kUavs + 1);
  EXPECT_EQ(r.silent_uav_epochs, kUavs - 1);
  EXPECT_TRUE(std::isnan(r.epochs[last_epoch].icn));
  EXPECT_EQ(r.fallback_uav_epochs, sum(live.run.stats.bf_fallback_iterations));
  const AppRun app = replay_app(path, temp_path("overflow_out"));
  EXPECT_EQ(app.code, 3) << app.err;
  EXPECT_TRUE(contains(app.err, "ended by a fault (numerical_fault): " + live.run.run.fault)) << app.err;
}

TEST(RawlogReplayFaults, AbsurdBeaconAtEpoch0_OneEpochLogReplaysAndExits3) {
  // GIVEN: every UAV's first beacon is absurd: the run ends at iteration 0 (no final positions,
  // an empty ICN trace).
  MissionConfig config = small_mission("ekf", false, "outlier_fraction = 1\n");
  config.closed_loop.simulator.outlier_sigma_range_m = 1e300;
  config.closed_loop.filter.max_beacon_range_m = std::numeric_limits<double>::max();  // screen opened
  const std::string path = temp_path("absurd_epoch0.rawlog");
  record_mission(config, {path, 6, {}});
  const Live live = run_live(config);
  ASSERT_EQ(live.run.run.status, placement::RunStatus::kNumericalFault);
  ASSERT_EQ(live.run.run.iterations, 0);
  // WHEN
  const MissionLog log = load_log(path);
  const ReplayResult r = replay_mission(log, {});
  // THEN: epoch 0 (the start-cube priors the loop fell back to), as the loop had it.
  EXPECT_TRUE(log.complete) << log.stop_description();
  EXPECT_EQ(log.run_end.status, "numerical_fault");
  EXPECT_EQ(log.run_end.fault, live.run.run.fault);
  EXPECT_FALSE(log.final_truth_m.has_value());
  EXPECT_EQ(expect_replay_matches_live(r, live, kSmallUavs), kSmallUavs);
  EXPECT_EQ(r.epochs.size(), 1u);
  const placement::ChannelModel model(config.placement.scenario);
  EXPECT_NEAR(r.final_icn, placement::inverse_condition_number(model.matrix(live.run.run.start_m)), kIcnTolerance);
  const AppRun app = replay_app(path, temp_path("absurd_epoch0_out"));
  EXPECT_EQ(app.code, 3) << app.err;
  EXPECT_TRUE(contains(app.err, "initial beacon fix")) << app.err;
}

}  // namespace
}  // namespace losmimo::rawlog
