#pragma once
// Interruption tests: start a real app binary that stops at a named pause point
// (common/test_hook.h), wait until it is there, then send it a real signal.
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "losmimo/placement/common/test_hook.h"
#include "support/child_process.h"

namespace losmimo::test_support {

constexpr auto kPauseDeadline = std::chrono::seconds(120);

struct PausedProcess {
  pid_t pid = -1;
  bool paused = false;  // reached the point (false: it ended, or the deadline passed)
};

// Runs argv with LOSMIMO_TEST_PAUSE=point ("name" or "name#n"); returns once the process waits
// at the point, or has ended without reaching it. A build without pause points
// (LOSMIMO_TEST_HOOKS OFF) fails the calling test instead of starting the binary.
inline PausedProcess spawn_until_paused(const std::vector<std::string>& argv, const std::string& log_path,
                                        const std::string& point) {
  if (!common::test_hooks_compiled_in()) {
    ADD_FAILURE() << "pause point " << point
                  << " needs the test hooks: configure with -DLOSMIMO_TEST_HOOKS=ON (the default with the tests)";
    return {};
  }
  const std::string mark = log_path + ".paused";
  std::filesystem::remove(mark);
  ::setenv("LOSMIMO_TEST_PAUSE", point.c_str(), 1);
  ::setenv("LOSMIMO_TEST_PAUSE_MARK", mark.c_str(), 1);
  PausedProcess p;
  p.pid = spawn(argv, log_path);
  ::unsetenv("LOSMIMO_TEST_PAUSE");
  ::unsetenv("LOSMIMO_TEST_PAUSE_MARK");
  const auto deadline = std::chrono::steady_clock::now() + kPauseDeadline;
  while (std::chrono::steady_clock::now() < deadline) {
    if (std::filesystem::exists(mark)) {
      p.paused = true;
      return p;
    }
    int status = 0;
    if (::waitpid(p.pid, &status, WNOHANG) == p.pid) {
      p.pid = -1;  // ended without pausing
      return p;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return p;
}

// Sends `signal` to a paused process and returns its wait status as wait_for does (128 + signal).
inline int interrupt(const PausedProcess& p, int signal) {
  if (p.pid <= 0) return -1;
  ::kill(p.pid, signal);
  return wait_for(p.pid);
}

}  // namespace losmimo::test_support
