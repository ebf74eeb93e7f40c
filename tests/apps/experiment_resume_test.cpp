// --resume: a run killed with SIGKILL mid-sweep, resumed, gives byte-identical
// results to an uninterrupted run; a resume with another config stops with exit code 2.
// Runs the real losmimo-experiment binary.
#include <gtest/gtest.h>

#include "support/child_process.h"
#include "support/files.h"

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

// Runs the real losmimo-experiment binary (LOSMIMO_EXPERIMENT_APP) as a child process.
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>



namespace fs = std::filesystem;
namespace lt = losmimo::test_support;

namespace {
constexpr int kPointsBeforeKill = 2;  // of 8
constexpr auto kPollInterval = std::chrono::milliseconds(2);
constexpr auto kKillDeadline = std::chrono::seconds(300);

using losmimo::test_support::read_file;

int count_done_points(const fs::path& records) {
  std::istringstream in(read_file(records));
  std::string line;
  int done = 0;
  while (std::getline(in, line)) done += line.rfind("d,", 0) == 0;
  return done;
}

// 8 points (5 + 3), 3 trials each, every algorithm; one thread so the points finish one by one.
std::vector<std::string> app_args(const fs::path& out, const std::string& seed = "2018") {
  return {LOSMIMO_EXPERIMENT_APP,
          "--out", out.string(),
          "--threads", "1",
          "--trials", "3",
          "--set", "experiment.sweeps=sigma_loc_m, sigma_act_m",
          "--set", "experiment.sigma_loc_values_m=0, 0.04, 0.08, 0.12, 0.16",
          "--set", "experiment.sigma_act_values_m=0, 0.06, 0.12",
          "--set", "experiment.plots=false",
          "--set", "experiment.seed=" + seed,
          "--set", "placement.max_iterations=200"};
}

std::vector<std::string> resume_args(const fs::path& dir, const std::string& seed = "2018") {
  std::vector<std::string> a = app_args(dir, seed);
  a[1] = "--resume";  // --resume DIR instead of --out DIR
  a[4] = "2";         // another thread count is fine
  return a;
}
}  // namespace

TEST(ExperimentResume, KilledMidSweep_ResumesToByteIdenticalResults) {
  const fs::path root = fs::path(::testing::TempDir()) / ("losmimo_resume_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  const fs::path whole = root / "whole";
  const fs::path killed = root / "killed";

  // GIVEN: an uninterrupted run, and the same run killed after kPointsBeforeKill points.
  ASSERT_EQ(lt::run_process(app_args(whole), (root / "whole.log").string()), 0) << read_file(root / "whole.log");
  const pid_t pid = lt::spawn(app_args(killed), (root / "killed.log").string());
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + kKillDeadline;
  while (count_done_points(killed / "records.partial") < kPointsBeforeKill &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(kPollInterval);
  }
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  ASSERT_EQ(lt::wait_for(pid), 128 + SIGKILL) << "the run ended before it could be killed";
  ASSERT_FALSE(fs::exists(killed / "trials.csv")) << "killed too late: the sweep had finished";
  ASSERT_TRUE(fs::exists(killed / "trials.csv.partial"));
  const int done_at_kill = count_done_points(killed / "records.partial");
  EXPECT_GE(done_at_kill, kPointsBeforeKill);
  EXPECT_LT(done_at_kill, 8);

  // WHEN: resumed with another config: refused, nothing touched.
  const std::string partial_before = read_file(killed / "records.partial");
  EXPECT_EQ(lt::run_process(resume_args(killed, "7"), (root / "mismatch.log").string()), 2);
  EXPECT_NE(read_file(root / "mismatch.log").find("config.ini"), std::string::npos) << read_file(root / "mismatch.log");
  EXPECT_EQ(read_file(killed / "records.partial"), partial_before);

  // WHEN: resumed with the same config (and another thread count).
  ASSERT_EQ(lt::run_process(resume_args(killed), (root / "resume.log").string()), 0) << read_file(root / "resume.log");

  // THEN: every result file is byte-identical to the uninterrupted run's, no partial is left.
  for (const char* f : {"trials.csv", "summary.csv", "positions.csv", "traces.csv"}) {
    ASSERT_GT(read_file(whole / f).size(), 100u) << f;
    EXPECT_EQ(read_file(killed / f), read_file(whole / f)) << f;
  }
  for (const char* f : {"trials.csv.partial", "positions.csv.partial", "records.partial"}) {
    EXPECT_FALSE(fs::exists(killed / f)) << f;
  }
  EXPECT_NE(read_file(root / "resume.log").find("already finished"), std::string::npos);
  fs::remove_all(root);
}

TEST(ExperimentResume, NothingToResume_Exits2) {
  const fs::path root = fs::path(::testing::TempDir()) / ("losmimo_resume_none_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  // No config.ini at all.
  EXPECT_EQ(lt::run_process(resume_args(root / "empty"), (root / "a.log").string()), 2);
  // A finished run: nothing to resume.
  const fs::path done = root / "done";
  std::vector<std::string> quick = app_args(done);
  quick.insert(quick.end(), {"--set", "experiment.sigma_loc_values_m=0", "--set", "experiment.sigma_act_values_m=0"});
  ASSERT_EQ(lt::run_process(quick, (root / "b.log").string()), 0) << read_file(root / "b.log");
  std::vector<std::string> again = quick;
  again[1] = "--resume";
  EXPECT_EQ(lt::run_process(again, (root / "c.log").string()), 2);
  EXPECT_NE(read_file(root / "c.log").find("nothing to resume"), std::string::npos) << read_file(root / "c.log");
  fs::remove_all(root);
}
