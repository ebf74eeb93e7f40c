// Bounded inputs: every file each app reads, given as /dev/zero or as a 4 GiB file, is refused
// with a clear message (exit 2) within seconds, by the real binaries running under a 1 GiB
// address-space limit: memory stays below 1 GB on any of them. (Skipped under AddressSanitizer,
// whose shadow memory does not fit an address-space limit.)
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "support/child_process.h"
#include "support/dependencies.h"
#include "support/files.h"

namespace fs = std::filesystem;
using losmimo::test_support::read_file;

namespace {

constexpr rlim_t kAddressSpace = rlim_t{1} << 30;
constexpr auto kDeadline = std::chrono::seconds(60);

// Runs argv under the address-space limit; its exit code, 128 + signal, or -2 past the deadline.
int run_limited(const std::vector<std::string>& argv, const std::string& log_path) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlimit limit{kAddressSpace, kAddressSpace};
    ::setrlimit(RLIMIT_AS, &limit);
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() - start > kDeadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return -2;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

class InputLimits : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
#if defined(__SANITIZE_ADDRESS__)
    LOSMIMO_SKIP_MACHINE_DEPENDENT("an AddressSanitizer build: an address-space limit does not fit its shadow memory");
#endif
    root_ = fs::path(::testing::TempDir()) / ("losmimo_limits_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    huge_ = root_ / "huge";
    if (GetParam() == "huge") {
      std::ofstream(huge_).close();
      fs::resize_file(huge_, std::uintmax_t{4} << 30);  // sparse: no disk used
    } else {
      fs::create_symlink("/dev/zero", huge_);
    }
  }
  void TearDown() override { fs::remove_all(root_); }

  // Expects exit 2 with `fragment` in the message.
  void expect_refused(const std::vector<std::string>& argv, const std::string& fragment) {
    const std::string log = (root_ / "app.log").string();
    EXPECT_EQ(run_limited(argv, log), 2) << argv[0] << " " << argv[1] << ": " << read_file(log);
    EXPECT_NE(read_file(log).find(fragment), std::string::npos) << read_file(log);
  }
  fs::path root_, huge_;
};

const std::string kPositions = std::string(LOSMIMO_SOURCE_DIR) + "/datasets/examples/ura_optimal_16.csv";

TEST_P(InputLimits, EvalPositionsAndConfig) {
  expect_refused({LOSMIMO_EVAL_APP, "--positions", huge_.string()}, "positions file larger than 16 MiB");
  expect_refused({LOSMIMO_EVAL_APP, "--positions", kPositions, "--config", huge_.string()},
                 "config file larger than 1 MiB");
}

TEST_P(InputLimits, ExperimentConfigCheckpointAndShards) {
  expect_refused({LOSMIMO_EXPERIMENT_APP, "--config", huge_.string(), "--out", (root_ / "r").string()},
                 "config file larger than 1 MiB");
  // A checkpoint whose records.partial, or config.ini, is the huge input.
  const std::vector<std::string> tiny = {"--threads", "1",
                                         "--trials",  "1",
                                         "--set",     "experiment.sweeps=sigma_loc_m",
                                         "--set",     "experiment.sigma_loc_values_m=0",
                                         "--set",     "experiment.plots=false",
                                         "--set",     "placement.max_iterations=5"};
  std::vector<std::string> shard = {LOSMIMO_EXPERIMENT_APP, "--out", (root_ / "s").string(), "--shard", "0/1"};
  shard.insert(shard.end(), tiny.begin(), tiny.end());
  ASSERT_EQ(losmimo::test_support::run_process(shard, (root_ / "s.log").string()), 0) << read_file(root_ / "s.log");
  fs::create_directories(root_ / "c.partial");
  fs::copy_file(root_ / "s" / "config.ini", root_ / "c.partial" / "config.ini");
  fs::create_symlink(huge_, root_ / "c.partial" / "records.partial");
  std::vector<std::string> resume = {LOSMIMO_EXPERIMENT_APP, "--resume", (root_ / "c").string()};
  resume.insert(resume.end(), tiny.begin(), tiny.end());
  expect_refused(resume, "line longer than 1 MiB");
  fs::remove(root_ / "c.partial" / "config.ini");
  fs::create_symlink(huge_, root_ / "c.partial" / "config.ini");
  expect_refused(resume, "config file larger than 1 MiB");
  // A shard folder whose records.csv, or config.ini, is the huge input.
  for (const char* file : {"records.csv", "config.ini"}) {
    fs::remove(root_ / "s" / file);
    fs::create_symlink(huge_, root_ / "s" / file);
    expect_refused({LOSMIMO_EXPERIMENT_APP, "merge", (root_ / "s").string(), "--out", (root_ / "m").string()}, file);
  }
}

TEST_P(InputLimits, RecordConfigAndReplayLog) {
  expect_refused({LOSMIMO_RECORD_APP, "--config", huge_.string(), "--out", (root_ / "x.rawlog").string()},
                 "config file larger than 1 MiB");
  expect_refused({LOSMIMO_REPLAY_APP, huge_.string()}, "not a readable rawlog: stopped at object 0");
}

INSTANTIATE_TEST_SUITE_P(DevZeroAndHugeFile, InputLimits, ::testing::Values("dev_zero", "huge"));

}  // namespace
