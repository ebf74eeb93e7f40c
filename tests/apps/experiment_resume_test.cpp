// --resume: a run killed with SIGKILL mid-sweep (at a pause point, common/test_hook.h), resumed,
// gives byte-identical results to an uninterrupted run; a resume with another config stops with
// exit code 2. Runs the real losmimo-experiment binary.
#include <gtest/gtest.h>

#include "apps/pause_point.h"
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

namespace fs = std::filesystem;
namespace lt = losmimo::test_support;

namespace {
constexpr int kPointsBeforeKill = 2;  // of 8

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
          "--out",
          out.string(),
          "--threads",
          "1",
          "--trials",
          "3",
          "--set",
          "experiment.sweeps=sigma_loc_m, sigma_act_m",
          "--set",
          "experiment.sigma_loc_values_m=0, 0.04, 0.08, 0.12, 0.16",
          "--set",
          "experiment.sigma_act_values_m=0, 0.06, 0.12",
          "--set",
          "experiment.plots=false",
          "--set",
          "experiment.seed=" + seed,
          "--set",
          "placement.max_iterations=200"};
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
  const fs::path staging = root / "killed.partial";

  // GIVEN: an uninterrupted run, and the same run killed once kPointsBeforeKill points are done.
  ASSERT_EQ(lt::run_process(app_args(whole), (root / "whole.log").string()), 0) << read_file(root / "whole.log");
  const lt::PausedProcess p = lt::spawn_until_paused(app_args(killed), (root / "killed.log").string(),
                                                     "experiment.point_done#" + std::to_string(kPointsBeforeKill));
  ASSERT_TRUE(p.paused) << read_file(root / "killed.log");
  ASSERT_EQ(lt::interrupt(p, SIGKILL), 128 + SIGKILL);
  // THEN: nothing under the output folder's name; the checkpoint in its staging folder.
  ASSERT_FALSE(fs::exists(killed));
  ASSERT_TRUE(fs::exists(staging / "trials.csv.partial"));
  EXPECT_EQ(count_done_points(staging / "records.partial"), kPointsBeforeKill);

  // WHEN: resumed with another config: refused, nothing touched.
  const std::string partial_before = read_file(staging / "records.partial");
  EXPECT_EQ(lt::run_process(resume_args(killed, "7"), (root / "mismatch.log").string()), 2);
  EXPECT_NE(read_file(root / "mismatch.log").find("config.ini"), std::string::npos) << read_file(root / "mismatch.log");
  EXPECT_EQ(read_file(staging / "records.partial"), partial_before);
  // AND: a fresh run into the same folder is refused too (it would discard the checkpoint).
  EXPECT_EQ(lt::run_process(app_args(killed), (root / "fresh.log").string()), 2);
  EXPECT_NE(read_file(root / "fresh.log").find("interrupted run"), std::string::npos) << read_file(root / "fresh.log");

  // WHEN: resumed with the same config (and another thread count).
  ASSERT_EQ(lt::run_process(resume_args(killed), (root / "resume.log").string()), 0) << read_file(root / "resume.log");

  // THEN: every result file is byte-identical to the uninterrupted run's, no partial is left.
  for (const char* f : {"trials.csv", "summary.csv", "positions.csv", "traces.csv"}) {
    ASSERT_GT(read_file(whole / f).size(), 100u) << f;
    EXPECT_EQ(read_file(killed / f), read_file(whole / f)) << f;
  }
  EXPECT_FALSE(fs::exists(staging));
  for (const char* f : {"trials.csv.partial", "positions.csv.partial", "records.partial"}) {
    EXPECT_FALSE(fs::exists(killed / f)) << f;
  }
  EXPECT_NE(read_file(root / "resume.log").find("2 of 8 points already finished"), std::string::npos)
      << read_file(root / "resume.log");
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

TEST(ExperimentResume, CtrlC_Exits130_SayingWhatWasKeptAndTheCommandThatContinuesIt) {
  const fs::path root = fs::path(::testing::TempDir()) / ("losmimo_resume_int_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  const fs::path whole = root / "whole";
  const fs::path stopped = root / "stopped";
  // GIVEN: a run interrupted by SIGINT (Ctrl-C) once two points are done.
  ASSERT_EQ(lt::run_process(app_args(whole), (root / "whole.log").string()), 0) << read_file(root / "whole.log");
  const lt::PausedProcess p = lt::spawn_until_paused(app_args(stopped), (root / "stopped.log").string(),
                                                     "experiment.point_done#" + std::to_string(kPointsBeforeKill));
  ASSERT_TRUE(p.paused) << read_file(root / "stopped.log");
  // THEN: exit 130, and a message naming the checkpoint and the exact command to continue.
  ASSERT_EQ(lt::interrupt(p, SIGINT), 128 + SIGINT);
  const std::string log = read_file(root / "stopped.log");
  EXPECT_NE(log.find("interrupted; the trials finished so far are kept in " + stopped.string() + ".partial"),
            std::string::npos)
      << log;
  const std::string marker = "Continue the run with:\n  ";
  const std::size_t at = log.find(marker);
  ASSERT_NE(at, std::string::npos) << log;
  const std::string command = log.substr(at + marker.size(), log.find('\n', at + marker.size()) - at - marker.size());
  EXPECT_NE(command.find("--resume " + stopped.string()), std::string::npos) << command;
  EXPECT_EQ(command.find("--out"), std::string::npos) << command;
  // AND: re-running the same --out says --resume, and that command, run by a shell, finishes the
  // run with the uninterrupted run's results.
  EXPECT_EQ(lt::run_process(app_args(stopped), (root / "again.log").string()), 2);
  EXPECT_NE(read_file(root / "again.log").find("continue it with --resume " + stopped.string()), std::string::npos)
      << read_file(root / "again.log");
  ASSERT_EQ(lt::run_process({"/bin/sh", "-c", command}, (root / "resume.log").string()), 0)
      << read_file(root / "resume.log");
  for (const char* f : {"trials.csv", "summary.csv"}) EXPECT_EQ(read_file(stopped / f), read_file(whole / f)) << f;
  fs::remove_all(root);
}
