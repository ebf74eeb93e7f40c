// losmimo-replay: golden replays of the shipped missions, bit-for-bit reproduction of
// the recorded beliefs, co-evaluation with another estimator, the placement evaluation against
// the run's own ICN trace, and a mission killed mid-way.
#include <gtest/gtest.h>

#include <csignal>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/fusion/rawlog/mission/recorder.h"
#include "losmimo/fusion/rawlog/mission/replay.h"
#include "rawlog/rawlog_test_util.h"

namespace losmimo::rawlog {
namespace {

using test_support::load_log;
using test_support::read_file;
using test_support::small_mission;
using test_support::source_path;
using test_support::temp_path;

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream l(line);
    for (std::string c; std::getline(l, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

// Numbers equal within a relative 1e-9 (nan == nan), text exactly.
void expect_same_csv(const std::string& golden_path, const std::string& actual_path) {
  constexpr double kRelTol = 1e-9;
  const auto golden = csv_rows(read_file(golden_path));
  const auto actual = csv_rows(read_file(actual_path));
  ASSERT_FALSE(golden.empty()) << golden_path;
  ASSERT_EQ(golden.size(), actual.size()) << golden_path;
  int differences = 0;
  for (std::size_t r = 0; r < golden.size() && differences < 10; ++r) {
    ASSERT_EQ(golden[r].size(), actual[r].size()) << golden_path << " row " << r;
    for (std::size_t c = 0; c < golden[r].size(); ++c) {
      const std::string& g = golden[r][c];
      const std::string& a = actual[r][c];
      if (g == a) continue;
      char* end_g = nullptr;
      char* end_a = nullptr;
      const double x = std::strtod(g.c_str(), &end_g), y = std::strtod(a.c_str(), &end_a);
      const bool numbers = *end_g == '\0' && *end_a == '\0' && !g.empty() && !a.empty();
      const bool close =
          numbers && ((std::isnan(x) && std::isnan(y)) || std::abs(x - y) <= kRelTol * std::max(1.0, std::abs(x)));
      if (!close) {
        ADD_FAILURE() << golden_path << " row " << r << " column " << c << ": golden " << g << ", replay " << a;
        ++differences;
      }
    }
  }
}

struct GoldenCase {
  std::string mission;
  std::string variant;  // golden/<variant>: "ekf", "pf", "ekf+ceres"
};

class GoldenReplay : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(GoldenReplay, MatchesTheGoldenCsv) {
  // GIVEN: a shipped mission and its golden outputs (scripts/regenerate-golden).
  const GoldenCase& c = GetParam();
  const std::string dir = source_path("datasets/missions/" + c.mission);
  const MissionLog log = load_log(dir + "/mission.rawlog");
  ASSERT_TRUE(log.complete) << log.stop_description();
  // WHEN
  ReplayOptions options;
  options.estimator = localization::filter_kind_from_string(c.variant.substr(0, c.variant.find('+')));
  options.refine = c.variant.find("+ceres") != std::string::npos;
  const ReplayResult r = replay_mission(log, options);
  const std::string out = temp_path("golden_" + c.mission + "_" + c.variant);
  write_replay_csv(log, r, out);
  // THEN
  for (const char* file : {"estimates.csv", "epochs.csv", "summary.csv"})
    expect_same_csv(dir + "/golden/" + c.variant + "/" + file, out + "/" + file);
  // AND: the recorded estimator reproduces the logged beliefs bit for bit.
  if (r.same_as_recorded) {
    EXPECT_GT(r.filter_beliefs_compared, 0);
    EXPECT_EQ(r.filter_beliefs_bitwise_equal, r.filter_beliefs_compared);
    EXPECT_EQ(r.refined_means_bitwise_equal, r.refined_beliefs_compared);
    EXPECT_LT(r.refined_cov_max_rel_diff, 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Datasets, GoldenReplay,
                         ::testing::Values(GoldenCase{"nominal", "ekf"}, GoldenCase{"nominal", "pf"},
                                           GoldenCase{"high_beacon_noise", "pf"},
                                           GoldenCase{"high_beacon_noise", "ekf"},
                                           GoldenCase{"beacon_outage", "ekf+ceres"},
                                           GoldenCase{"beacon_outage", "ekf"}),
                         [](const ::testing::TestParamInfo<GoldenCase>& i) {
                           std::string v = i.param.variant;
                           for (char& ch : v)
                             if (ch == '+') ch = '_';
                           return i.param.mission + "_" + v;
                         });

TEST(RawlogReplay, RecordedEstimators_ReproduceTheLoggedBeliefsBitwise) {
  for (const std::string filter : {"ekf", "pf"}) {
    // GIVEN: a mission recorded with this filter, refinement on.
    const MissionConfig config = small_mission(filter, true);
    const std::string path = temp_path("bitwise_" + filter + ".rawlog");
    const RecordResult rec = record_mission(config, {path, 6, {}});
    // WHEN: replayed with the same estimator.
    const ReplayResult r = replay_mission(load_log(path), {});
    // THEN: every filter belief and refined mean equal, bit for bit.
    EXPECT_TRUE(r.same_as_recorded);
    EXPECT_EQ(r.filter_beliefs_compared, rec.epochs * 4) << filter;
    EXPECT_EQ(r.filter_beliefs_bitwise_equal, r.filter_beliefs_compared) << filter;
    EXPECT_EQ(r.refined_beliefs_compared, rec.epochs * 4) << filter;
    EXPECT_EQ(r.refined_means_bitwise_equal, r.refined_beliefs_compared) << filter;
    // AND: the replayed statistics are the run's own (closed_loop.h fusion::ClosedLoopStats).
    EXPECT_NEAR(r.rmse_m, rec.run.stats.rmse_m, 1e-12);
    EXPECT_NEAR(r.filter_rmse_m, rec.run.stats.filter_rmse_m, 1e-12);
    EXPECT_NEAR(r.average_nees, rec.run.stats.average_nees, 1e-9 * rec.run.stats.average_nees);
    // AND: so is the swarm-shape split, computed there online and here from the log.
    EXPECT_NEAR(r.common_lateral_rms_m, rec.run.stats.common_lateral_rms_m, 1e-12) << filter;
    EXPECT_NEAR(r.shape_lateral_rmse_m, rec.run.stats.shape_lateral_rmse_m, 1e-12) << filter;
    EXPECT_NEAR(r.shape_nees_per_dof, rec.run.stats.shape_nees_per_dof, 1e-9 * rec.run.stats.shape_nees_per_dof)
        << filter;
  }
}

TEST(RawlogReplay, BsAzimuthMisalignment_ShowsAsTheCommonOffsetNotAsShape) {
  // GIVEN: the same mission recorded with an aligned BS array and with one turned by 1 mrad in
  // azimuth: every beacon bearing is off by 1 mrad, which moves every UAV's fix by R x 1 mrad
  // the same way (R = the swarm's range).
  const double bias_rad = 0.0009765625;  // ~1 mrad, exact in the INI text
  const MissionConfig aligned = small_mission("ekf", false);
  const double range_m = aligned.placement.scenario.range_m();
  const std::string a_path = temp_path("aligned.rawlog"), b_path = temp_path("misaligned.rawlog");
  record_mission(aligned, {a_path, 6, {}});
  record_mission(small_mission("ekf", false, "bs_azimuth_bias_rad = 0.0009765625\n"), {b_path, 6, {}});
  // WHEN: both are replayed.
  const ReplayResult a = replay_mission(load_log(a_path), {});
  const ReplayResult b = replay_mission(load_log(b_path), {});
  // THEN: the misaligned log's common lateral offset is R x bias (to the aligned one's own
  // common error and second order), and its shape error stays the aligned one's size.
  EXPECT_NEAR(b.common_lateral_rms_m, range_m * bias_rad, 0.1 * range_m * bias_rad + a.common_lateral_rms_m);
  EXPECT_GT(b.lateral_rmse_m, 5.0 * a.lateral_rmse_m);
  EXPECT_LT(b.shape_lateral_rmse_m, 0.2 * b.common_lateral_rms_m);
  EXPECT_LT(b.shape_lateral_rmse_m, 3.0 * a.shape_lateral_rmse_m + 0.01);
}

TEST(RawlogReplay, IcnAlongTheTrajectory_EqualsTheRunsOwnTrace) {
  // GIVEN: the run's ICN trace (cached Gram matrix, placement/run.h) and the replay's ICN from
  // the logged true positions (an SVD of H rebuilt from scratch).
  const std::string path = temp_path("icn.rawlog");
  const RecordResult rec = record_mission(small_mission("ekf", false), {path, 6, {}});
  const ReplayResult r = replay_mission(load_log(path), {});
  // THEN: epoch k's positions are the run's iteration k; the final row is the last iteration.
  ASSERT_EQ(r.epochs.size(), rec.run.run.trace.size());
  for (std::size_t k = 0; k < r.epochs.size(); ++k)
    EXPECT_NEAR(r.epochs[k].icn, rec.run.run.trace[k].icn, 1e-6) << "epoch " << k;
  EXPECT_TRUE(r.epochs.back().final_positions);
}

TEST(RawlogReplay, OtherEstimator_IsACoEvaluationOnTheSameData) {
  // GIVEN: the nominal mission (EKF). WHEN: replayed with the particle filter.
  const MissionLog log = load_log(source_path("datasets/missions/nominal/mission.rawlog"));
  ReplayOptions pf;
  pf.estimator = localization::FilterKind::kParticle;
  const ReplayResult a = replay_mission(log, {});
  const ReplayResult b = replay_mission(log, pf);
  // THEN: same trajectory (same ICN), different but comparable estimates; no belief comparison.
  EXPECT_FALSE(b.same_as_recorded);
  EXPECT_EQ(b.filter_beliefs_compared, 0);
  EXPECT_EQ(a.final_icn, b.final_icn);
  EXPECT_NE(a.rmse_m, b.rmse_m);
  EXPECT_LT(std::abs(a.rmse_m - b.rmse_m), 0.5 * a.rmse_m);
}

TEST(RawlogReplay, MissionKilledMidway_LeavesAReadablePrefix) {
  // GIVEN: a recording killed (SIGKILL) right after epoch 5's mark was flushed.
  constexpr int kKillEpoch = 5;
  const std::string path = temp_path("killed.rawlog");
  const MissionConfig config = small_mission("ekf", false);
  const auto record_and_die = [&] {
    RecordOptions o;
    o.out_path = path;
    o.after_epoch_mark = [](int epoch) {
      if (epoch == kKillEpoch) std::raise(SIGKILL);
    };
    record_mission(config, o);
    std::exit(0);
  };
  EXPECT_EXIT(record_and_die(), ::testing::KilledBySignal(SIGKILL), "");
  // WHEN
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(path);
  const MissionLog log = load_mission_log(reader);
  // THEN: epochs 0..5 are there and verified; the log says it is partial.
  EXPECT_TRUE(log.ours);
  EXPECT_FALSE(log.complete);
  EXPECT_EQ(static_cast<int>(log.epochs.size()), kKillEpoch + 1);
  EXPECT_TRUE(log.integrity_error.empty()) << log.integrity_error;
  EXPECT_NE(log.stop_description().find("partial"), std::string::npos) << log.stop_description();
  const ReplayResult r = replay_mission(log, {});
  EXPECT_EQ(r.filter_beliefs_bitwise_equal, 4 * (kKillEpoch + 1));
  // AND: the app replays the prefix and exits 1 with the reason.
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app({path, "", false, false, temp_path("killed_out"), false, true}, out, err), 1);
  EXPECT_NE(err.str().find("partial"), std::string::npos) << err.str();
}

TEST(RawlogReplay, App_ExitCodesAndOutputs) {
  std::ostringstream out, err;
  const std::string nominal = source_path("datasets/missions/nominal/mission.rawlog");
  EXPECT_EQ(apps::run_replay_app({"/nonexistent.rawlog", "", false, false, "", false}, out, err), 2);
  EXPECT_EQ(apps::run_replay_app({nominal, "ukf", false, false, "", false}, out, err), 2);
  const std::string dir = temp_path("app_out");
  EXPECT_EQ(apps::run_replay_app({nominal, "pf", false, false, dir, false, true}, out, err), 0) << err.str();
  EXPECT_FALSE(read_file(dir + "/summary.csv").empty());
  EXPECT_NE(out.str().find("rmse_m"), std::string::npos);
}

}  // namespace
}  // namespace losmimo::rawlog
