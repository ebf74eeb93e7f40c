// The four sources of a scene, through the apps' entry points (what the mains call): the
// experiment's path runs, losmimo-record, losmimo-replay on our own log and on MRPT's range-only
// demo. Each scene is read back through MRPT and checked against the run's own CSV outputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "csv_table.h"
#include "losmimo/apps/lib/experiment_app.h"
#include "losmimo/apps/lib/experiment_scene.h"
#include "losmimo/apps/lib/record_app.h"
#include "losmimo/apps/lib/replay_app.h"
#include "losmimo/fusion/rawlog/mission/log.h"
#include "losmimo/fusion/rawlog/io/reader.h"
#include "scene_reader.h"
#include "temp_dir.h"
#include "support/dependencies.h"

namespace losmimo {
namespace {
namespace fs = std::filesystem;
using test_support::CsvTable;
using test_support::expected_ellipsoids;
using test_support::load_scene;
using test_support::LoadedScene;
using test_support::read_csv_table;

constexpr double kFloatTol_m = 1e-3;  // MRPT keeps positions as float: ~6e-5 m at 1 km
constexpr double kRelTol = 1e-9;      // CSV values written with 17 digits, ellipsoid covariances double
const std::string kMrptData = "/usr/share/mrpt/datasets";
const std::string kUwbIni = "/usr/share/mrpt/config_files/ro-localization/UWB_localization_demo.ini";

fs::path temp_dir(const std::string& name) { return test_support::scene_temp_dir(name); }

// 2 x 2 BS, 4 UAVs, EKF without refinement: logged beliefs equal replayed ones bit for bit.
std::string small_mission_ini(const fs::path& dir) {
  fs::create_directories(dir);
  const fs::path p = dir / "mission.ini";
  std::ofstream(p) << "[scenario]\nbs_rows = 2\nbs_cols = 2\nnum_uavs = 4\n[errors]\nsigma_act_m = 0.02\n"
                      "[placement]\nmax_iterations = 12\n[closed_loop]\nfilter = ekf\nrefine = false\n"
                      "[mission]\nseed = 11\nstart_seed = 5\n";
  return p.string();
}

// The 2 x 2 array at the default 0.25 m spacing: element m = r * 2 + c at (0, +-0.125, +-0.125).
void expect_small_bs_array(const LoadedScene& s) {
  const auto bs = s.points("bs_array");
  ASSERT_EQ(bs.size(), 4u);
  for (int m = 0; m < 4; ++m) {
    EXPECT_NEAR(bs[m].x(), 0.0, kFloatTol_m);
    EXPECT_NEAR(bs[m].y(), (m % 2 - 0.5) * 0.25, kFloatTol_m) << m;
    EXPECT_NEAR(bs[m].z(), (m / 2 - 0.5) * 0.25, kFloatTol_m) << m;
  }
}

// The UAV's rows of a replay's estimates.csv against its track in the scene: beliefs, their
// covariance diagonal at the ellipsoids, and the truths (then `final_truth`, the last vertex).
void expect_track_matches_estimates(const LoadedScene& s, const CsvTable& est, int uav,
                                    const Eigen::Vector3d& final_truth) {
  const std::string name = "uav0" + std::to_string(uav);
  std::vector<std::size_t> rows;
  for (std::size_t r = 0; r < est.rows.size(); ++r) {
    if (est.text(r, "uav") == std::to_string(uav)) rows.push_back(r);
  }
  ASSERT_FALSE(rows.empty());
  const auto believed = s.points(name + "/believed_points");
  ASSERT_EQ(believed.size(), rows.size()) << name;
  const auto truth = s.points(name + "/true_points");
  ASSERT_EQ(truth.size(), rows.size() + 1) << name;  // every epoch has truth here, then the final positions
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_NEAR(believed[i].x(), est.number(rows[i], "x_est"), kFloatTol_m);
    EXPECT_NEAR(believed[i].z(), est.number(rows[i], "z_est"), kFloatTol_m);
    EXPECT_NEAR(truth[i].y(), est.number(rows[i], "y_true"), kFloatTol_m);
  }
  EXPECT_NEAR((truth.back() - final_truth).norm(), 0.0, kFloatTol_m);
  EXPECT_EQ(s.names_with(name + "/cov/").size(), expected_ellipsoids(rows.size()));
  const std::size_t last = rows.size() - 1;
  const auto e = s.get<mrpt::opengl::CEllipsoid3D>(name + "/cov/" + std::to_string(last));
  ASSERT_TRUE(e);
  const double sigma_y = est.number(rows[last], "sigma_y_m");
  EXPECT_NEAR(e->getCovMatrix()(1, 1), sigma_y * sigma_y, kRelTol * sigma_y * sigma_y);
  EXPECT_NEAR(e->getPoseX(), est.number(rows[last], "x_est"), kFloatTol_m);
}

Eigen::Matrix3Xd final_truth_of(const std::string& log_path) {
  rawlog_io::RawlogReader reader = rawlog_io::RawlogReader::open_file(log_path);
  const rawlog::MissionLog log = rawlog::load_mission_log(reader);
  return log.final_truth_m.value_or(Eigen::Matrix3Xd());
}

// losmimo-replay with --scene into out_dir, and its scene read back (not loaded, with the app's
// error reported, when the replay fails).
LoadedScene replay_scene(apps::ReplayAppOptions r, const fs::path& out_dir) {
  r.out_dir = out_dir.string();
  r.out_given = true;
  r.scene = true;
  std::ostringstream out, err;
  const int code = apps::run_replay_app(r, out, err);
  EXPECT_EQ(code, 0) << err.str();
  if (code != 0) return {};
  return load_scene((out_dir / "scene.3Dscene").string());
}

TEST(SceneSources, ExperimentPathRuns_TruePathsFromPathsCsvAndBsArray) {
  const fs::path dir = temp_dir("experiment") / "run";
  apps::ExperimentOptions o;
  o.out_dir = dir.string();
  o.threads = 1;
  o.overrides = {"experiment.trials=1",
                 "experiment.fig1_trials=1",
                 "experiment.sigma_loc_values_m=0",
                 "experiment.sigma_act_values_m=0, 0.04",
                 "experiment.plots=false",
                 "experiment.algorithms=gd, bf",
                 "scenario.num_uavs=4",
                 "scenario.bs_rows=2",
                 "scenario.bs_cols=2",
                 "placement.max_iterations=40"};
  o.scene = true;
  o.scene_writer = apps::write_experiment_scene;
  std::ostringstream out, err;
  ASSERT_EQ(apps::run_experiment_app(o, {}, out, err), 0) << err.str();
  const LoadedScene s = load_scene((dir / "paths.3Dscene").string());
  ASSERT_TRUE(s.loaded);
  expect_small_bs_array(s);
  // paths.csv: algorithm,sigma_act_m,trial,iteration,uav,x,y,z, grouped into the scene's tracks.
  const CsvTable paths = read_csv_table((dir / "paths.csv").string());
  std::map<std::string, std::vector<std::size_t>> rows_of;
  for (std::size_t r = 0; r < paths.rows.size(); ++r) {
    const std::string sigma = paths.text(r, "sigma_act_m");
    const std::string run = paths.text(r, "algorithm") + (sigma == "0" ? "_no_error" : "_sigma_act_" + sigma);
    rows_of[run + "/uav0" + paths.text(r, "uav")].push_back(r);
  }
  EXPECT_EQ(rows_of.size(), 16u);  // GD and BF, without error and under sigma_act 0.04, 4 UAVs each
  EXPECT_EQ(s.names_with("gd_sigma_act_0.04/").size(), 4u * 2);  // points and path per UAV
  EXPECT_EQ(s.names_with("bf_no_error/").size(), 4u * 2);
  for (const auto& [track, rows] : rows_of) {
    const auto truth = s.points(track + "/true_points");
    ASSERT_EQ(truth.size(), rows.size()) << track;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      EXPECT_NEAR(truth[i].x(), paths.number(rows[i], "x"), kFloatTol_m) << track;
      EXPECT_NEAR(truth[i].y(), paths.number(rows[i], "y"), kFloatTol_m) << track;
      EXPECT_NEAR(truth[i].z(), paths.number(rows[i], "z"), kFloatTol_m) << track;
    }
  }
  EXPECT_TRUE(s.names_with("gd_no_error/uav01/cov/").empty());  // exact positions: no belief

  // The same run in two shards (2 threads), merged with --scene: the same bytes.
  std::vector<std::string> shards;
  for (const char* i : {"0", "1"}) {
    apps::ExperimentOptions shard = o;
    shard.scene = false;
    shard.threads = 2;
    shard.shard = std::string(i) + "/2";
    shard.out_dir = (dir.parent_path() / ("shard" + std::string(i))).string();
    ASSERT_EQ(apps::run_experiment_app(shard, {}, out, err), 0) << err.str();
    shards.push_back(*shard.out_dir);
  }
  apps::MergeOptions m;
  m.shard_dirs = shards;
  m.out_dir = (dir.parent_path() / "merged").string();
  m.scene = true;
  m.scene_writer = apps::write_experiment_scene;
  ASSERT_EQ(apps::merge_experiment_app(m, {}, out, err), 0) << err.str();
  EXPECT_EQ(test_support::read_file(fs::path(m.out_dir) / "paths.3Dscene"),
            test_support::read_file(dir / "paths.3Dscene"));
}

TEST(SceneSources, RecordedMission_TruthAndLoggedBeliefsAsTheReplayFindsThem) {
  const fs::path dir = temp_dir("record");
  apps::RecordAppOptions o;
  o.config_path = small_mission_ini(dir);
  o.out_path = (dir / "m.rawlog").string();
  o.scene = true;
  std::ostringstream out, err;
  ASSERT_EQ(apps::run_record_app(o, out, err), 0) << err.str();
  EXPECT_FALSE(fs::exists(dir / "m.3Dscene.partial"));
  // The replay with the recorded estimator reproduces the logged beliefs: its estimates.csv is
  // what the scene must hold.
  apps::ReplayAppOptions r;
  r.rawlog_path = o.out_path;
  r.out_dir = (dir / "replay").string();
  r.out_given = true;
  ASSERT_EQ(apps::run_replay_app(r, out, err), 0) << err.str();
  const LoadedScene s = load_scene((dir / "m.3Dscene").string());
  ASSERT_TRUE(s.loaded);
  expect_small_bs_array(s);
  const auto beacons = s.points("beacons");  // the BS as the BS_RANGES beacon, at the origin
  ASSERT_EQ(beacons.size(), 1u);
  EXPECT_NEAR(beacons[0].norm(), 0.0, kFloatTol_m);
  const CsvTable est = read_csv_table((dir / "replay" / "estimates.csv").string());
  const Eigen::Matrix3Xd final_truth = final_truth_of(o.out_path);
  ASSERT_EQ(final_truth.cols(), 4);
  for (int u = 0; u < 4; ++u) expect_track_matches_estimates(s, est, u, final_truth.col(u));
}

TEST(SceneSources, ReplayOwnLog_SceneHoldsItsEstimatesCsv) {
  const fs::path dir = temp_dir("replay");
  apps::RecordAppOptions rec;
  rec.config_path = small_mission_ini(dir);
  rec.out_path = (dir / "m.rawlog").string();
  std::ostringstream out, err;
  ASSERT_EQ(apps::run_record_app(rec, out, err), 0) << err.str();
  EXPECT_FALSE(fs::exists(dir / "m.3Dscene"));  // only when asked
  apps::ReplayAppOptions r;
  r.rawlog_path = rec.out_path;
  r.estimator = "pf";  // another estimator than the recorded one: the replay's beliefs, not the log's
  const LoadedScene s = replay_scene(r, dir / "replay");
  ASSERT_TRUE(s.loaded);
  expect_small_bs_array(s);
  const CsvTable est = read_csv_table((dir / "replay" / "estimates.csv").string());
  const Eigen::Matrix3Xd final_truth = final_truth_of(rec.out_path);
  ASSERT_EQ(final_truth.cols(), 4);
  for (int u = 0; u < 4; ++u) expect_track_matches_estimates(s, est, u, final_truth.col(u));
}

TEST(SceneSources, RangeReplayOfMrptUwbDemo_BeaconsTrackAndGroundTruth) {
  LOSMIMO_REQUIRE_FILE(kUwbIni, "mrpt-common");
  const fs::path dir = temp_dir("range");
  apps::ReplayAppOptions r;
  r.rawlog_path = kMrptData + "/uwb_ro-localization_demo.rawlog";
  r.mrpt_config = kUwbIni;
  r.estimator = "ekf";
  const LoadedScene s = replay_scene(r, dir / "out");
  ASSERT_TRUE(s.loaded);
  EXPECT_FALSE(s.has("bs_array"));
  // The config's three anchors (its [MetricMap_landmarksMap_00_creationOpts] beacon_002_*).
  const auto beacons = s.points("beacons");
  ASSERT_EQ(beacons.size(), 3u);
  const Eigen::Vector3d beacon_2(6.71, -0.33, 1.04);
  EXPECT_EQ(std::count_if(beacons.begin(), beacons.end(),
                          [&](const Eigen::Vector3d& b) { return (b - beacon_2).norm() < kFloatTol_m; }),
            1);
  const auto label = s.get<mrpt::opengl::CRenderizable>("beacon/2");
  ASSERT_TRUE(label);
  EXPECT_NEAR(label->getPoseX(), beacon_2.x(), kFloatTol_m);
  EXPECT_NEAR(label->getPoseZ(), beacon_2.z(), kFloatTol_m);
  const CsvTable track = read_csv_table((dir / "out" / "track.csv").string());
  const auto believed = s.points("robot/believed_points");
  ASSERT_EQ(believed.size(), track.rows.size());
  std::vector<Eigen::Vector3d> truth_rows;
  for (std::size_t i = 0; i < track.rows.size(); ++i) {
    EXPECT_NEAR(believed[i].x(), track.number(i, "x_m"), kFloatTol_m);
    EXPECT_NEAR(believed[i].y(), track.number(i, "y_m"), kFloatTol_m);
    if (std::isfinite(track.number(i, "gt_x_m")))
      truth_rows.emplace_back(track.number(i, "gt_x_m"), track.number(i, "gt_y_m"), 0.0);
  }
  const auto truth = s.points("robot/true_points");
  ASSERT_FALSE(truth_rows.empty());
  ASSERT_EQ(truth.size(), truth_rows.size());
  for (std::size_t i = 0; i < truth.size(); ++i) EXPECT_NEAR((truth[i] - truth_rows[i]).norm(), 0.0, kFloatTol_m);
  EXPECT_EQ(s.names_with("robot/cov/").size(), expected_ellipsoids(track.rows.size()));
  const auto e = s.get<mrpt::opengl::CEllipsoid3D>("robot/cov/0");
  ASSERT_TRUE(e);
  const double var_x = track.number(0, "var_x_m2");
  EXPECT_NEAR(e->getCovMatrix()(0, 0), var_x, kRelTol * var_x);
}

// A 6-D bearing-range log localized on its landmark map: 50 landmarks as beacons (the file's first
// row checked by hand), beliefs, truth and the smoother's path equal to track.csv's columns.
TEST(SceneSources, BearingReplayOfMrptKfSlam6D_LandmarksTrackTruthAndSmoother) {
  const fs::path dir = temp_dir("bearing");
  apps::ReplayAppOptions r;
  r.rawlog_path = kMrptData + "/kf-slam_6D_demo.rawlog";
  r.landmarks_path = kMrptData + "/kf-slam_6D_demo_ground_truth.txt";
  r.ground_truth = kMrptData + "/kf-slam_6D_demo_ground_truth_robot_path.txt";
  r.refine = true;
  const LoadedScene s = replay_scene(r, dir / "out");
  ASSERT_TRUE(s.loaded);
  const auto landmarks = s.points("beacons");
  ASSERT_EQ(landmarks.size(), 50u);
  const Eigen::Vector3d landmark_1(-0.707910, 5.694330, 3.929384);
  EXPECT_EQ(std::count_if(landmarks.begin(), landmarks.end(),
                          [&](const Eigen::Vector3d& b) { return (b - landmark_1).norm() < kFloatTol_m; }),
            1);
  const CsvTable track = read_csv_table((dir / "out" / "track.csv").string());
  const auto believed = s.points("robot/believed_points");
  const auto truth = s.points("robot/true_points");
  const auto refined = s.points("robot_refined/believed_points");
  ASSERT_EQ(believed.size(), track.rows.size());
  ASSERT_EQ(refined.size(), track.rows.size());
  ASSERT_EQ(truth.size(), track.rows.size());
  for (std::size_t i = 0; i < track.rows.size(); ++i) {
    const Eigen::Vector3d b(track.number(i, "x_m"), track.number(i, "y_m"), track.number(i, "z_m"));
    const Eigen::Vector3d g(track.number(i, "gt_x_m"), track.number(i, "gt_y_m"), track.number(i, "gt_z_m"));
    const Eigen::Vector3d f(track.number(i, "refined_x_m"), track.number(i, "refined_y_m"),
                            track.number(i, "refined_z_m"));
    EXPECT_NEAR((believed[i] - b).norm(), 0.0, kFloatTol_m) << i;
    EXPECT_NEAR((truth[i] - g).norm(), 0.0, kFloatTol_m) << i;
    EXPECT_NEAR((refined[i] - f).norm(), 0.0, kFloatTol_m) << i;
  }
  EXPECT_EQ(s.names_with("robot/cov/").size(), expected_ellipsoids(track.rows.size()));
  EXPECT_TRUE(s.names_with("robot_refined/cov/").empty());  // the smoother gives no covariance
  const auto e = s.get<mrpt::opengl::CEllipsoid3D>("robot/cov/0");
  ASSERT_TRUE(e);
  const double var_z = track.number(0, "var_z_m2");
  EXPECT_NEAR(e->getCovMatrix()(2, 2), var_z, kRelTol * var_z);
}

}  // namespace
}  // namespace losmimo
