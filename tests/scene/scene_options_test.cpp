// --scene refused with exit 2 and nothing written: where there is nothing to draw or nowhere to
// put it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "losmimo/apps/lib/experiment_app.h"
#include "losmimo/apps/lib/experiment_scene.h"
#include "losmimo/apps/lib/record_app.h"
#include "losmimo/apps/lib/replay_app.h"
#include "temp_dir.h"

namespace losmimo {
namespace {
namespace fs = std::filesystem;

constexpr int kExitBadInput = 2;

fs::path temp_dir(const std::string& name) { return test_support::scene_temp_dir(name); }

bool empty_folder(const fs::path& d) { return fs::is_directory(d) && fs::is_empty(d); }

apps::ExperimentOptions scene_experiment(const fs::path& out) {
  apps::ExperimentOptions o;
  o.out_dir = out.string();
  o.threads = 1;
  o.overrides = {"experiment.trials=1", "experiment.plots=false", "scenario.num_uavs=4", "scenario.bs_rows=2",
                 "scenario.bs_cols=2"};
  o.scene = true;
  o.scene_writer = apps::write_experiment_scene;
  return o;
}

TEST(SceneOption, ExperimentWithoutPathRuns_ExitsTwoBeforeAnyFile) {
  const fs::path dir = temp_dir("no_paths");
  apps::ExperimentOptions o = scene_experiment(dir / "out");
  o.overrides.push_back("experiment.paths=false");
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_experiment_app(o, {}, out, err), kExitBadInput);
  EXPECT_NE(err.str().find("--scene: this run records no path"), std::string::npos) << err.str();
  EXPECT_TRUE(empty_folder(dir));
  // Without GD and BF there is no path run either.
  o = scene_experiment(dir / "out");
  o.overrides.push_back("experiment.algorithms=random, ura");
  EXPECT_EQ(apps::run_experiment_app(o, {}, out, err), kExitBadInput);
  EXPECT_TRUE(empty_folder(dir));
}

TEST(SceneOption, ExperimentShardOrNoWriter_ExitsTwoBeforeAnyFile) {
  const fs::path dir = temp_dir("shard");
  apps::ExperimentOptions o = scene_experiment(dir / "out");
  o.shard = "0/2";
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_experiment_app(o, {}, out, err), kExitBadInput);
  EXPECT_NE(err.str().find("--scene: not with --shard"), std::string::npos) << err.str();
  o = scene_experiment(dir / "out");
  o.scene_writer = nullptr;
  EXPECT_EQ(apps::run_experiment_app(o, {}, out, err), kExitBadInput);
  EXPECT_TRUE(empty_folder(dir));
}

TEST(SceneOption, RecordWhereTheSceneCannotGo_ExitsTwoAndWritesNothing) {
  const fs::path dir = temp_dir("record");
  fs::create_directories(dir / "m.3Dscene");  // a folder in the scene's way
  apps::RecordAppOptions o;
  o.overrides = {"scenario.num_uavs=2", "scenario.bs_rows=2", "scenario.bs_cols=1", "placement.max_iterations=3"};
  o.out_path = (dir / "m.rawlog").string();
  o.scene = true;
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_record_app(o, out, err), kExitBadInput);
  EXPECT_NE(err.str().find("m.3Dscene"), std::string::npos) << err.str();
  // Only the folder that was there: no log, no beacon map, no staged file.
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"m.3Dscene"});
}

TEST(SceneOption, ReplayWithoutOut_ExitsTwoNamingTheOption) {
  const fs::path dir = temp_dir("replay");
  apps::ReplayAppOptions r;
  r.rawlog_path = std::string(LOSMIMO_SOURCE_DIR) + "/datasets/missions/nominal/mission.rawlog";
  r.scene = true;
  std::ostringstream out, err;
  EXPECT_EQ(apps::run_replay_app(r, out, err), kExitBadInput);
  EXPECT_NE(err.str().find("--scene"), std::string::npos) << err.str();
  // The range-only replay the same way.
  r.beacons_path = (dir / "beacons.txt").string();
  std::ofstream(r.beacons_path) << "1 0 0 0\n";
  std::ostringstream err2;
  EXPECT_EQ(apps::run_replay_app(r, out, err2), kExitBadInput);
  EXPECT_NE(err2.str().find("--scene"), std::string::npos) << err2.str();
  EXPECT_FALSE(fs::exists(dir / "scene.3Dscene"));
}

}  // namespace
}  // namespace losmimo
