// Range-only replay (mrpt_logs/range_log.h, range_replay.h, beacon_list.h) on MRPT's shipped
// RO-SLAM demo (Debian mrpt-common) and on edited copies of its frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <Eigen/Dense>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CArchive.h>

#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/placement/common/input_error.h"
#include "losmimo/fusion/rawlog/mrpt_logs/beacon_list.h"
#include "losmimo/fusion/rawlog/mrpt_logs/range_replay.h"
#include "rawlog_test_util.h"
#include "support/dependencies.h"

namespace losmimo::mrpt_logs {
namespace {

using localization::FilterKind;

const std::string kDemoDir = "/usr/share/mrpt/datasets";
const std::string kDemoLog = kDemoDir + "/RO-SLAM_demo.rawlog";
const std::string kDemoBeacons = kDemoDir + "/RO-SLAM_demo_ground_truth.txt";
constexpr double kDemoStdError_m = 0.01;  // the log's stdError
constexpr int kDemoFrames = 100;

#define SKIP_WITHOUT_DEMO()                      \
  LOSMIMO_REQUIRE_FILE(kDemoLog, "mrpt-common"); \
  LOSMIMO_REQUIRE_FILE(kDemoBeacons, "mrpt-common")

RangeLog demo_log() {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(kDemoLog);
  return load_range_log(reader);
}

RangeReplayOptions demo_options(FilterKind kind) {
  RangeReplayOptions o;
  o.estimator = kind;
  o.config.use_observation_std = true;
  localization::PoseBelief start;  // the demo starts at the map origin, heading 0
  start.cov = Eigen::Vector4d(0.01, 0.01, 1e-6, 1e-3).asDiagonal();
  o.prior = start;
  return o;
}

// Independent reference: per-frame 2-D trilateration (Gauss-Newton on x, y with z = 0, from the
// previous frame's solution), no odometry.
Eigen::Vector2d trilaterate(const RangeFrame& f, const localization::BeaconMap& map, Eigen::Vector2d p) {
  for (int it = 0; it < 20; ++it) {
    Eigen::Matrix2d AtA = Eigen::Matrix2d::Zero();
    Eigen::Vector2d Atr = Eigen::Vector2d::Zero();
    for (const auto& s : f.scans)
      for (const auto& r : s.ranges) {
        const Eigen::Vector3d* b = map.find(r.beacon_id);
        if (!b) continue;
        const Eigen::Vector3d d(p.x() - b->x(), p.y() - b->y(), -b->z());
        const double h = d.norm();
        const Eigen::RowVector2d J(d.x() / h, d.y() / h);
        AtA += J.transpose() * J;
        Atr += J.transpose() * (r.range_m - h);
      }
    p += AtA.ldlt().solve(Atr);
  }
  return p;
}

class RoSlamDemo : public ::testing::TestWithParam<FilterKind> {};

TEST_P(RoSlamDemo, EveryKnownBeaconRangeFused_ResidualWithinTwiceTheRangeNoise) {
  SKIP_WITHOUT_DEMO();
  // GIVEN: the demo log and its beacon file (15 beacons, IDs 0..14: every reading is known).
  const RangeLog log = demo_log();
  const localization::BeaconMap map = read_beacon_list(kDemoBeacons);
  ASSERT_EQ(map.size(), 15u);
  ASSERT_EQ(static_cast<int>(log.frames.size()), kDemoFrames);
  // WHEN
  const RangeReplayResult r = replay_ranges(log, map, demo_options(GetParam()));
  // THEN: every range read is fused, none skipped.
  EXPECT_EQ(r.counters.ranges_received, log.ranges);
  EXPECT_EQ(r.counters.ranges_fused, log.ranges);
  EXPECT_EQ(r.counters.rejected_ranges(), 0);
  // AND: the post-fit residual after convergence is within 2x the range noise, the NIS near 1.
  std::cout << to_string(GetParam()) << ": residual RMS " << r.residual_rms_settled_m << " m, mean NIS " << r.mean_nis
            << "\n";
  EXPECT_LT(r.residual_rms_settled_m, 2.0 * kDemoStdError_m);
  EXPECT_GT(r.mean_nis, 0.5);
  EXPECT_LT(r.mean_nis, 1.5);
  // AND: steps are the frames' indices in the log.
  for (int k = 0; k < kDemoFrames; ++k) EXPECT_EQ(r.track[k].step, k);
}

TEST_P(RoSlamDemo, TrackAgreesWithPerFrameTrilateration) {
  SKIP_WITHOUT_DEMO();
  const RangeLog log = demo_log();
  const localization::BeaconMap map = read_beacon_list(kDemoBeacons);
  const RangeReplayResult r = replay_ranges(log, map, demo_options(GetParam()));
  Eigen::Vector2d p(0.0, 0.0);
  double sq = 0.0;
  for (std::size_t k = 0; k < log.frames.size(); ++k) {
    p = trilaterate(log.frames[k], map, p);
    sq += (r.track[k].belief.mean.head<2>() - p).squaredNorm();
  }
  const double rms = std::sqrt(sq / static_cast<double>(log.frames.size()));
  std::cout << to_string(GetParam()) << ": RMS distance to trilateration " << rms << " m\n";
  EXPECT_LT(rms, 0.02);
}

TEST_P(RoSlamDemo, RefinedTrack_ResidualWithinTheRangeNoiseAndNearTrilateration) {
  SKIP_WITHOUT_DEMO();
  // GIVEN: the demo replayed with the batch smoother.
  const RangeLog log = demo_log();
  const localization::BeaconMap map = read_beacon_list(kDemoBeacons);
  RangeReplayOptions o = demo_options(GetParam());
  o.refine = fusion::RangeSmootherConfig{};
  // WHEN
  const RangeReplayResult r = replay_ranges(log, map, o);
  // THEN: one converged problem, every range used, none beyond the loss scale (the demo is clean).
  ASSERT_TRUE(r.refined);
  EXPECT_EQ(r.smoother.problems, 1);
  EXPECT_EQ(r.smoother.not_converged, 0);
  EXPECT_EQ(r.smoother.covariance_fallbacks, 0);
  EXPECT_EQ(r.smoother.ranges_used, log.ranges - static_cast<std::int64_t>(log.frames[0].scans[0].ranges.size()));
  EXPECT_EQ(r.smoother.ranges_down_weighted, 0);
  // AND: the post-fit residual is the range noise (the filter's: 0.0097 m), and the track is
  // within 1 cm RMS of the per-frame trilateration (a reference a few mm noisy itself: both
  // tracks sit there, 0.0042 m the filter, 0.0046 m the smoother).
  std::cout << to_string(GetParam()) << " refined: residual RMS " << r.refined_residual_rms_settled_m << " m\n";
  EXPECT_LT(r.refined_residual_rms_settled_m, 1.1 * kDemoStdError_m);
  Eigen::Vector2d p(0.0, 0.0);
  double sq = 0.0;
  for (std::size_t k = 0; k < log.frames.size(); ++k) {
    p = trilaterate(log.frames[k], map, p);
    sq += (r.track[k].refined->mean.head<2>() - p).squaredNorm();
  }
  const double rms = std::sqrt(sq / static_cast<double>(log.frames.size()));
  std::cout << to_string(GetParam()) << " refined: RMS distance to trilateration " << rms << " m\n";
  EXPECT_LT(rms, 0.01);
}

INSTANTIATE_TEST_SUITE_P(BothFilters, RoSlamDemo, ::testing::Values(FilterKind::kEkf, FilterKind::kParticle),
                         [](const auto& info) { return localization::to_string(info.param); });

TEST(RangeLog, RoSlamOdometry_IsTheComposedPoseChangesOfTheActions) {
  SKIP_WITHOUT_DEMO();
  // Independent: MRPT itself, CPose2D composition of every action's poseChange mean.
  mrpt::io::CFileGZInputStream f(kDemoLog);
  auto a = mrpt::serialization::archiveFrom(f);
  mrpt::poses::CPose2D dr;
  int sensory_frames = 0;
  mrpt::poses::CPose2D at_last_sf;
  try {
    for (;;) {
      auto o = a.ReadObject();
      if (auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(o)) {
        if (auto m = acts->getBestMovementEstimation()) dr = dr + m->poseChange->getMeanVal();
      } else if (std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(o)) {
        ++sensory_frames;
        at_last_sf = dr;
      }
    }
  } catch (const std::exception&) {  // end of file
  }
  const RangeLog log = demo_log();
  ASSERT_EQ(static_cast<int>(log.frames.size()), sensory_frames);
  EXPECT_FALSE(log.frames.front().has_odometry);
  EXPECT_EQ(log.trailing_actions, 1);
  Eigen::Vector4d x = Eigen::Vector4d::Zero();
  for (const RangeFrame& fr : log.frames)
    if (fr.has_odometry) x = localization::compose(x, fr.odometry.delta);
  EXPECT_NEAR(x(0), at_last_sf.x(), 1e-9);
  EXPECT_NEAR(x(1), at_last_sf.y(), 1e-9);
  EXPECT_NEAR(x(3), at_last_sf.phi(), 1e-9);
  EXPECT_GT(log.frames[50].odometry.cov(0, 0), 0.0);  // the log's covariance is carried
}

TEST(RangeReplay, UnknownIdsAndOutOfLimitsRanges_CountedAndSkipped) {
  SKIP_WITHOUT_DEMO();
  // GIVEN: the demo with, in every frame from 5 on, one reading of an unmapped beacon and one
  // beyond the sensor's maxSensorDistance.
  RangeLog log = demo_log();
  const localization::BeaconMap map = read_beacon_list(kDemoBeacons);
  int added = 0;
  for (std::size_t k = 5; k < log.frames.size(); ++k) {
    auto& scan = log.frames[k].scans.front();
    localization::BeaconRange unknown = scan.ranges.front();
    unknown.beacon_id = 99;
    localization::BeaconRange far = scan.ranges.front();
    far.range_m = scan.max_sensor_distance_m + 1.0;
    scan.ranges.push_back(unknown);
    scan.ranges.push_back(far);
    ++added;
  }
  // WHEN
  const RangeReplayResult r = replay_ranges(log, map, demo_options(FilterKind::kEkf));
  // THEN
  EXPECT_EQ(r.counters.rejected_unknown_beacon, added);
  EXPECT_EQ(r.counters.rejected_outside_sensor_limits, added);
  EXPECT_EQ(r.counters.ranges_fused, r.counters.ranges_received - 2 * added);
  EXPECT_LT(r.residual_rms_settled_m, 2.0 * kDemoStdError_m);
}

TEST(RangeReplay, NothingToFuse_ThrowsWithTheReason) {
  SKIP_WITHOUT_DEMO();
  const RangeLog log = demo_log();
  localization::BeaconMap other;
  other.add(100, Eigen::Vector3d(1.0, 2.0, 0.0));
  try {
    replay_ranges(log, other, demo_options(FilterKind::kEkf));
    FAIL() << "no throw";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none of the log's beacon IDs (0, 1,"), std::string::npos) << e.what();
  }
  RangeLog empty;
  EXPECT_THROW(replay_ranges(empty, read_beacon_list(kDemoBeacons), demo_options(FilterKind::kEkf)),
               common::InputError);
}

TEST(BeaconList, ParsesIdXyzAndIgnoresFurtherColumns) {
  const localization::BeaconMap m = parse_beacon_list("# comment\n\n3 1.5 -2 0.25 0 0 0\n7 0 0 1\n", "t");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(*m.find(3), Eigen::Vector3d(1.5, -2.0, 0.25));
  EXPECT_EQ(*m.find(7), Eigen::Vector3d(0.0, 0.0, 1.0));
}

TEST(BeaconList, BadLines_NameLineFieldAndValue) {
  const auto message = [](const std::string& text) {
    try {
      parse_beacon_list(text, "b.txt");
    } catch (const common::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  EXPECT_NE(message("1 0 0 0\n2 0 x 0\n").find("b.txt:2"), std::string::npos);
  EXPECT_NE(message("1 0 0 0\n2 0 x 0\n").find("x"), std::string::npos);
  EXPECT_NE(message("1 0 0\n").find("3 column"), std::string::npos);
  EXPECT_NE(message("-1 0 0 0\n").find("-1"), std::string::npos);
  EXPECT_NE(message("1 0 0 0\n1 2 2 2\n").find("listed twice"), std::string::npos);
  EXPECT_NE(message("# only a comment\n").find("no beacon"), std::string::npos);
}

TEST(RangeReplayApp, DemoWithoutBeaconMap_ExitsTwoSayingWhy) {
  SKIP_WITHOUT_DEMO();
  apps::ReplayAppOptions o;
  o.rawlog_path = kDemoLog;
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
  EXPECT_NE(err.str().find("CObservationBeaconRanges but no beacon map"), std::string::npos) << err.str();
  EXPECT_EQ(out.str().find("nan"), std::string::npos) << out.str();
}

TEST(RangeReplayApp, RefineWithAnUnusableWindow_ExitsTwoNamingTheOption) {
  SKIP_WITHOUT_DEMO();
  for (const int window : {1, -2}) {
    apps::ReplayAppOptions o;
    o.rawlog_path = kDemoLog;
    o.beacons_path = kDemoBeacons;
    o.refine = true;
    o.refine_window = window;
    o.refine_window_given = true;
    std::ostringstream out, err;
    EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
    EXPECT_NE(err.str().find("--refine-window " + std::to_string(window) + ": must be 0"), std::string::npos)
        << err.str();
  }
  apps::ReplayAppOptions o;  // a window without --refine
  o.rawlog_path = kDemoLog;
  o.beacons_path = kDemoBeacons;
  o.refine_window = 5;
  o.refine_window_given = true;
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
  EXPECT_NE(err.str().find("--refine-window: needs --refine"), std::string::npos) << err.str();
}

// The app on the demo with its beacon file, starting at the origin, writing into a fresh `dir`.
apps::ReplayAppOptions demo_app_options(const std::string& dir) {
  std::filesystem::remove_all(dir);
  apps::ReplayAppOptions o;
  o.rawlog_path = kDemoLog;
  o.beacons_path = kDemoBeacons;
  o.initial_pose = "0,0,0";
  o.out_dir = dir;
  o.out_given = true;
  return o;
}

TEST(RangeReplayApp, DemoRefined_TrackHasRefinedColumnsAndSummaryTheFigures) {
  SKIP_WITHOUT_DEMO();
  const std::string dir = test_support::temp_path("range_replay_refined_out");
  apps::ReplayAppOptions o = demo_app_options(dir);
  o.refine = true;
  std::ostringstream out, err;
  ASSERT_EQ(apps::run_replay_app(o, out, err), 0) << err.str();
  std::ifstream track(dir + "/track.csv");
  std::string header;
  std::getline(track, header);
  EXPECT_NE(header.find(",refined_x_m,refined_y_m,refined_z_m,refined_heading_rad,"), std::string::npos) << header;
  EXPECT_NE(header.find(",refined_residual_rms_m,refined_error_m,refined_nees"), std::string::npos) << header;
  std::ifstream summary(dir + "/summary.csv");
  std::stringstream s;
  s << summary.rdbuf();
  EXPECT_NE(s.str().find("refinement,\"batch\""), std::string::npos) << s.str();
  EXPECT_NE(s.str().find("refined_residual_rms_m,"), std::string::npos) << s.str();
  EXPECT_NE(out.str().find("refine_wall_s = "), std::string::npos) << out.str();
}

TEST(RangeReplayApp, DemoWithBeacons_WritesTrackAndSummary) {
  SKIP_WITHOUT_DEMO();
  const std::string dir = test_support::temp_path("range_replay_out");
  const apps::ReplayAppOptions o = demo_app_options(dir);
  std::ostringstream out, err;
  ASSERT_EQ(apps::run_replay_app(o, out, err), 0) << err.str();
  std::ifstream track(dir + "/track.csv");
  std::string header, line;
  std::getline(track, header);
  EXPECT_EQ(header.rfind("step,timestamp_s,x_m,y_m,z_m,heading_rad,var_x_m2,var_y_m2,var_z_m2", 0), 0u) << header;
  int rows = 0;
  while (std::getline(track, line)) ++rows;
  EXPECT_EQ(rows, kDemoFrames);
  std::ifstream summary(dir + "/summary.csv");
  std::stringstream s;
  s << summary.rdbuf();
  EXPECT_NE(s.str().find("ranges_fused,\"1415\""), std::string::npos) << s.str();
  EXPECT_NE(out.str().find("skipped_unknown_beacon = 0"), std::string::npos) << out.str();
  // The plot's script always; the picture where gnuplot is installed (else one warning).
  EXPECT_TRUE(std::filesystem::exists(dir + "/track.gp"));
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/track.png")) << err.str();
  } else {
    EXPECT_NE(err.str().find("gnuplot not found"), std::string::npos) << err.str();
  }
}

}  // namespace
}  // namespace losmimo::mrpt_logs

namespace losmimo::mrpt_logs {
namespace {

// An observation-format log (MRPT's pf-localization reads these): cumulative 2-D
// CObservationOdometry and CObservationBeaconRanges alternating, with a known path.
TEST(RangeLog, ObservationFormat_OdometryDifferencesAndRangesWithKnownTruth) {
  constexpr int kSteps = 60;
  constexpr double kSigma_m = 0.02;
  const std::vector<Eigen::Vector3d> beacons = {{-3.0, -2.0, 1.0}, {6.0, -1.0, 0.5}, {5.0, 7.0, 2.0}, {-2.0, 6.0, 0.0}};
  localization::BeaconMap map;
  for (std::size_t b = 0; b < beacons.size(); ++b) map.add(static_cast<std::int32_t>(b + 10), beacons[b]);
  std::vector<mrpt::poses::CPose2D> truth;
  mrpt::poses::CPose2D p(0.5, 0.2, 0.1);
  for (int k = 0; k < kSteps; ++k) {
    truth.push_back(p);
    p = p + mrpt::poses::CPose2D(0.2, 0.0, 0.05);
  }
  const std::string path = test_support::temp_path("obs_format.rawlog");
  {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, kSigma_m);
    mrpt::io::CFileGZOutputStream f(path);
    auto a = mrpt::serialization::archiveFrom(f);
    for (int k = 0; k < kSteps; ++k) {
      mrpt::obs::CObservationOdometry odo;
      odo.odometry = truth[k];
      odo.timestamp = mrpt::Clock::fromDouble(1000.0 + k);
      a << odo;
      mrpt::obs::CObservationBeaconRanges r;
      r.timestamp = mrpt::Clock::fromDouble(1000.0 + k + 0.5);
      r.stdError = static_cast<float>(kSigma_m);
      r.maxSensorDistance = 50.0f;
      for (std::size_t b = 0; b < beacons.size(); ++b) {
        mrpt::obs::CObservationBeaconRanges::TMeasurement m;
        m.beaconID = static_cast<int32_t>(b + 10);
        const Eigen::Vector3d d(truth[k].x() - beacons[b].x(), truth[k].y() - beacons[b].y(), -beacons[b].z());
        m.sensedDistance = static_cast<float>(d.norm() + noise(rng));
        r.sensedData.push_back(m);
      }
      a << r;
    }
  }
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(path);
  const RangeLog log = load_range_log(reader);
  ASSERT_EQ(static_cast<int>(log.frames.size()), kSteps);
  EXPECT_FALSE(log.frames[0].has_odometry);
  EXPECT_EQ(log.frames[3].step, 7);  // its index among the log's top-level observations
  EXPECT_NEAR(log.frames[3].timestamp_s, 1003.5, 1e-6);
  ASSERT_TRUE(log.frames[3].has_odometry);
  // The increment between cumulative readings, in the robot frame: (0.2, 0, 0.05).
  EXPECT_NEAR(log.frames[3].odometry.delta(0), 0.2, 1e-12);
  EXPECT_NEAR(log.frames[3].odometry.delta(1), 0.0, 1e-12);
  EXPECT_NEAR(log.frames[3].odometry.delta(3), 0.05, 1e-12);
  for (const FilterKind kind : {FilterKind::kEkf, FilterKind::kParticle}) {
    RangeReplayOptions o;
    o.estimator = kind;
    o.config.use_observation_std = true;
    localization::PoseBelief start;
    start.mean = Eigen::Vector4d(0.5, 0.2, 0.0, 0.1);
    start.cov = Eigen::Vector4d(0.01, 0.01, 1e-6, 1e-3).asDiagonal();
    o.prior = start;
    const RangeReplayResult r = replay_ranges(log, map, o);
    EXPECT_EQ(r.counters.ranges_fused, static_cast<std::int64_t>(kSteps * beacons.size()));
    double sq = 0.0;
    for (int k = 0; k < kSteps; ++k) {
      sq +=
          std::pow(r.track[k].belief.mean(0) - truth[k].x(), 2) + std::pow(r.track[k].belief.mean(1) - truth[k].y(), 2);
    }
    const double rmse = std::sqrt(sq / kSteps);
    std::cout << localization::to_string(kind) << " observation-format log: RMSE " << rmse << " m\n";
    EXPECT_LT(rmse, 2.0 * kSigma_m);
    EXPECT_LT(r.residual_rms_settled_m, 2.0 * kSigma_m);
  }
}

}  // namespace
}  // namespace losmimo::mrpt_logs
