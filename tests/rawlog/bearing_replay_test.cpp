// Bearing-range replay (mrpt_logs/bearing_log.h, bearing_replay.h, landmark_files.h) on MRPT's
// four kf-slam demo logs (Debian mrpt-common) with their ground-truth landmarks and robot paths.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/localization/range_az_el.h"
#include "losmimo/fusion/rawlog/mrpt_logs/bearing_replay.h"
#include "losmimo/fusion/rawlog/mrpt_logs/landmark_files.h"
#include "rawlog_test_util.h"
#include "support/dependencies.h"

namespace losmimo::mrpt_logs {
namespace {

using localization::FilterKind;
using localization::Pose6;

const std::string kDir = "/usr/share/mrpt/datasets/";
constexpr int kTestParticles = 20;  // the optimal proposal keeps few particles diverse

struct Demo {
  std::string name;
  double max_rmse_m;  // about twice the EKF's measured RMSE (docs/bearing-range.md)
};
const Demo k2d{"kf-slam_demo", 0.006};
const Demo k6d{"kf-slam_6D_demo", 0.02};
const Demo kNoncentered{"kf-slam_6D_demo_noncentered", 0.014};
const Demo kDa{"kf-slam_6D_demo_DA", 0.06};

std::string log_path(const Demo& d) { return kDir + d.name + ".rawlog"; }
std::string landmarks_path(const Demo& d) { return kDir + d.name + "_ground_truth.txt"; }
std::string path_path(const Demo& d) { return kDir + d.name + "_ground_truth_robot_path.txt"; }

#define SKIP_WITHOUT(demo)                             \
  LOSMIMO_REQUIRE_FILE(log_path(demo), "mrpt-common"); \
  LOSMIMO_REQUIRE_FILE(path_path(demo), "mrpt-common")

BearingLog load(const Demo& d) {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(log_path(d));
  return load_bearing_log(reader);
}

BearingReplayResult replay(const Demo& d, const BearingLog& log, FilterKind kind, bool refine = false,
                           bool ignore_sensor_pose = false) {
  BearingReplayOptions o;
  o.estimator = kind;
  o.config.num_particles = kTestParticles;
  o.ground_truth = read_robot_path(path_path(d));
  o.refine = refine;
  o.ignore_sensor_pose = ignore_sensor_pose;
  return replay_bearings(log, read_landmark_file(landmarks_path(d)), o);
}

// Every estimator within the log's bound and far below dead reckoning; the smoother at or below
// the filter.
void check_rmse(const Demo& d) {
  const BearingLog log = load(d);
  ASSERT_EQ(log.read_status.stop, rawlog_io::RawlogStop::kEnd);
  const BearingReplayResult ekf = replay(d, log, FilterKind::kEkf, true);
  const BearingReplayResult pf = replay(d, log, FilterKind::kParticle);
  EXPECT_EQ(ekf.truth_frames, static_cast<std::int64_t>(log.frames.size()));
  EXPECT_LT(ekf.rmse_m, d.max_rmse_m) << d.name;
  EXPECT_LT(pf.rmse_m, d.max_rmse_m) << d.name;
  EXPECT_LT(ekf.refined_rmse_m, ekf.rmse_m) << d.name;
  // The smoother's horizontal RMSE, recomputed from the rows' smoothed poses and the truth.
  double e2_xy = 0.0;
  for (const BearingTrackRow& row : ekf.track) {
    const double dx = (*row.refined)(0) - row.truth(0), dy = (*row.refined)(1) - row.truth(1);
    e2_xy += dx * dx + dy * dy;
  }
  EXPECT_NEAR(ekf.refined_rmse_xy_m, std::sqrt(e2_xy / static_cast<double>(ekf.track.size())), 1e-12) << d.name;
  EXPECT_LE(ekf.refined_rmse_xy_m, ekf.refined_rmse_m) << d.name;
  EXPECT_LT(ekf.rmse_m, ekf.dr_rmse_m / 20.0) << d.name << ": dead reckoning " << ekf.dr_rmse_m;
  EXPECT_TRUE(ekf.smoother.converged) << d.name;
  EXPECT_EQ(ekf.counters.gated, 0) << d.name;
  // Consistent noise: mean NIS near 3 (near 2 on the planar log, whose elevations say nothing).
  EXPECT_GT(ekf.mean_nis, log.planar() ? 1.5 : 2.4) << d.name;
  EXPECT_LT(ekf.mean_nis, log.planar() ? 2.6 : 3.6) << d.name;
}

TEST(BearingReplay, Planar2dLog_EkfPfAndRefineWithinBounds) {
  SKIP_WITHOUT(k2d);
  check_rmse(k2d);
}

TEST(BearingReplay, SixDofLog_EkfPfAndRefineWithinBounds) {
  SKIP_WITHOUT(k6d);
  check_rmse(k6d);
}

TEST(BearingReplay, NoncenteredLog_EkfPfAndRefineWithinBounds) {
  SKIP_WITHOUT(kNoncentered);
  check_rmse(kNoncentered);
}

TEST(BearingReplay, DataAssociationLog_NearestNeighbourWithinBoundsWithoutAmbiguity) {
  SKIP_WITHOUT(kDa);
  check_rmse(kDa);
  const BearingLog log = load(kDa);
  EXPECT_EQ(log.readings_without_id, log.readings);
  const BearingReplayResult ekf = replay(kDa, log, FilterKind::kEkf);
  EXPECT_EQ(ekf.counters.ambiguous, 0);
  EXPECT_EQ(ekf.counters.fused, log.readings);
}

TEST(BearingReplay, LogReadingsAtTheGroundTruthPoses_AgreeWithOurModelToTheSensorNoise) {
  // MRPT's own simulator wrote these logs from the ground-truth path: our model (range_az_el of
  // the landmark in the sensor frame, sensorLocationOnRobot included, pitch = -elevation) at row
  // k of the path must reproduce frame k's readings to the logged sensor_std_*, and row k + 1
  // must not (the alignment of rows and frames).
  for (const Demo& d : {k2d, k6d, kNoncentered}) {
    SKIP_WITHOUT(d);
    const BearingLog log = load(d);
    const localization::BeaconMap map = read_landmark_file(landmarks_path(d));
    const std::vector<Pose6> truth = read_robot_path(path_path(d));
    ASSERT_EQ(truth.size(), log.frames.size()) << d.name;
    for (const int offset : {0, 1}) {
      Eigen::Vector3d sq = Eigen::Vector3d::Zero();
      int n = 0;
      for (std::size_t k = 0; k + offset < truth.size(); ++k)
        for (const auto& s : log.frames[k].scans)
          for (const auto& r : s.readings) {
            const Eigen::Vector3d h =
                localization::landmark_predict(truth[k + offset], s.sensor_on_robot, *map.find(r.landmark_id));
            sq += localization::range_az_el_innovation(r.z, h).cwiseAbs2();
            ++n;
          }
      const Eigen::Vector3d rms = (sq / n).cwiseSqrt();
      const Eigen::Vector3d sigma = log.frames[0].scans[0].sigma;
      if (offset == 0) {
        EXPECT_LT(rms(0), 1.2 * sigma(0)) << d.name;
        EXPECT_LT(rms(1), 1.2 * sigma(1)) << d.name;
        if (!log.planar()) {
          EXPECT_LT(rms(2), 1.2 * sigma(2)) << d.name;
        }
      } else {
        EXPECT_GT(rms(0), 5.0 * sigma(0)) << d.name;
      }
    }
  }
}

TEST(BearingReplay, NoncenteredLog_UsesTheSensorPose_IgnoringItLocalizesFarWorse) {
  SKIP_WITHOUT(kNoncentered);
  SKIP_WITHOUT(k6d);
  // GIVEN: the same trajectory seen from a sensor at (0.5, 0.2, 0.1) m, yaw 80 deg, pitch -20 deg,
  // roll 10 deg on the robot.
  const BearingLog log = load(kNoncentered);
  const Pose6& s = log.frames[0].scans[0].sensor_on_robot;
  EXPECT_NEAR(s(0), 0.5, 1e-6);
  EXPECT_NEAR(s(3), 80.0 * 3.14159265358979323846 / 180.0, 1e-6);
  // THEN: the same quality as the centered log; a replay that drops the sensor pose (negative
  // control) is far off.
  const double centered = replay(k6d, load(k6d), FilterKind::kEkf).rmse_m;
  const double noncentered = replay(kNoncentered, log, FilterKind::kEkf).rmse_m;
  const double ignored = replay(kNoncentered, log, FilterKind::kEkf, false, true).rmse_m;
  RecordProperty("rmse_centered_m", std::to_string(centered));
  RecordProperty("rmse_noncentered_m", std::to_string(noncentered));
  RecordProperty("rmse_sensor_pose_ignored_m", std::to_string(ignored));
  EXPECT_LT(noncentered, 1.5 * centered);
  EXPECT_GT(ignored, 10.0 * noncentered) << "ignored " << ignored << " noncentered " << noncentered;
}

TEST(BearingLogLoad, TwoDimensionalDemoIsPlanarAndTheSixDofOnesAreNot) {
  SKIP_WITHOUT(k2d);
  SKIP_WITHOUT(k6d);
  const BearingLog planar = load(k2d);
  EXPECT_TRUE(planar.planar());
  EXPECT_EQ(planar.frames.size(), 250u);
  EXPECT_FALSE(planar.frames[0].has_odometry);
  EXPECT_TRUE(planar.frames[1].has_odometry);
  const BearingLog six = load(k6d);
  EXPECT_FALSE(six.planar());
  EXPECT_EQ(six.actions_3d, static_cast<std::int64_t>(six.frames.size()) - 1 + six.trailing_actions);
}

// --- the app: exit codes, messages, outputs ---

apps::ReplayAppOptions app_options(const Demo& d) {
  apps::ReplayAppOptions o;
  o.rawlog_path = log_path(d);
  o.landmarks_path = landmarks_path(d);
  o.ground_truth = path_path(d);
  return o;
}

TEST(BearingReplayApp, WithoutAMap_ExitsTwoNamingWhatIsMissing) {
  SKIP_WITHOUT(k6d);
  apps::ReplayAppOptions o;
  o.rawlog_path = log_path(k6d);
  o.out_dir = test_support::temp_path("no_map");
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app(o, out, err), 2) << out.str();
  EXPECT_NE(err.str().find("needs the landmark map: give --landmarks FILE"), std::string::npos) << err.str();
  EXPECT_FALSE(std::filesystem::exists(o.out_dir));
}

TEST(BearingReplayApp, LandmarkMissingFromTheMap_NamedOnceAndSkipped_StrictStops) {
  SKIP_WITHOUT(k6d);
  // GIVEN: the map without the first landmark frame 0 sees.
  const std::string id = std::to_string(load(k6d).frames[0].scans[0].readings[0].landmark_id);
  std::ifstream in(landmarks_path(k6d));
  std::ostringstream kept;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream cols(line);
    std::string c, last;
    while (cols >> c) last = c;
    if (last != id) kept << line << "\n";
  }
  const std::string map = test_support::temp_path("map_without_one.txt");
  std::ofstream(map) << kept.str();
  apps::ReplayAppOptions o = app_options(k6d);
  o.landmarks_path = map;
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app(o, out, err), 0) << err.str();
  const std::string msg = "landmark ID " + id + " (first at frame 0) is not in the landmark map";
  const std::size_t at = err.str().find(msg);
  EXPECT_NE(at, std::string::npos) << err.str();
  EXPECT_EQ(err.str().find(msg, at + 1), std::string::npos) << "named more than once";
  // WHEN --strict: exit 2 naming the ID and the frame.
  o.strict = true;
  std::ostringstream out2, err2;
  EXPECT_EQ(apps::run_replay_app(o, out2, err2), 2);
  EXPECT_NE(err2.str().find("landmark ID " + id + " (frame 0) is not in the landmark map (--strict)"),
            std::string::npos)
      << err2.str();
}

TEST(BearingReplayApp, StockKfSlamConfig_GivesMapNoiseAndTruth_OutputsCarryPoseAndRmse) {
  SKIP_WITHOUT(kNoncentered);
  const std::string ini = "/usr/share/mrpt/config_files/kf-slam/EKF-SLAM_6D_noncentered_test.ini";
  LOSMIMO_REQUIRE_FILE(ini, "mrpt-common");
  apps::ReplayAppOptions o;
  o.rawlog_path = log_path(kNoncentered);
  o.mrpt_config = ini;  // its ../../datasets paths resolve against its folder
  o.out_dir = test_support::temp_path("kf_slam_ini");
  std::ostringstream out, err;
  ASSERT_EQ(apps::run_replay_app(o, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("not used from " + ini + ": [MappingApplication] logOutput_dir"), std::string::npos);
  std::ifstream summary(o.out_dir + "/summary.csv");
  std::map<std::string, std::string> rows;
  std::string line;
  while (std::getline(summary, line)) {
    const auto comma = line.find(',');
    rows[line.substr(0, comma)] = line.substr(comma + 2, line.size() - comma - 3);
  }
  ASSERT_TRUE(rows.count("rmse_m"));
  EXPECT_LT(std::stod(rows["rmse_m"]), kNoncentered.max_rmse_m);
  EXPECT_EQ(rows["ground_truth_frames"], "600");
  std::ifstream track(o.out_dir + "/track.csv");
  std::getline(track, line);
  EXPECT_EQ(line.rfind("step,timestamp_s,x_m,y_m,z_m,yaw_rad,pitch_rad,roll_rad,", 0), 0u) << line;
}

TEST(BearingReplayApp, BadLandmarkFileAndRangeOnlyOptions_ExitTwoNamingTheProblem) {
  SKIP_WITHOUT(k2d);
  const std::string map = test_support::temp_path("bad_map.txt");
  std::ofstream(map) << "% landmarks\n1.0 2.0 0.0 5 0 0 1\n3.0 x 0.0 5 0 0 2\n";
  apps::ReplayAppOptions o = app_options(k2d);
  o.landmarks_path = map;
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app(o, out, err), 2);
  EXPECT_NE(err.str().find(map + ":3"), std::string::npos) << err.str();
  apps::ReplayAppOptions o2 = app_options(k2d);
  o2.refine_window_given = true;
  std::ostringstream out2, err2;
  EXPECT_EQ(apps::run_replay_app(o2, out2, err2), 2);
  EXPECT_NE(err2.str().find("--refine-window"), std::string::npos) << err2.str();
}

}  // namespace
}  // namespace losmimo::mrpt_logs
