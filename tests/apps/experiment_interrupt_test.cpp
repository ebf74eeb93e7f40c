// losmimo-experiment interrupted by real signals at chosen moments (pause points,
// common/test_hook.h): an output folder holds one run or nothing mixed, a shard's checkpoint is
// resumed as that shard, and a folder that holds results is refused unless --replace.
// Runs the real binary.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "apps/pause_point.h"
#include "support/child_process.h"
#include "support/files.h"

namespace fs = std::filesystem;
namespace lt = losmimo::test_support;
using lt::read_file;

namespace {

// 8 points x 2 trials x 2 algorithms, one thread: points finish one by one, ~0.2 s a run.
std::vector<std::string> args(const std::string& option, const fs::path& dir, const std::string& seed,
                              const std::vector<std::string>& more = {}) {
  std::vector<std::string> a = {LOSMIMO_EXPERIMENT_APP,
                                option,
                                dir.string(),
                                "--threads",
                                "1",
                                "--trials",
                                "2",
                                "--set",
                                "experiment.sweeps=sigma_loc_m, sigma_act_m",
                                "--set",
                                "experiment.sigma_loc_values_m=0, 0.04, 0.08, 0.12, 0.16",
                                "--set",
                                "experiment.sigma_act_values_m=0, 0.06, 0.12",
                                "--set",
                                "experiment.algorithms=random, gd",
                                "--set",
                                "experiment.seed=" + seed,
                                "--set",
                                "placement.max_iterations=40"};
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

// Every file of a folder and its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    files[e.path().filename().string()] = read_file(e.path());
  return files;
}

class ExperimentInterrupt : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::path(::testing::TempDir()) / ("losmimo_interrupt_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  int run(const std::vector<std::string>& argv, const std::string& name) {
    return lt::run_process(argv, (root_ / (name + ".log")).string());
  }
  std::string log(const std::string& name) { return read_file(root_ / (name + ".log")); }
  fs::path root_;
};

}  // namespace

// An interrupted shard folder resumed without --shard is finished as that shard, never taken for
// a whole run (its half-done points counted as finished: fewer rows, wrong trial counts).
TEST_F(ExperimentInterrupt, ShardKilledMidRun_ResumeWithoutShardFinishesThatShard) {
  const fs::path s0 = root_ / "s0", s1 = root_ / "s1", whole = root_ / "whole";
  ASSERT_EQ(run(args("--out", whole, "1"), "whole"), 0) << log("whole");
  ASSERT_EQ(run(args("--out", s1, "1", {"--shard", "1/2"}), "s1"), 0) << log("s1");
  const lt::PausedProcess p = lt::spawn_until_paused(args("--out", s0, "1", {"--shard", "0/2"}),
                                                     (root_ / "s0.log").string(), "experiment.point_done#3");
  ASSERT_TRUE(p.paused) << log("s0");
  ASSERT_EQ(lt::interrupt(p, SIGKILL), 128 + SIGKILL);
  ASSERT_FALSE(fs::exists(s0));
  // WHEN: resumed as a whole run would be (no --shard), or as another shard.
  EXPECT_EQ(run(args("--resume", s0, "1", {"--shard", "1/2"}), "wrong"), 2);
  EXPECT_NE(log("wrong").find("is shard 0/2"), std::string::npos) << log("wrong");
  ASSERT_EQ(run(args("--resume", s0, "1"), "resume"), 0) << log("resume");
  // THEN: it finished shard 0, which merges with shard 1 into the uninterrupted run's results.
  EXPECT_NE(log("resume").find("shard 0/2"), std::string::npos) << log("resume");
  EXPECT_NE(read_file(s0 / "losmimo-run.ini").find("kind = shard"), std::string::npos);
  ASSERT_EQ(run({LOSMIMO_EXPERIMENT_APP, "merge", s0.string(), s1.string(), "--out", (root_ / "m").string()}, "merge"),
            0)
      << log("merge");
  for (const char* f : {"trials.csv", "summary.csv", "positions.csv"}) {
    EXPECT_EQ(read_file(root_ / "m" / f), read_file(whole / f)) << f;
  }
}

// Re-running a shard into its folder never replaces config.ini before the records: an
// interrupted re-run must not merge the old seed's records under the new seed's report.
TEST_F(ExperimentInterrupt, ShardRerunIntoItsFolder_IsRefusedOrKeepsTheOldShardWholeUntilDone) {
  const fs::path s0 = root_ / "s0", s1 = root_ / "s1";
  ASSERT_EQ(run(args("--out", s0, "1", {"--shard", "0/2"}), "a"), 0) << log("a");
  ASSERT_EQ(run(args("--out", s1, "1", {"--shard", "1/2"}), "b"), 0) << log("b");
  const auto before = snapshot(s0);
  // WHEN: shard 0 again with another seed: refused, naming what is there.
  EXPECT_EQ(run(args("--out", s0, "2", {"--shard", "0/2"}), "again"), 2);
  EXPECT_NE(log("again").find(s0.string() + " holds a finished shard"), std::string::npos) << log("again");
  EXPECT_NE(log("again").find("--replace"), std::string::npos) << log("again");
  // WHEN: with --replace, killed after its first point.
  const lt::PausedProcess p = lt::spawn_until_paused(args("--out", s0, "2", {"--shard", "0/2", "--replace"}),
                                                     (root_ / "c.log").string(), "experiment.point_done");
  ASSERT_TRUE(p.paused) << log("c");
  ASSERT_EQ(lt::interrupt(p, SIGTERM), 128 + SIGTERM);
  // THEN: the old shard is whole; the merge of the two seed-1 shards is consistent.
  EXPECT_EQ(snapshot(s0), before);
  ASSERT_EQ(run({LOSMIMO_EXPERIMENT_APP, "merge", s0.string(), s1.string(), "--out", (root_ / "m").string()}, "m"), 0)
      << log("m");
  // AND: once shard 1 is re-run with seed 2 too, the mixed pair is refused.
  ASSERT_EQ(run(args("--out", s1, "2", {"--shard", "1/2", "--replace"}), "d"), 0) << log("d");
  EXPECT_EQ(run({LOSMIMO_EXPERIMENT_APP, "merge", s0.string(), s1.string(), "--out", (root_ / "m2").string()}, "m2"),
            2);
  EXPECT_NE(log("m2").find("differs"), std::string::npos) << log("m2");
}

// An interrupted run leaves the old run whole (never its trials.csv, summary.csv, report.md and
// figures beside a new config.ini), and a later run with plots=false keeps no old figures.
TEST_F(ExperimentInterrupt, ReplaceKilledMidRunOrAtPublish_LeavesTheOldRunWhole_AndANewRunNoOldFiles) {
  const fs::path dir = root_ / "r";
  ASSERT_EQ(run(args("--out", dir, "1", {"--set", "experiment.plots=true"}), "a"), 0) << log("a");
  const auto before = snapshot(dir);
  ASSERT_TRUE(before.count("fig2a.gp"));
  for (const std::string point : {"experiment.point_done", "staged.before_rename"}) {
    SCOPED_TRACE(point);
    const lt::PausedProcess p = lt::spawn_until_paused(
        args("--out", dir, "2", {"--replace", "--set", "experiment.plots=false"}), (root_ / "k.log").string(), point);
    ASSERT_TRUE(p.paused) << log("k");
    ASSERT_EQ(lt::interrupt(p, SIGTERM), 128 + SIGTERM);
    EXPECT_EQ(snapshot(dir), before);
  }
  // WHEN: a complete run with plots=false replaces it.
  ASSERT_EQ(run(args("--out", dir, "2", {"--replace", "--set", "experiment.plots=false"}), "c"), 0) << log("c");
  // THEN: only the new run's files, each listed in the manifest; no figure scripts or images.
  const auto after = snapshot(dir);
  for (const auto& [name, bytes] : after) {
    EXPECT_TRUE(name.rfind("fig", 0) != 0 || name.find(".png") == std::string::npos) << name;
    if (name != "losmimo-run.ini") {
      EXPECT_NE(after.at("losmimo-run.ini").find(" = " + name + " "), std::string::npos) << name;
    }
  }
  EXPECT_NE(after.at("config.ini").find("seed = 2"), std::string::npos);
  EXPECT_FALSE(fs::exists(root_ / "r.partial"));
}
