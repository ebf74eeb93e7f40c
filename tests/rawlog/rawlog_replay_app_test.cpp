// The real losmimo-record and losmimo-replay binaries on a mission whose UAV dies mid-mission:
// record exits 3 and closes the log, replay reads it to the end within a deadline, prints the
// status and the loop's reason, writes its outputs and exits 3 (rawlog/replay.h).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "support/child_process.h"
#include "rawlog/rawlog_test_util.h"

namespace losmimo::rawlog {
namespace {

namespace fs = std::filesystem;
using test_support::read_file;
using test_support::temp_path;
using test_support::write_file_bytes;
using ::testing::HasSubstr;

constexpr auto kDeadline = std::chrono::seconds(120);  // the replay takes well under a second
constexpr auto kPollInterval = std::chrono::milliseconds(5);
constexpr int kTimedOut = -2;

// Runs argv with output to log_path; its exit code, or kTimedOut (then killed) past kDeadline.
int run_with_deadline(const std::vector<std::string>& argv, const std::string& log_path) {
  const pid_t pid = losmimo::test_support::spawn(argv, log_path);
  if (pid < 0) return -1;
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() - start > kDeadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return kTimedOut;
    }
    std::this_thread::sleep_for(kPollInterval);
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

TEST(ReplayApp, UavDeadMidMission_RecordAndReplayBinariesExit3WithTheReason) {
  // GIVEN: the small mission (4 UAVs) in which UAV 2 dies at iteration 4: found at iteration 6.
  const std::string dir = temp_path("replay_app_dead_uav");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string ini = dir + "/mission.ini", rawlog = dir + "/mission.rawlog";
  write_file_bytes(ini, mission_to_ini(test_support::small_mission("ekf", false, "faults = unresponsive:2:4\n")));
  const std::string reason = "UAV 2: no measurement and no motion for 3 iterations (since iteration 4) at iteration 6";
  ASSERT_EQ(run_with_deadline({LOSMIMO_RECORD_APP, "--config", ini, "--out", rawlog}, dir + "/record.log"), 3)
      << read_file(dir + "/record.log");
  ASSERT_THAT(read_file(dir + "/record.log"), HasSubstr("run ended by a fault: " + reason));
  // WHEN
  const int code = run_with_deadline({LOSMIMO_REPLAY_APP, rawlog, "--out", dir + "/out"}, dir + "/replay.log");
  // THEN: no crash (128 + signal), no hang (kTimedOut): exit 3, status and reason printed.
  const std::string log = read_file(dir + "/replay.log");
  EXPECT_EQ(code, 3) << log;
  EXPECT_THAT(log, HasSubstr("complete = true\n"));
  EXPECT_THAT(log, HasSubstr("epochs = 6\n"));
  EXPECT_THAT(log, HasSubstr("status = uav_unresponsive\nfault_uav = 2\nfault = " + reason + "\n"));
  EXPECT_THAT(log, HasSubstr("the recorded run was ended by a fault (uav_unresponsive): " + reason));
  EXPECT_THAT(log, HasSubstr("filter_beliefs_bitwise_equal = 21/21\n"));  // 6 x 4 - 3 silent
  EXPECT_THAT(read_file(dir + "/out/summary.csv"), HasSubstr("\nstatus,uav_unresponsive\n"));
  // 6 epochs x 4 UAVs plus the header.
  const std::string estimates = read_file(dir + "/out/estimates.csv");
  EXPECT_EQ(std::count(estimates.begin(), estimates.end(), '\n'), 1 + 6 * 4);
}

}  // namespace
}  // namespace losmimo::rawlog
