// losmimo-record and losmimo-replay interrupted by real signals at chosen moments (pause points,
// common/test_hook.h): an earlier log or replay folder stays whole, the interrupted one is never
// under the final name, and an existing output is refused unless --replace. Real binaries.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "apps/pause_point.h"
#include "rawlog/rawlog_test_util.h"
#include "support/child_process.h"

namespace losmimo::rawlog {
namespace {

namespace fs = std::filesystem;
namespace lt = losmimo::test_support;
using lt::read_file;

std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    files[e.path().filename().string()] = read_file(e.path());
  return files;
}

class OutputsInterrupt : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(lt::temp_path("outputs_interrupt"));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // The small mission; another seed (--set mission.seed) gives another log.
    lt::write_file_bytes((dir_ / "m11.ini").string(), mission_to_ini(lt::small_mission("ekf", false)));
  }
  void TearDown() override { fs::remove_all(dir_); }
  int run(const std::vector<std::string>& argv, const std::string& name) {
    return lt::run_process(argv, (dir_ / (name + ".log")).string());
  }
  std::string log(const std::string& name) { return read_file(dir_ / (name + ".log")); }
  std::vector<std::string> record(const fs::path& out, const std::string& seed, std::vector<std::string> more = {}) {
    std::vector<std::string> a = {
        LOSMIMO_RECORD_APP, "--config", (dir_ / "m11.ini").string(), "--set", "mission.seed=" + seed, "--out",
        out.string()};
    a.insert(a.end(), more.begin(), more.end());
    return a;
  }
  fs::path dir_;
};

// Re-recording into a log never truncates it first: an interruption leaves the complete log
// whole, and a partial one only under `.partial`, never under the final name.
TEST_F(OutputsInterrupt, RecordKilledMidMission_LeavesTheOldLogWholeAndThePartOnlyInDotPartial) {
  const fs::path log_path = dir_ / "mission.rawlog";
  ASSERT_EQ(run(record(log_path, "11"), "a"), 0) << log("a");
  const std::string before = read_file(log_path);
  EXPECT_EQ(run(record(log_path, "12"), "again"), 2);
  EXPECT_NE(log("again").find(log_path.string() + " holds a file"), std::string::npos) << log("again");
  const lt::PausedProcess p =
      lt::spawn_until_paused(record(log_path, "12", {"--replace"}), (dir_ / "b.log").string(), "record.epoch_mark#3");
  ASSERT_TRUE(p.paused) << log("b");
  ASSERT_EQ(lt::interrupt(p, SIGKILL), 128 + SIGKILL);
  EXPECT_EQ(read_file(log_path), before);
  // The partial log: its verified epochs replay, and say they are partial (exit 1).
  ASSERT_TRUE(fs::exists(log_path.string() + ".partial"));
  EXPECT_EQ(run({LOSMIMO_REPLAY_APP, log_path.string() + ".partial"}, "c"), 1) << log("c");
  EXPECT_NE(log("c").find("partial log, 3 complete epochs"), std::string::npos) << log("c");
}

// A replay never writes its files in place: a SIGTERM mid-write must not leave a cut
// estimates.csv of the new log beside the old epochs.csv and a summary.csv saying complete.
TEST_F(OutputsInterrupt, ReplayKilledWhileWriting_LeavesTheOldReplayWhole) {
  const fs::path a = dir_ / "a.rawlog", b = dir_ / "b.rawlog", out = dir_ / "replay";
  ASSERT_EQ(run(record(a, "11"), "ra"), 0) << log("ra");
  ASSERT_EQ(run(record(b, "12"), "rb"), 0) << log("rb");
  ASSERT_EQ(run({LOSMIMO_REPLAY_APP, a.string(), "--out", out.string()}, "pa"), 0) << log("pa");
  const auto before = snapshot(out);
  EXPECT_EQ(run({LOSMIMO_REPLAY_APP, b.string(), "--out", out.string()}, "pb"), 2);
  EXPECT_NE(log("pb").find(out.string() + " holds a finished replay"), std::string::npos) << log("pb");
  const lt::PausedProcess p =
      lt::spawn_until_paused({LOSMIMO_REPLAY_APP, b.string(), "--out", out.string(), "--replace"},
                             (dir_ / "pc.log").string(), "replay.outputs_written");
  ASSERT_TRUE(p.paused) << log("pc");
  ASSERT_EQ(lt::interrupt(p, SIGTERM), 128 + SIGTERM);
  EXPECT_EQ(snapshot(out), before);
  // AND: once complete, the new replay replaces the old one whole.
  ASSERT_EQ(run({LOSMIMO_REPLAY_APP, b.string(), "--out", out.string(), "--replace"}, "pd"), 0) << log("pd");
  EXPECT_NE(snapshot(out).at("estimates.csv"), before.at("estimates.csv"));
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
}

}  // namespace
}  // namespace losmimo::rawlog
